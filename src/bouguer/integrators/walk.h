#pragma once
// One random walk for camera and light subpaths (pbrt-v4's RandomWalk, Tungsten's TraceBase): a
// subpath as a list of vertex records, each with what a connection and its MIS weight need,
// handed to a visitor (WalkVisitor, below) that decides what each vertex is for. Every estimator
// but Whitted's recursion walks with it: the path tracer (radiance.h), the light tracer
// (light.cpp), bdpt and vcm, both of whose subpaths it builds (bidirectional.h).
//
// Densities. pdf_fwd is the density with which the walk produced the vertex, pdf_rev the one with
// which a walk from the other end would have; both per unit area at the vertex (per unit solid
// angle for a light at infinity), and both include the distance density of the segment in a
// scattering medium: exp(−τ) to pass through it, times σ̄_s·ρ(x) to stop at a medium vertex. They
// serve only as MIS weights, which need not be the estimator's own densities, only the same
// function of the path for every strategy: τ uses σ̄_s, the mean σ_s over the wavelengths carried
// when the sample began (not the hero's), so the weights do not depend on which wavelength drew
// the distances, and the spectral MIS over wavelengths (media/scattering.h) stays unbiased
// beneath them. The throughput beta and the ratios r_u are the estimator's own.
#include <cmath>
#include <concepts>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "bouguer/core/error.h"
#include "bouguer/integrators/events.h"
#include "bouguer/integrators/shell_hops.h"

namespace bouguer {

enum class VertexKind : std::uint8_t { camera, light, surface, medium };

// A vertex of a subpath but its surface event (Vertex, below): all a merge reads of a photon
// (vcm.cpp keeps its light subpaths so, and builds their events again for each pixel's
// connections: rebuilt_light_vertex).
template <std::size_t N>
struct VertexCore {
  VertexKind kind = VertexKind::surface;
  Vec3 point;
  Vec3 normal;  // unit geometric normal: surfaces and area lights; zero elsewhere
  Hit hit;      // surfaces and area lights: where rays leave from
  int medium = -1;            // medium vertices: the medium they sit in
  int arrived_in = -1;        // surfaces: the medium the walk arrived through (their event's)
  InsideSet inside = 0;       // the nested objects the subpath was inside there (surfaces: as it arrived)
  double sigma_rho = 0.0;     // medium vertices: σ̄_s·ρ(x), the density of stopping here
  Vec3 wo;                    // unit, towards the previous vertex of the subpath (zero at its start)
  double tau_in = 0.0;        // σ̄_s·∫ρ over the segment from the previous vertex
  SampledSpectrum<N> beta;    // the subpath's throughput up to here, divided by its densities
  SampledSpectrum<N> r_u = SampledSpectrum<N>::constant(1.0f);  // its spectral-MIS ratios so far
  double pdf_fwd = 0.0, pdf_rev = 0.0;
  bool delta = false;  // a specular surface: never connected
  bool dispersed = false;  // its subpath has crossed a dispersive interface (here or before)
  // Light endpoints (the start of a light subpath, or where a camera subpath met a lamp or escaped).
  int light = -1;
  bool infinite = false;  // background, environment or distant light (no point)
  Vec3 light_dir;         // infinite: unit, from the scene towards where the light comes from

