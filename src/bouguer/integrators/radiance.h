#pragma once
// The path tracer's visitor of a camera walk (integrators/walk.h): what the path sees directly and
// next-event estimation at every vertex, weighted by MIS (path.cpp says how). Also the tail of the
// bidirectional estimators' camera subpaths beyond the vertices they keep (bidirectional.h).
#include "bouguer/integrators/integrators.h"
#include "bouguer/integrators/manifold.h"
#include "bouguer/integrators/walk.h"

namespace bouguer {

// The refractions a walk has made since its last connecting vertex (a non-specular surface or a
// scattering event of the path tracer), up to K of them: the trails below are made of it. Whether a
// specular vertex refracted shows only at the next one, by the side of the surface the walk left
// along.
template <std::size_t K>
struct Refractions {
  bool open = false;
  int crossings = 0;
  bool pending = false;  // the last vertex was a crossing; wo and normal there
  Vec3 wo{}, normal{};
  double pdf_x = 0.0;    // the density of the direction the walk left the connecting vertex along
  std::array<Vec3, K> crossing{};

  void restart(bool connected) { open = connected, crossings = 0, pending = false; }
  // The walk went on from the pending vertex along d: open only if it refracted there.
  bool settle(const Vec3& d) {
    if (pending && dot(d, normal) * dot(wo, normal) >= 0.0) open = false;
    pending = false;
    return open;
  }
  bool full() const { return crossings == static_cast<int>(K); }
  // A crossing at `hit`, the walk arriving from wo_here along a direction of density pdf_dir.
  void add(const Hit& hit, const Vec3& wo_here, double pdf_dir) {
    if (crossings == 0) pdf_x = pdf_dir;
    crossing[static_cast<std::size_t>(crossings++)] = hit.point;
    pending = true, wo = wo_here, normal = hit.normal;
  }
  std::span<const Vec3> points() const { return {crossing.data(), static_cast<std::size_t>(crossings)}; }
};

// The walk's side of next-event estimation through the casters (manifold.h): its refractions at one
// caster. A lamp it then reaches after one of them, or after two from outside the caster, is a
// path the connection also draws: the two are weighted against each other by the power heuristic
// (manifold.h: caster_path_densities).
struct CasterTrail {
  Refractions<2> path;
  const ManifoldCaster* caster = nullptr;
  bool from_outside = false;
  Vec3 x{};  // the connecting vertex

  void start(bool connected, const Vec3& at) {
    *this = CasterTrail{};
    path.open = connected, x = at;
  }
  // A specular vertex at `hit`, the walk arriving from wo_here along a direction of density
  // pdf_dir.
  void specular(const RenderScene& scene, const Hit& hit, const Vec3& wo_here, double pdf_dir) {
    if (!path.settle(-wo_here)) return;
    const ManifoldCaster* at = find_caster(scene, hit.geometry);
    if (!at || (path.crossings > 0 && at != caster) || path.full()) {
      path.open = false;
      return;
    }
    if (path.crossings == 0) caster = at, from_outside = dot(wo_here, hit.normal) > 0.0;
    path.add(hit, wo_here, pdf_dir);
  }
  // A lamp reached along d: whether the connection through the caster draws this path too.
  bool shared_with_connection(const Vec3& d) {
    return path.settle(d) && (path.crossings == 1 || (path.crossings == 2 && from_outside && caster->twice));
  }
};

// The same for chains of mesh faces (manifold.h: area_light_through_chain): the walk's refractions at
// faces of meshes, up to kMaxChain. A lamp it then reaches is weighted against the connection from
// the connecting vertex, which may draw the same path (chain_path_densities runs the connection's
// own seed and solve for the lamp point and looks for the walk's path among what they find).
// Reflections and exact shapes close it.
// The vertex a trail's connection starts from: its point, on the surface x_hit (when on_surface),
// and the nested set there (a surface's as the walk arrived).
struct ConnectingVertex {
  Vec3 x{};
  bool on_surface = false;
  Hit x_hit{};
  InsideSet inside = 0;
  void set(const Vec3& at, const Hit* hit, InsideSet in) {
    x = at, on_surface = hit != nullptr, inside = in;
    if (hit) x_hit = *hit;
  }
  const Hit* hit() const { return on_surface ? &x_hit : nullptr; }
};

// Up to K refractions since a connecting vertex, for a connection from there: what ChainTrail and
// CylinderTrail share (each says which refractions it keeps).
template <std::size_t K>
struct TrailFrom {
  Refractions<K> path;
  ConnectingVertex from;

  void start(bool connected, const Vec3& at, const Hit* hit, InsideSet in) {
    path.restart(connected);
    from.set(at, hit, in);
  }
  // A lamp reached along d after refracting at least once.
  bool reached_through(const Vec3& d) { return path.settle(d) && path.crossings > 0; }
};

struct ChainTrail : TrailFrom<kMaxChain> {
  void specular(const RenderScene& scene, const Hit& hit, const Vec3& wo_here, double pdf_dir) {
    if (!path.settle(-wo_here)) return;
    if (scene.rays.analytic(hit.geometry) || path.full()) {
      path.open = false;
      return;
    }
    path.add(hit, wo_here, pdf_dir);
  }
};

// The same for an exact cylinder's side (manifold.h: area_light_through_cylinder): the walk's
// refractions at the side of one cylinder, once or in and out. A lamp it then reaches is weighted
// against the connection from the connecting vertex where the straight segment to the lamp point
// meets that side first (cylinder_path_densities). Any other surface, or the cylinder's cap, closes
// it.
struct CylinderTrail : TrailFrom<2> {
  std::uint32_t geometry = 0;

  void specular(const RenderScene& scene, const Hit& hit, const Vec3& wo_here, double pdf_dir) {
    if (!path.settle(-wo_here)) return;
    const AnalyticShape* shape = scene.rays.analytic(hit.geometry);
    if (!shape || !std::holds_alternative<CylinderSurface>(shape->surface) ||
        hit.primitive != static_cast<std::uint32_t>(AnalyticPart::side) ||
        (path.crossings > 0 && hit.geometry != geometry) || path.full()) {
      path.open = false;
      return;
    }
    geometry = hit.geometry;
    path.add(hit, wo_here, pdf_dir);
  }
};

// A direction a training walk drew at a non-specular surface, kept until the walk ends to learn
// the light it found that way (integrators/guiding.h): the throughput after the vertex and the
// radiance the path had gathered before it.
struct PendingRecord {
  Vec3f point, direction;
  float pdf = 0.0f;       // the mixture's, which drew the direction
  double carried = 0.0;   // the throughput after the vertex, summed over the wavelengths
  double gathered = 0.0;  // the radiance the walk had gathered before it, summed likewise
};
// The share of a guided vertex's directions drawn from the guide (Müller et al.'s 0.5: the BSDF's
// own half bounds the variance where the guide learned wrong).
inline constexpr double kGuideAlpha = 0.5;
// A walk keeps the first and the last kPendingRecords / 2 of them (max_depth may be 1000).
inline constexpr std::size_t kPendingRecords = 64;

// The path tracer's visitor: at each vertex of a camera walk, what it sees directly (an emitter or
// the environment, weighted against next-event estimation) and next-event estimation; at most
// max_depth surface vertices and kMaxScatterings medium vertices.
template <std::size_t N>
struct Radiance {
  static constexpr bool kReverse = false;
  const SceneView<N>& v;
  const SampledWavelengths<N>& w;
  WalkState<N>& state;  // its mis: r_u over the path, r_l since its last vertex (media/scattering.h)
  Rng& rng;
  std::uint64_t& rays;
  Vec3 previous;  // the last vertex: where next-event estimation would have started
  SampledSpectrum<N> l;
  int surfaces = 0, scatterings = 0;
  // The bidirectional estimators' deferred dispersion (walk.h: WalkState::kept): what a
  // contribution of a path that has crossed a dispersive interface is multiplied by (N at the
  // kept wavelength, 0 elsewhere). None in the path tracer, which keeps one wavelength instead.
  const SampledSpectrum<N>* dispersed_keep = nullptr;
  // What only this visitor reads of the walk (walk.h: its abilities): the exit guide carried from
  // the last guided vertex (GuidesExits), the last bound on the distance to the surfaces near the
  // walk (BoundsSurfaceDistance: next-event estimation's thinning keeps it, dense_media.h), and a
  // split walk's bin weight (SplitsWalks).
  GuideTrail trail = {};
  SurfaceDistance near = {};
  float bin_weight = 1.0f;
  // A walk of one wavelength from a split: the dense medium it split at (dense_media.h:
  // split_walk_nee_share, which holds there alone), or −1.
  int split_medium = -1;
  // Its next-event estimation: the path tracer's own adds lamps behind one smooth interface
  // (direct_light.h: NextEvent::lights_map_and_interfaces), a bidirectional tail does not.
  NextEvent next_event = NextEvent::lights_and_map_weighted;
  CasterTrail casters = {};
  ChainTrail chains = {};
  CylinderTrail cylinders = {};
  // Path guiding (render/path_guide.h): the guide drawn from (null: none), its mixture at the
  // surface vertex just handed over, and, while it trains (integrators/guiding.h), where the walk's
  // records go.
  const PathGuide* guide = nullptr;
  DirectionGuide here = {};
  std::vector<GuideRecord>* learning = nullptr;
  std::vector<PendingRecord> pending = {};
  std::size_t drawn = 0;
  // The map's lobe next-event estimation drew from at the last non-specular surface vertex
  // (direct_light.h: environment_lobe), which a direction drawn there to the map is weighted
  // against; −1 after a medium vertex or none. Only the path tracer's own walk draws from lobes
  // (map_lobes); a bidirectional tail keeps the map's own density.
  int env_lobe = -1;
  bool map_lobes = false;