  bool on_surface() const { return normal != Vec3{}; }
  bool connectible() const { return !delta; }
};
template <std::size_t N>
struct Vertex : VertexCore<N> {
  SurfaceEvent<N> event{Frame(Vec3{0.0, 0.0, 1.0}), DiffuseReflection<N>{}};
};

// A vertex as a connection from it sees it (bdpt's strategies, the light paths' test of next-event
// estimation): f·|cos θ| towards wi (the phase function at a medium vertex) with x reached along
// wo (x.wo: the walk's), the density of sampling wi there (solid angle), the medium wi leaves
// into, and the vertex as a connection starts from it.
template <std::size_t N>
SampledSpectrum<N> vertex_f(const RenderScene& s, const Vertex<N>& x, const Vec3& wo, const Vec3& wi,
                            TransportMode mode) {
  if (x.kind == VertexKind::medium)
    return SampledSpectrum<N>::constant(static_cast<float>(phase_value(scattering_medium(s, x.medium)->phase, -wo, wi)));
  return x.event.eval(wo, wi, mode);
}
template <std::size_t N>
double vertex_pdf(const RenderScene& s, const Vertex<N>& x, const Vec3& wo, const Vec3& wi) {
  if (x.kind == VertexKind::medium) return phase_value(scattering_medium(s, x.medium)->phase, -wo, wi);
  return x.event.pdf(wo, wi);
}
template <std::size_t N>
int vertex_medium_towards(const Vertex<N>& x, const Vec3& wi) {
  return x.kind == VertexKind::surface ? x.event.medium_towards(wi) : x.medium;
}
template <std::size_t N>
PathVertex vertex_at(const Vertex<N>& x) {
  return PathVertex{x.point, x.kind == VertexKind::medium ? nullptr : &x.hit, x.inside};
}

// A light path's vertex splatted to the camera (splats.h) with throughput `beta`: a medium vertex
// through its phase function, a surface that is not specular through its BSDF; `which` of its
// paths to the camera.
template <std::size_t N>
void splat_vertex_to_camera(const SceneView<N>& v, const Vertex<N>& x, const SampledSpectrum<N>& beta,
                            const SampledWavelengths<N>& w, Rng& rng, FilmBuffer& film, std::uint64_t& rays,
                            CameraPaths which = CameraPaths::all) {
  if (x.kind == VertexKind::medium)
    splat_medium_to_camera(v, MediumPoint{x.point, -x.wo, scattering_medium(v.scene, x.medium)->phase, x.medium, x.inside},
                           beta, w, x.r_u, rng, film, rays, which);
  else if (x.kind == VertexKind::surface && !x.delta)
    splat_surface_to_camera(v, x.hit, x.event, x.wo, beta, w, x.r_u, rng, film, rays, which);
}

// What a walk needs besides the scene: the mean σ_s of every medium (0 for those that do not
// scatter) over the wavelengths the sample began with, which the MIS densities use.
struct WalkMedia {
  std::span<const double> sigma_mean;
  double sigma(int medium) const {
    return medium < 0 || sigma_mean.empty() ? 0.0 : sigma_mean[static_cast<std::size_t>(medium)];
  }
};

// σ̄_s·∫ρ dt over [0, t] from `start` along d in `medium` (0 where it does not scatter).
template <std::size_t N>
double scattering_depth(const SceneView<N>& v, const WalkMedia& media, int medium, const Vec3& start, const Vec3& d,
                        double t) {
  const double sigma = media.sigma(medium);
  if (!(sigma > 0.0)) return 0.0;
  return sigma * scattering_column_density(*scattering_medium(v.scene, medium), Ray{start, d}, 0.0, t);
}

// The state a walk continues from: the ray leaving the last vertex, where the current segment
// began (a vertex or a medium boundary), the medium it travels in, the throughput and ratios,
// and the solid-angle density of the ray's direction (0: specular).
// Its head (media_travel.h, PathHead: the ray, the segment's start, medium and nested set, the
// index-matched crossings, the throughput) is what the continuations and the crossings change.
template <std::size_t N>
struct WalkState : PathHead<N> {
  SpectralMis<N> mis;
  Vec3 from;  // the last vertex
  double pdf_dir = 0.0;
  double dispersion_u = 0.0;  // chooses the wavelength kept at the first dispersive interface
  // Deferred dispersion (the bidirectional estimator): the wavelengths stay as they are and the
  // surfaces from the first dispersive one on are built for `kept` (one wavelength, the same for
  // both subpaths of a sample); `dispersed` marks the vertices whose contributions count only
  // at that wavelength.
  const SampledWavelengths<N>* kept = nullptr;
  bool dispersed = false;
  // The ray cone (scene/texture.h) that chooses texture MIP levels: its width where the current
  // ray starts and its spread angle. Camera subpaths start it at the pixel's; a bounce keeps the
  // spread (as a mirror would), so after a diffuse bounce textures are read sharper than needed,
  // never blurrier. Light subpaths carry none (the finest level).
  double cone_width_m = 0.0, cone_spread_rad = 0.0;
  bool parallel = false;  // pdf_dir is per unit area across parallel rays (orthographic camera,
                          // light at infinity): the first vertex's density is pdf_dir·|cos θ|
  int events = 0;  // vertices so far (Russian roulette); a shell's collisions count too
  ShellUse shells;  // the shell-transport entries the walk has taken (shell_hops.h)
};
// What only the path tracer reads (the bound that lets walk_deep go without a ray, the exit guide,
// a split walk's bin weight) is its visitor's (radiance.h), which the walk asks for by the
// abilities below (BoundsSurfaceDistance, GuidesExits, SplitsWalks).

// Converts a solid-angle density at `from` towards `to` into one per unit area at `to` (none for
// a light at infinity), times the segment's distance density. `to`: a Vertex, or any record with
// its point, normal, kind, sigma_rho, infinite and on_surface().
template <typename V>
double to_area_density(double pdf_dir, const Vec3& from, const V& to, double tau, bool parallel = false) {
  double pdf = pdf_dir;
  if (parallel) {
    if (to.on_surface()) pdf *= std::abs(dot(to.normal, normalize(to.point - from)));
  } else if (!to.infinite) {
    const Vec3 d = to.point - from;
    const double d2 = dot(d, d);
    if (!(d2 > 0.0)) return 0.0;
    if (to.on_surface()) pdf *= std::abs(dot(to.normal, d)) / std::sqrt(d2);
    pdf /= d2;
  }
  if (tau > 0.0) pdf *= std::exp(-tau);
  if (to.kind == VertexKind::medium) pdf *= to.sigma_rho;
  return pdf;
}

// A walk of one wavelength deep in a homogeneous scattering medium (#20): when the bound `near`
// (the visitor's last distance from a query point to the nearest surface, dense_media.h: less how
// far the walk has moved from there, less a float margin) exceeds where the next collision falls
// (read from a copy of the stream), the collision comes before any surface, so it is taken without
// a ray and without tracking the segment again (take_first_collision: the stream moved on past
// the same draws): the same vertex, from the same numbers, as the ray would have given. Nothing otherwise
// (more than one wavelength carried, a varying density, a medium no object encloses, no bound
// yet, a collision beyond it). This holds where the scene's media agree: the ray takes the medium
// from the surface it will meet (medium_arrived_through), walk_deep keeps the vertex's, and the
// two differ only where two surfaces disagree about the medium between them.
template <std::size_t N>
std::optional<Vec3> walk_deep(const SceneView<N>& v, WalkState<N>& state, const SurfaceDistance& near,
                              const SampledWavelengths<N>& w, Rng& rng) {
  if (!w.secondary_terminated() || !(near.radius_m > 0.0)) return std::nullopt;
  const ScatteringMedium* sm = scattering_medium(v.scene, state.medium);
  if (!sm || !v.scene.media[static_cast<std::size_t>(state.medium)].enclosed) return std::nullopt;
  const Vec3& p = state.start;
  const double safe_m = free_radius_m(v.scene.rays, near, p);
  if (!(safe_m > 0.0)) return std::nullopt;
  const auto single = static_cast<std::size_t>(w.single);
  // (σ_s·ρ as the visitor last read it for this medium and wavelength, where it did: the same product)
  const double t = near.holds_sigma(state.medium, w.single)
                       ? first_collision_at_rate_m(near.sigma_min_per_m, rng)
                       : first_collision_m(*sm, v.tables, w, single, rng);
  if (!(t < safe_m)) return std::nullopt;
#ifndef NDEBUG
  {  // (Debug builds: the collision so taken is the tracking's, as test_scattering.cpp checks.)
    Rng r = rng;
    SampledSpectrum<N> b = state.beta;
    SpectralMis<N> m = state.mis;
    const MediumEvent e = sample_scattering(*sm, v.tables, Ray{p, state.ray.direction}, safe_m, w, r, b, m);
    if (!e.scattered || e.t != t) fail("internal error: walk_deep's collision ({} m) is not the tracking's", t);
  }
#endif
  take_first_collision(*sm, v.tables, Ray{p, state.ray.direction}, t, w, single, rng, state.beta);
  return p + state.ray.direction * t;
}

// What a visitor of random_walk (below) provides: the walk hands it each vertex and asks it
// whether to go on; the visitor holds the limits (depth, scattering events) and decides what a
// vertex is for. Required of every visitor:
//   static constexpr bool kReverse: whether it reads reverse densities;
//   vertex(x) -> bool: a new vertex, its pdf_fwd set; false ends the walk. The visitor may read
//       and edit the walk's state here (the path tracer's MIS reads the density of the direction
//       that arrived, state.pdf_dir, and restarts the light-connection ratios);
//   reverse(pdf_dir), where kReverse: once the walk has sampled on from the last vertex, the
//       solid-angle density with which that vertex samples the direction back towards the one
//       before it.
template <typename V, std::size_t N>
concept WalkVisitor = requires(V& visit, const Vertex<N>& x) {
  { V::kReverse } -> std::convertible_to<bool>;
  { visit.vertex(x) } -> std::same_as<bool>;
} && (!V::kReverse || requires(V& visit, double pdf_dir) { visit.reverse(pdf_dir); });

// The optional abilities of a visitor, each one the walk looks for:
// KeepsRecords: keeps_records() -> bool says whether it wants every vertex as a record just now
//   (the bidirectional estimators' camera subpaths until their tail, bidirectional.h); while it
//   says true the walk neither hands medium vertices by point nor splits.
template <typename V>
concept KeepsRecords = requires(const V& visit) {
  { visit.keeps_records() } -> std::same_as<bool>;
};
// ChoosesReverse: wants_reverse() -> bool says whether a visitor with kReverse still reads
//   reverse densities (a camera subpath's tail does not).
template <typename V>
concept ChoosesReverse = requires(const V& visit) {
  { visit.wants_reverse() } -> std::same_as<bool>;
};
// TakesMediumPoints: medium_vertex(point) -> bool, a medium vertex at `point`, the rest of it
//   (the throughput, the medium, the nested set, the direction it arrived along) in the walk's
//   state; called instead of vertex() for medium vertices (no record of 2 KB to fill and copy at
//   each of a dense walk's thousands of collisions); false ends the walk.
template <typename V>
concept TakesMediumPoints = requires(V& visit, const Vec3& point) {
  { visit.medium_vertex(point) } -> std::same_as<bool>;
};
// SplitsWalks: split(state, wavelengths, rng, bin_weight) -> child and join(child): at a dense
//   chromatic medium (dense_media.h: kSplitCount) a walk of one wavelength from here for each of
//   the split's wavelengths, each walked by its own child visitor (itself a WalkVisitor) from a
//   copy of the state and of the random stream, then joined back; split_weight() -> float, the
//   weight its own bin was given (1 for a walk never split; full mode: 1/(4·P(bin)) times its
//   parent's), which the roulette leaves out: a choice of spectral sample, not a path's
//   attenuation (without it, full mode's split walks, at about 24 times their path's throughput,
//   never played the roulette). The child of bin weight b is given b times the parent's.
template <typename V, std::size_t N>
concept SplitsWalks = requires(V& visit, const V& cvisit, WalkState<N>& s, SampledWavelengths<N>& w, Rng& r) {
  visit.join(visit.split(s, w, r, 1.0f));
  { cvisit.split_weight() } -> std::same_as<float>;
} && WalkVisitor<decltype(std::declval<V&>().split(std::declval<WalkState<N>&>(),
                                                    std::declval<SampledWavelengths<N>&>(), std::declval<Rng&>(), 1.0f)),
                 N>;
// BoundsSurfaceDistance: surface_distance() -> const SurfaceDistance&, the visitor's last bound
//   on the distance to every surface near the walk (dense_media.h: the path tracer's next-event
//   estimation keeps it), from which walk_deep takes collisions deep in a medium without a ray.
template <typename V>
concept BoundsSurfaceDistance = requires(const V& visit) {
  { visit.surface_distance() } -> std::same_as<const SurfaceDistance&>;
};
// GuidesExits: exit_guide_trail() -> GuideTrail&, the exit guide the visitor sets at its vertices
//   (exit_guide.h: the path tracer's next-event estimation through smooth interfaces), which the
//   walk carries on: it records the direction drawn at each medium or non-specular surface vertex
//   and its density, and clears the guide where the walk's own way no longer matches the guide's
//   connection (random_walk says where).
template <typename V>
concept GuidesExits = requires(V& visit) {
  { visit.exit_guide_trail() } -> std::same_as<GuideTrail&>;
};

// HopsShells: shell_bound() -> SurfaceDistance&, the bound hop_shell reads and refreshes (the same
//   as surface_distance()); hopped(hop) -> bool, a sphere of shell transport taken (shell_hops.h)
//   with its collisions (and the one it kept, for the lamps only connections reach), after which
//   the path's last vertex is one that makes no connection; false ends the walk. Only where the
//   view carries tables (SceneView::shells).
template <typename V>
concept HopsShells = requires(V& visit, const ShellHop& hop) {
  { visit.shell_bound() } -> std::same_as<SurfaceDistance&>;
  { visit.hopped(hop) } -> std::same_as<bool>;
};

// GuidesDirections: direction_guide() -> DirectionGuide, the path guide (render/path_guide.h) to
//   draw the next direction with at the surface vertex just handed over (a null one: the BSDF's
//   own, and no number more drawn); learned(point, direction, pdf, beta): the direction then drawn
//   there, the BSDF's density of it and the throughput after it (the guide's training,
//   integrators/guiding.h). Medium vertices are never guided (guiding.h says why).
template <typename V, std::size_t N>
concept GuidesDirections = requires(V& visit, const Vec3& p, double pdf, const SampledSpectrum<N>& beta) {
  { visit.direction_guide() } -> std::same_as<DirectionGuide>;
  visit.learned(p, p, pdf, beta);
};

// Whether a visitor wants every vertex as a record just now (KeepsRecords).
template <typename Visitor>
bool keeps_records(const Visitor& visit) {
  if constexpr (KeepsRecords<Visitor>)
    return visit.keeps_records();
  else
    return false;
}

// Whether a visitor with reverse densities still reads them (ChoosesReverse).
template <typename Visitor>
bool wants_reverse(const Visitor& visit) {
  if constexpr (!Visitor::kReverse)
    return false;
  else if constexpr (ChoosesReverse<Visitor>)
    return visit.wants_reverse();
  else
    return true;
}

// The bin weight of a walk (SplitsWalks; 1 for a visitor that never splits).
template <typename Visitor>
float split_weight(const Visitor& visit) {
  if constexpr (requires { { visit.split_weight() } -> std::same_as<float>; })
    return visit.split_weight();
  else
    return 1.0f;
}

// Walks on from `state` in the transport mode of the subpath (radiance: from the camera, which
// then also meets lamps and escapes to a light at infinity; importance: from a light), and hands
// each vertex to the visitor (Tungsten's TraceBase, pbrt-v4's RandomWalk; the visitor's contract:
// WalkVisitor and its optional abilities, above).
// At the first dispersive interface it keeps one wavelength (state.dispersion_u). Russian
// roulette and the medium tracking as the path tracer's; index-matched boundaries are crossed
// without a vertex.
template <std::size_t N, typename Visitor>
  requires WalkVisitor<Visitor, N>
void random_walk(const SceneView<N>& v, const WalkMedia& media, TransportMode mode, WalkState<N>& state,
                 SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays, Visitor& visit) {
  const RenderScene& scene = v.scene;
  double tau = 0.0;  // along the segment from the last vertex, across index-matched boundaries
  int& events = state.events;
  // The visitor's exit guide (GuidesExits) and distance bound (BoundsSurfaceDistance); for one
  // without them, a guide of the walk's own that nothing reads and no bound (radius < 0).
  GuideTrail unread;
  GuideTrail& trail = [&]() -> GuideTrail& {
    if constexpr (GuidesExits<Visitor>)
      return visit.exit_guide_trail();
    else
      return unread;
  }();
  const SurfaceDistance none;
  const SurfaceDistance& near = [&]() -> const SurfaceDistance& {
    if constexpr (BoundsSurfaceDistance<Visitor>)
      return visit.surface_distance();
    else
      return none;
  }();
  // The visitor's path guide at the vertex it was just handed (GuidesDirections), and its record of
  // the direction then drawn.
  auto guide_here = [&]() -> DirectionGuide {
    if constexpr (GuidesDirections<Visitor, N>)
      return visit.direction_guide();
    else
      return {};
  };
  auto learned = [&]([[maybe_unused]] const Vec3& point, [[maybe_unused]] double bsdf_pdf) {
    if constexpr (GuidesDirections<Visitor, N>) visit.learned(point, state.ray.direction, bsdf_pdf, state.beta);
  };
  auto make = [&](VertexKind kind, const Vec3& point) {
    Vertex<N> x;
    x.kind = kind;
    x.point = point;
    x.wo = -state.ray.direction;
    x.tau_in = tau;
    x.beta = state.beta;
    x.r_u = state.mis.r_u;
    x.dispersed = state.dispersed;
    x.inside = state.inside;
    return x;
  };
  auto record = [&](Vertex<N>& x) {
    x.pdf_fwd = to_area_density(state.pdf_dir, state.from, x, tau, state.parallel);
    return visit.vertex(x);
  };
  auto moved_on = [&](const Vec3& point) {
    state.parallel = false;
    state.from = state.start = point;
    tau = 0.0;
    ++events;
  };
  // What the roulette divides the throughput by (the mean of the path's ratios, and a split walk's
  // bin weight: SplitsWalks), and the one wavelength carried (−1: several).
  // A walk of one wavelength no longer changes its ratios (media/scattering.h: sample_scattering),
  // so their mean, 96 additions in full mode, is taken once.
  const float bin_weight = split_weight(visit);
  float single_mean_ratio = 0.0f;  // (0: not yet)
  auto roulette_divisor = [&] {
    if (!w.secondary_terminated()) return mean_ratio(scene, state.mis.r_u) * bin_weight;
    if (!(single_mean_ratio > 0.0f)) single_mean_ratio = mean_ratio(scene, state.mis.r_u);
    return single_mean_ratio * bin_weight;
  };
  auto roulette = [&] { return RouletteReading{roulette_divisor(), w.secondary_terminated() ? w.single : -1}; };
  // A vertex in the medium at x, reached along d (by the ray's segment, or by walk_deep without a
  // ray): record it, then the phase function's direction and the roulette. False ends the walk.
  auto medium_vertex = [&](const Vec3& x, const Vec3& d) -> bool {
    state.cone_width_m += state.cone_spread_rad * length(x - state.ray.origin);
    tau += scattering_depth(v, media, state.medium, state.start, d, length(x - state.start));
    if (state.beta.is_zero()) return false;
    const ScatteringMedium& sm = *scattering_medium(scene, state.medium);
    trail.clear();
    // A visitor that reads a medium vertex from the state alone (the path tracer's) is handed its
    // point: no record of 2 KB to fill and copy at each of a dense walk's thousands of collisions.
    bool by_point = false;
    if constexpr (TakesMediumPoints<Visitor>) {
      by_point = !keeps_records(visit);
      if (by_point && !visit.medium_vertex(x)) return false;
    }
    if (!by_point) {
      Vertex<N> vx = make(VertexKind::medium, x);
      vx.medium = state.medium;
      vx.sigma_rho = media.sigma(state.medium) * concentration_at(sm.density, x);
      if (!record(vx)) return false;
    }
    // (d may be the ray's own direction, which the phase function replaces: the reverse density
    // reads a copy, taken only for a visitor that reads reverse densities.)
    [[maybe_unused]] Vec3 arrived_along;
    if constexpr (Visitor::kReverse) arrived_along = d;
    // (The roulette counts this vertex as the surfaces' continuation does not: as before the walk.)
    const auto phase_pdf = continue_from_medium(scene, sm, x, events + 1, state, rng, mode, roulette());
    if (!phase_pdf) return false;
    if constexpr (Visitor::kReverse)
      if (wants_reverse(visit)) visit.reverse(phase_value(sm.phase, -state.ray.direction, -arrived_along));
    state.pdf_dir = *phase_pdf;
    trail.drew(state.ray.direction, *phase_pdf);
    moved_on(x);
    return true;
  };
  // The loop of advance_to_surface (surface_events.h) carries the walk across index-matched
  // boundaries; before each ray a collision deep in a homogeneous medium may need none (walk_deep),
  // and each segment up to a surface may end in a collision (through_medium), split into walks of
  // one wavelength, or end the walk (nothing left, a lamp).
  std::optional<Vec3> collision;  // a medium vertex before the next surface
  // The direction a collision on a ray's segment arrived along (the segment's own, a copy of the
  // ray's); walk_deep's collision arrived along the ray's direction.
  Vec3 arrived;
  bool on_segment = false;
  auto before_ray = [&] {
    // Shell transport first (shell_hops.h): spheres as long as one fits, each leaving the walk
    // mid-flight on their surface, with no vertex to connect from (its direction's density 0).
    if constexpr (HopsShells<Visitor>) {
      const ShellTable* table = v.shells ? v.shells->table(v.sample, state.medium) : nullptr;
      while (const auto hop = table ? hop_shell(v, table, state, state.shells, visit.shell_bound(), w, rng)
                                    : std::nullopt) {
        if (hop->collisions == 0) {  // a flight straight through: the last vertex is still the last
          tau += scattering_depth(v, media, state.medium, hop->centre, state.ray.direction, hop->length_m);
          continue;
        }
        events += hop->collisions;
        state.from = hop->exit;
        state.pdf_dir = 0.0;
        state.parallel = false;
        tau = 0.0;
        trail.clear();
        // The roulette, as at the vertices the sphere stands for: without it a path deep in the
        // medium took sphere after sphere at a throughput the walk would long have ended.
        const RouletteReading r = roulette();
        if (!visit.hopped(*hop) ||
            !survives_roulette(scene, events, state.medium, state.beta, rng, r.divisor,
                               roulette_scale(scene, state.medium, mode), r.single)) {
          collision.reset();
          return false;
        }
      }
    }
    collision = walk_deep(v, state, near, w, rng);
    on_segment = false;
    return !collision;
  };
  auto segment = [&](const Hit* hit, const SurfaceSeen* seen) {
    if (!hit) return true;  // (a camera subpath may end on a light at infinity: below)
    state.medium = medium_arrived_through(*seen, state.ray, *hit, state.medium);
    // A surface's guide goes through no scattering medium (exit_guide.h: surface_exit_guide).
    if (trail.guide.from_surface && scattering_medium(scene, state.medium)) trail.clear();
    const Vec3 d = state.ray.direction;
    // A visitor that can split (the path tracer's) does so at a dense chromatic medium (dense_media.h:
    // kSplitCount): each walk takes this segment again from the same state and a copy of the same
    // random stream.
    if constexpr (SplitsWalks<Visitor, N>) {
      // (Not once a bidirectional tail has crossed a dispersive interface: only the kept wavelength
      // counts there, and it is rarely among the split's.)
      if (!keeps_records(visit) && !(state.kept && state.dispersed) &&
          splits_wavelengths(v, state.medium, w, state.start, d, length(hit->point - state.start))) {
        const double u_nm = rng.next_double();
        const Rng common = rng;
        for (std::size_t i = 0; i < kSplitCount<N>; ++i) {
          WalkState<N> sub = state;
          SampledWavelengths<N> wk = w;
          Rng r = common;
          const float weight = static_cast<float>(keep_split_wavelength(v, wk, sub.beta, i, u_nm)) * bin_weight;
          auto child = visit.split(sub, wk, r, weight);
          random_walk(v, media, mode, sub, wk, r, rays, child);
          visit.join(child);
        }
        return false;
      }
    }
    collision = through_medium(v, state.medium, state.start, d, *hit, w, rng, state.beta, state.mis);
    if (collision) {
      arrived = d;
      on_segment = true;
      return false;
    }
    tau += scattering_depth(v, media, state.medium, state.start, d, length(hit->point - state.start));
    if (state.beta.is_zero()) return false;
    if (seen->surface.kind == SurfaceKind::emitter) {  // lamps absorb what reaches them
      if (mode == TransportMode::radiance) {
        Vertex<N> x = make(VertexKind::light, hit->point);
        x.normal = hit->normal;
        x.hit = *hit;
        x.light = seen->surface.first_light + static_cast<int>(hit->primitive);
        record(x);
      }
      return false;
    }
    state.cone_width_m += state.cone_spread_rad * hit->t;
    return true;
  };
  for (;;) {
    const RayStop stop = advance_to_surface(scene, state, rays, before_ray, segment);
    if (collision) {
      if (!medium_vertex(*collision, on_segment ? arrived : state.ray.direction)) return;
      continue;
    }
    if (stop.at == RayStop::At::escape) {  // a camera subpath may end on a light at infinity
      const int light = scene.environment_light >= 0 ? scene.environment_light : scene.background_light;
      if (mode == TransportMode::radiance && light >= 0 && !absorbs(scene, state.medium) &&
          !scattering_medium(scene, state.medium)) {
        Vertex<N> x = make(VertexKind::light, Vec3{});
        x.infinite = true;
        x.light = light;
        x.light_dir = state.ray.direction;
        x.pdf_fwd = state.pdf_dir * std::exp(-tau);
        visit.vertex(x);
      }
      return;
    }
    if (stop.at != RayStop::At::surface) return;  // the segment ended the walk, or too many crossings
    const Hit& hit = *stop.hit;
    const SurfaceSeen& seen = *stop.seen;
    const Vec3 d = state.ray.direction;
    // A surface's guide goes through no dispersive interface while several wavelengths ride on the
    // path (exit_guide.h: surface_exit_guide), whether the walk keeps one here or defers it (bdpt, vcm).
    if (trail.guide.from_surface && !w.secondary_terminated() && is_dispersive(scene, seen)) trail.clear();
    if (!state.kept)
      keep_one_wavelength(v, seen, w, state.beta, state.dispersion_u, rng);
    else if (!state.dispersed && is_dispersive(scene, seen))
      state.dispersed = true;
    const Vec3 wo = -d;
    Vertex<N> vx = make(VertexKind::surface, hit.point);
    vx.normal = hit.normal;
    vx.hit = hit;
    vx.arrived_in = state.medium;
    vx.event = surface_event(v, hit, seen, wo, state.medium, state.dispersed ? *state.kept : w, state.cone_width_m);
    vx.event.inside = state.inside;
    vx.delta = is_specular(vx.event.bsdf);
    if (!vx.delta) trail.clear();  // (the visitor may set a surface's: radiance.h)
    if (!record(vx)) return;
    const SurfaceEvent<N>& e = vx.event;
    const auto bsdf_pdf =
        continue_path(scene, hit, e, wo, mode, events, state, rng, roulette(), vx.delta ? DirectionGuide{} : guide_here());
    if (!bsdf_pdf) return;
    if (!vx.delta) {
      learned(hit.point, *bsdf_pdf);
      trail.drew(state.ray.direction, *bsdf_pdf);  // (read only where the visitor set a guide)
    } else if (seen.surface.kind != SurfaceKind::interface ||
               dot(d, hit.normal) * dot(state.ray.direction, hit.normal) <= 0.0) {
      trail.clear();  // a reflection, or a thin sheet: the guide's connection crosses neither
    }
    state.inside = inside_towards(scene, hit, state.inside, state.ray.direction);
    if constexpr (Visitor::kReverse)
      if (wants_reverse(visit)) visit.reverse(vx.delta ? 0.0 : e.pdf(state.ray.direction, wo));
    state.pdf_dir = vx.delta ? 0.0 : *bsdf_pdf;
    moved_on(hit.point);
  }
}

// A light subpath's vertex kept without its event (vcm.cpp) with its surface event built again as
// the walk built it (random_walk, above): from the same hit, nested set (the surface as seen),
// direction and medium arrived through, for the wavelengths the walk carried, `w` (a light
// subpath's are never changed: its dispersion is deferred), or `kept` from a dispersive
// interface on; light subpaths carry no ray cone. The same event bit for bit
// (test_bdpt.cpp: ALightVertexKeptWithoutItsEventGetsItBack).
template <std::size_t N>
Vertex<N> rebuilt_light_vertex(const SceneView<N>& v, const VertexCore<N>& y, const SampledWavelengths<N>& w,
                               const SampledWavelengths<N>& kept) {
  Vertex<N> x;
  static_cast<VertexCore<N>&>(x) = y;
  if (x.kind == VertexKind::surface) {
    x.event = surface_event(v, x.hit, surface_seen(v.scene, x.hit, x.inside), x.wo, x.arrived_in,
                            x.dispersed ? kept : w, 0.0);
    x.event.inside = x.inside;
  }
  return x;
}

// The medium a light emits into: the one in front of an emitter surface, the world's otherwise (a
// lamp inside an object: the first boundary the walk meets from inside sets it right).
inline int emission_medium(const RenderScene& scene, const Light& light) {
  if (const auto* a = std::get_if<AreaLight>(&light)) return scene.surfaces[a->geometry].medium_front;
  if (const auto* sp = std::get_if<SphereLight>(&light)) return scene.surfaces[sp->geometry].medium_front;
  return scene.world_medium;
}

// The start of a light subpath: a light drawn by power (among all, or among `lamps`), a ray from
// its own emission sampling. Its first vertex `y` (beta: the emitted radiance over the densities
// of the light and the point) and the walk's state on the ray leaving it. False when nothing leaves.
template <std::size_t N>
bool start_light_subpath(const SceneView<N>& v, const SampledWavelengths<N>& w, Rng& rng, Vertex<N>& y,
                         WalkState<N>& state, const LightDistribution* lamps = nullptr) {
  const RenderScene& scene = v.scene;
  const double u_light = rng.next_double(), u1 = rng.next_double(), u2 = rng.next_double(), u3 = rng.next_double(),
               u4 = rng.next_double();
  const auto chosen = (lamps ? *lamps : scene.emitters).sample(u_light);
  if (!chosen) return false;
  const Light& light = scene.lights[static_cast<std::size_t>(chosen->first)];
  const auto le = sample_le(light, scene.bounds, u1, u2, u3, u4);
  if (!le) return false;
  const SampledSpectrum<N> radiance = sample_radiance(v, *le, w);
  const double pmf = chosen->second;
  y = Vertex<N>{};
  y.kind = VertexKind::light;
  y.light = chosen->first;
  y.infinite = le->delta_direction || std::holds_alternative<BackgroundLight>(light) ||
               std::holds_alternative<EnvironmentLight>(light);
  y.point = le->ray.origin;
  y.normal = le->normal;
  if (const auto* a = std::get_if<AreaLight>(&light)) {
    y.hit.point = le->ray.origin;
    y.hit.normal = a->normal;
    y.hit.geometry = a->geometry;
    y.hit.primitive = a->primitive;
    y.hit.uv = le->uv;
  } else if (const auto* sp = std::get_if<SphereLight>(&light)) {
    y.hit.point = le->ray.origin;
    y.hit.normal = le->normal;
    y.hit.geometry = sp->geometry;
  }
  y.light_dir = -le->ray.direction;
  y.beta = radiance * static_cast<float>(1.0 / (pmf * le->pdf_pos));
  y.pdf_fwd = y.infinite ? pmf * (le->delta_direction ? 1.0 : le->pdf_dir) : pmf * le->pdf_pos;
  state.ray = le->ray;
  if (y.on_surface()) state.ray.origin = offset_ray_origin(y.hit, le->ray.direction);
  state.from = state.start = le->ray.origin;
  state.medium = emission_medium(scene, light);
  const double cos_light = le->normal == Vec3{} ? 1.0 : std::abs(dot(le->normal, le->ray.direction));
  state.beta = radiance * static_cast<float>(le->factor * cos_light / (pmf * le->pdf_pos * le->pdf_dir));
  state.parallel = y.infinite;
  state.pdf_dir = y.infinite ? le->pdf_pos : le->pdf_dir;
  return true;
}

// A visitor that keeps the vertices, at most `max_vertices` in all (the bidirectional estimator:
// its depth counts medium vertices too), each previous vertex's pdf_rev set as the walk goes on.
template <std::size_t N>
struct KeepVertices {
  static constexpr bool kReverse = true;
  std::vector<Vertex<N>>& path;  // the subpath is path[first..]
  std::size_t max_vertices;
  std::size_t first = 0;
  bool vertex(const Vertex<N>& x) {
    path.push_back(x);
    return path.size() - first < max_vertices;
  }
  void reverse(double pdf_dir) {
    const Vertex<N>& at = path.back();
    Vertex<N>& prev = path[path.size() - 2];
    prev.pdf_rev = to_area_density(pdf_dir, at.point, prev, at.tau_in);
  }
};
static_assert(WalkVisitor<KeepVertices<kFullBins>, kFullBins>);

}  // namespace bouguer