  DirectionGuide direction_guide() const { return here; }
  // Guided: diffuse surfaces (a glossy lobe narrower than the guide's cells is better drawn by
  // itself, a specular one always is; scattering events are not guided: integrators/guiding.h).
  void guide_at(const Vec3& point, bool guidable) {
    here = {};
    if (guide && guidable)
      if (const DirectionTree* t = guide->at(point)) here = DirectionGuide{t, kGuideAlpha};
  }
  // (bsdf_pdf: the BSDF's density of d; the record's is the mixture's, which drew it)
  void learned(const Vec3& point, const Vec3& d, double bsdf_pdf, const SampledSpectrum<N>& beta_after) {
    if (!learning) return;
    const PendingRecord r{Vec3f{static_cast<float>(point.x), static_cast<float>(point.y), static_cast<float>(point.z)},
                          Vec3f{static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z)},
                          static_cast<float>(here.mixture_pdf(bsdf_pdf, d)), sum(beta_after), sum(l)};
    if (pending.size() < kPendingRecords)
      pending.push_back(r);
    else  // (the last half a ring)
      pending[kPendingRecords / 2 + (drawn - kPendingRecords / 2) % (kPendingRecords / 2)] = r;
    ++drawn;
  }
  // The walk has ended: what each kept direction found, per unit of the throughput it left with
  // (summed over the wavelengths before the ratio, so that a wavelength the path barely carries
  // does not make one record outweigh a thousand), over its density.
  void finish_learning() const {
    if (!learning) return;
    const double gathered = sum(l);
    for (const PendingRecord& r : pending)
      if (r.carried > 0.0 && r.pdf > 0.0f)
        learning->push_back(
            GuideRecord{r.point, r.direction, static_cast<float>(std::max(0.0, gathered - r.gathered) / r.carried / r.pdf)});
  }
  // (In double, not SampledSpectrum::average's float: a record subtracts two sums, and what a dim
  // path adds after a bright one would be lost in a float's rounding.)
  static double sum(const SampledSpectrum<N>& s) {
    double total = 0.0;
    for (std::size_t k = 0; k < N; ++k) total += s[k];
    return total;
  }

  bool through_casters() const {
    return next_event == NextEvent::lights_map_and_interfaces && !v.scene.casters.empty();
  }

  // Area and spherical lamps through chains of mesh faces: where next-event estimation goes on
  // through them (direct_light.h).
  bool through_chains() const {
    return next_event == NextEvent::lights_map_and_interfaces && v.any_lamp_through_chains();
  }

  // And through exact cylinders' sides, where the scene has any that next-event estimation
  // refracts through (direct_light.h).
  bool through_cylinders() const { return through_chains() && v.scene.glass_cylinders; }

  GuideTrail& exit_guide_trail() { return trail; }
  const SurfaceDistance& surface_distance() const { return near; }
  SurfaceDistance& shell_bound() { return near; }
  // A sphere of shell transport taken (shell_hops.h): its collisions count as scattering events;
  // the vertex it leaves the path at makes no connection, so nothing is open through glass. Where
  // it kept a collision (a scene with point, spot or distant lamps), the connections to those lamps
  // its n collisions would have made, estimated by n times the kept one's, thinned as the analog
  // walk thins its own deep in a medium (dense_media.h): made with probability q = min(1, n·q₁),
  // q₁ the one vertex's, and divided by it, so the sphere makes as many as its vertices would;
  // those through glass with the split walk's share of them as well (through_share).
  // Where the sphere takes the path past kMaxScatterings, only the collisions before the limit
  // connect, as the analog walk's would: the kept one if it is one of them.
  bool hopped(const ShellHop& hop) {
    const int before = scatterings;
    scatterings += hop.collisions;
    if (hop.kept && hop.kept_beta > 0.0f && before + hop.kept_ordinal <= kMaxScatterings) {
      const int medium = state.medium;
      const double q = std::min(1.0, hop.collisions * nee_probability_in_medium(v, medium, hop.kept_point, w, near));
      if (q >= 1.0 || rng.next_double() < q) {
        const MediumPoint at{hop.kept_point, hop.kept_direction, scattering_medium(v.scene, medium)->phase, medium,
                             state.inside};
        SampledSpectrum<N> beta = state.beta;
        beta[static_cast<std::size_t>(w.single)] = hop.kept_beta;
        add(beta * delta_lights_in_medium(v, at, w, state.mis.r_u, rng, rays,
                                          next_event == NextEvent::lights_map_and_interfaces, through_share(medium)) *
            static_cast<float>(hop.collisions / q));
      }
    }
    if (scatterings > kMaxScatterings) return false;
    casters.start(false, state.start);
    chains.start(false, state.start, nullptr, state.inside);
    cylinders.start(false, state.start, nullptr, state.inside);
    moved_to(state.start, true);
    return true;
  }
  float split_weight() const { return bin_weight; }

  void add(const SampledSpectrum<N>& c) { l += dispersed_keep && state.dispersed ? c * *dispersed_keep : c; }

  // A lamp met through refractions from the connecting vertex (left along a direction of density
  // pdf_x), weighted against the connection through the glass with the densities p.
  void add_against_connection(const Vertex<N>& x, double pdf_x, const CasterPathDensities& p) {
    const double weight = p.connection > 0.0 && pdf_x > 0.0
                              ? spectral_power_heuristic(v.scene, pdf_x * p.refraction, state.mis.r_u, p.connection,
                                                         state.mis.r_l)
                              : 1.0;
    add(x.beta * emitted(v, x.hit, x.wo, w) * static_cast<float>(weight / mean_ratio(v.scene, state.mis.r_u)));
  }

  // A light met along a direction drawn with density state.pdf_dir (0: specular, or the camera).
  void arrived_at_light(const Vertex<N>& x) {
    const RenderScene& scene = v.scene;
    const double arrived = state.pdf_dir;
    const Vec3 d = -x.wo;
    if (x.infinite) {  // an environment map is also reached by next-event estimation: weighted against it
      // Through smooth interfaces from a guided vertex: against the guide (exit_guide.h). A surface's
      // guide is next-event estimation's own sample carried on, so it is weighted as that is.
      auto against_the_guide = [&] {
        const ExitGuide& g = trail.guide;
        const double guide_pdf = exit_guide_pdf(scene, g, trail.dir);
        return g.from_surface ? spectral_power_heuristic(scene, trail.phase_pdf, state.mis.r_u, guide_pdf, state.mis.r_l)
                              : power_heuristic(trail.phase_pdf, guide_pdf);
      };
      double weight = 1.0;
      if (arrived == 0.0) {
        if (trail.guide.active()) weight = against_the_guide();
      } else if (scene.environment) {
        weight = spectral_power_heuristic(scene, arrived, state.mis.r_u, environment_pdf(scene, d, env_lobe),
                                          state.mis.r_l);
      }
      add(x.beta * escaped(v, -1, d, w) * static_cast<float>(weight / mean_ratio(scene, state.mis.r_u)));
      return;
    }
    if (casters.path.open && casters.shared_with_connection(d)) {  // (manifold.h: through_casters)
      // (A specular lobe drawn at the connecting vertex, density 0, is the walk's alone: the
      // connection evaluates only the vertex's finite part.)
      add_against_connection(x, casters.path.pdf_x,
                             caster_path_densities(scene, *casters.caster, casters.x, casters.path.crossing,
                                                   casters.path.crossings, x.hit));
      return;
    }
    if (chains.path.open && v.lamp_through_chains(x.hit.geometry) &&
        chains.reached_through(d)) {  // (manifold.h: area_light_through_chain)
      add_against_connection(x, chains.path.pdf_x,
                             chain_path_densities(scene, chains.from.x, chains.from.hit(), chains.from.inside,
                                                  chains.path.points(), x.hit, rays));
      return;
    }
    if (cylinders.path.open && v.lamp_through_chains(x.hit.geometry) &&
        cylinders.reached_through(d)) {  // (manifold.h: area_light_through_cylinder)
      add_against_connection(x, cylinders.path.pdf_x,
                             cylinder_path_densities(scene, cylinders.from.x, cylinders.from.hit(),
                                                     cylinders.from.inside, cylinders.path.points(), x.hit, rays));
      return;
    }
    const double weight =
        arrived == 0.0 ? 1.0
                       : spectral_power_heuristic(scene, arrived, state.mis.r_u, area_light_pdf(scene, x.hit, previous, d),
                                                  state.mis.r_l);
    add(x.beta * emitted(v, x.hit, x.wo, w) * static_cast<float>(weight / mean_ratio(scene, state.mis.r_u)));
  }

  // A walk of one wavelength from here on (walk.h: the split at a dense chromatic medium), adding
  // to nothing yet; join() takes what it found.
  Radiance split(WalkState<N>& s, const SampledWavelengths<N>& wk, Rng& r, float weight) const {
    Radiance child{v, wk, s, r, rays, previous, {}, surfaces, scatterings, dispersed_keep, trail, near, weight, s.medium,
                   next_event, casters, chains, cylinders, guide, here, learning};
    child.env_lobe = env_lobe;
    child.map_lobes = map_lobes;
    return child;
  }
  void join(const Radiance& child) {
    child.finish_learning();
    l += child.l;
  }

  bool vertex(const Vertex<N>& x) {
    if (x.kind == VertexKind::light) {
      arrived_at_light(x);
      return false;
    }
    if (x.kind == VertexKind::medium) return medium_vertex(x.point);  // (the walk calls it itself)
    if (++surfaces > v.max_depth) return false;
    guide_at(x.point, !x.delta && std::holds_alternative<DiffuseReflection<N>>(x.event.bsdf));
    if (!x.delta) {
      // Through the smooth interfaces in the way, where the walk could still cross one (exit_guide.h:
      // surface_exit_guide; the walk keeps the guide for the direction it draws next).
      const bool guided = surfaces < v.max_depth && exit_guide_runs(v);
      const ThroughInterfaces through{v.max_depth - surfaces, state.crossings};
      env_lobe = map_lobes ? environment_lobe(v.scene, x.event, x.wo) : -1;
      add(x.beta * direct_light(v, x.hit, x.event, x.wo, w, state.mis.r_u, rng, rays,
                                next_event, guided ? &through : nullptr, env_lobe));
      if (guided) trail.guide = surface_exit_guide(env_lobe);
      casters.start(through_casters(), x.point);
      chains.start(through_chains(), x.point, &x.hit, x.event.inside);
      cylinders.start(through_cylinders(), x.point, &x.hit, x.event.inside);
    } else {
      if (casters.path.open) casters.specular(v.scene, x.hit, x.wo, state.pdf_dir);
      if (chains.path.open) chains.specular(v.scene, x.hit, x.wo, state.pdf_dir);
      if (cylinders.path.open) cylinders.specular(v.scene, x.hit, x.wo, state.pdf_dir);
    }
    moved_to(x.point, x.delta);
    return true;
  }

  // The share of a medium vertex's connections through the interfaces that are made: a split
  // walk's in the medium it split at (dense_media.h: split_walk_nee_share), all of them elsewhere.
  double through_share(int medium) const {
    return medium >= 0 && medium == split_medium ? split_walk_nee_share(scattering_medium(v.scene, medium)->phase)
                                                 : 1.0;
  }

  // A scattering event at `point`; its throughput, medium and nested set are the walk's state's.
  bool medium_vertex(const Vec3& point) {
    const RenderScene& scene = v.scene;
    if (++scatterings > kMaxScatterings) return false;
    const int medium = state.medium;
    // (the direction it arrived along: the walk replaces the ray's after this)
    const MediumPoint at{point, state.ray.direction, scattering_medium(scene, medium)->phase, medium, state.inside};
    env_lobe = -1;  // (next-event estimation in a medium draws from the map's own density)
    casters.start(through_casters(), point);
    chains.start(through_chains(), point, nullptr, state.inside);
    cylinders.start(through_cylinders(), point, nullptr, state.inside);
    // Thinned deep in a dense medium, where it finds nothing, and through the interfaces along a
    // split walk's direction memory (dense_media.h: nee_probability_in_medium, split_walk_nee_share).
    const double q = nee_probability_in_medium(v, medium, point, w, near);
    if (q >= 1.0 || rng.next_double() < q)
      add(state.beta *
          direct_light_in_medium(v, at, w, state.mis.r_u, rng, rays, next_event == NextEvent::lights_map_and_interfaces,
                                 through_share(medium)) *
          static_cast<float>(1.0 / q));
    // Near the boundary, through it (exit_guide.h: ExitGuide). Its numbers come from a stream of its
    // own, so the walk's moves on by one however many the connection takes.
    // (None where the walk could not cross one more surface.)
    trail.guide = surfaces < v.max_depth ? exit_guide_at(v, medium, point, w, near, state.inside) : ExitGuide{};
    if (trail.guide.active()) {
      Rng side(rng.next_u32(), kExitGuideStream);
      add(state.beta *
          environment_through_interfaces(v, at, trail.guide, w, side, rays,
                                         ThroughInterfaces{v.max_depth - surfaces, state.crossings}) *
          static_cast<float>(1.0 / mean_ratio(scene, state.mis.r_u)));
    }
    moved_to(point);
    return true;
  }

  // The light-connection ratios restart at a vertex a connection leaves from, not at a specular
  // one: a lamp reached through glass is weighted against the connection from the vertex before
  // it (CasterTrail).
  void moved_to(const Vec3& point, bool delta = false) {
    if (v.scene.scatters && !delta) state.mis.r_l = state.mis.r_u;  // (all ones otherwise)
    previous = point;
  }
};
static_assert(WalkVisitor<Radiance<kFullBins>, kFullBins> && TakesMediumPoints<Radiance<kFullBins>> &&
              SplitsWalks<Radiance<kFullBins>, kFullBins> && GuidesExits<Radiance<kFullBins>> &&
              BoundsSurfaceDistance<Radiance<kFullBins>> && GuidesDirections<Radiance<kFullBins>, kFullBins> &&
              HopsShells<Radiance<kFullBins>>);

// The path tracer's estimate along one camera ray (path.cpp): guided by `guide` where it is not
// null, and while a guide trains (integrators/guiding.h) its walk's records added to `learning`.
template <std::size_t N>
SampledSpectrum<N> path_radiance(const SceneView<N>& v, const Ray& ray, SampledWavelengths<N>& w, double dispersion_u,
                                 Rng& rng, std::uint64_t& rays, const PathGuide* guide = nullptr,
                                 std::vector<GuideRecord>* learning = nullptr) {
  WalkState<N> state;
  state.ray = ray;
  state.from = state.start = ray.origin;
  state.medium = v.scene.world_medium;
  state.dispersion_u = dispersion_u;
  const Camera::Cone cone = v.camera.pixel_cone();
  state.cone_width_m = cone.width_m;
  state.cone_spread_rad = cone.spread_rad;
  Radiance<N> li{v, w, state, rng, rays, ray.origin, {}, 0, 0};
  li.next_event = v.manifold ? NextEvent::lights_map_and_interfaces : NextEvent::lights_and_map_weighted;
  li.map_lobes = true;
  li.guide = guide;
  li.learning = learning;
  random_walk(v, WalkMedia{}, TransportMode::radiance, state, w, rng, rays, li);
  li.finish_learning();
  return li.l;
}

}  // namespace bouguer
