#pragma once
// The events of a path, one function each, shared by every estimator that meets them (Whitted,
// the path tracer, the light tracer): travel through a medium, escape to the background, an
// emitter hit, a surface's BSDF, direct light at a surface (next-event estimation), the choice of
// one wavelength at a dispersive interface, and the connection of a light path to the camera.
// A path owns its state (wavelengths, throughput, medium); these functions only read the scene.
#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>

#include "bouguer/core/frame.h"
#include "bouguer/materials/surface_bsdf.h"
#include "bouguer/media/scattering.h"
#include "bouguer/render/camera.h"
#include "bouguer/render/film.h"
#include "bouguer/core/rng.h"
#include "bouguer/lights/environment.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/normal_map.h"

namespace bouguer {

// A path's scattering events, and the index-matched interfaces it crosses, are not bounded by
// max_depth (a dense medium needs thousands); these stop a path that would never end.
inline constexpr int kMaxScatterings = 100000;
inline constexpr int kMaxCrossings = 1024;

// What every event reads: the compiled scene, its spectra for this render's mode, the camera.
template <std::size_t N>
struct SceneView {
  const RenderScene& scene;
  const SpectralTables<N>& tables;
  const Camera& camera;
  int max_depth = 32;
  bool exit_guide = true;  // the path tracer's ExitGuide (below)
};

double power_heuristic(double pdf_a, double pdf_b);

// Transmittance through scene medium `medium` (−1: none) along ray over [0, t_m]. Callers measure
// segments from the surface point a ray left (not its offset origin), so a slab's path length is
// exact and does not depend on where on the surface the ray starts.
template <std::size_t N>
SampledSpectrum<N> travel(const SceneView<N>& v, int medium, const Ray& ray, double t_m, const SampledWavelengths<N>& w);

inline bool absorbs(const RenderScene& scene, int medium) {
  return medium >= 0 && absorbs(scene.media[static_cast<std::size_t>(medium)].medium);
}

// Radiance a ray leaving the scene in direction d brings back through `medium`: the background
// or the environment map, none through an absorber (an infinite path).
template <std::size_t N>
SampledSpectrum<N> escaped(const SceneView<N>& v, int medium, const Vec3& d, const SampledWavelengths<N>& w);

// Radiance an emitter hit sends back along wo (zero behind a one-sided emitter).
template <std::size_t N>
SampledSpectrum<N> emitted(const SceneView<N>& v, const Hit& hit, const Vec3& wo, const SampledWavelengths<N>& w);

// Solid-angle density with which next-event estimation at `from` reaches this emitter hit (for
// MIS), and the one for a direction that escapes to the environment map.
double area_light_pdf(const RenderScene& scene, const Hit& hit, const Vec3& from, const Vec3& wi);
double environment_pdf(const RenderScene& scene, const Vec3& d);

// A surface hit as a BSDF in its shading frame. Opaque surfaces are two-sided: both normals face
// wo. Interfaces keep the geometric normal's side, so z > 0 is the medium_front side.
//
// Shading normals (docs/rendering.md "Shading normals"), treated as pbrt-v3 does. The BSDF is
// evaluated and sampled in the frame of the hit's shading normal; the geometric normal `ng` alone
// says which side a direction is on, so it decides the medium a direction travels in and whether
// wo → wi is a reflection or a transmission. A pair on which the two frames disagree (a reflection
// through the geometric surface, a refraction that stays on its side, a wo behind the shading
// normal) carries nothing, and a sample that draws one ends the path: no light leaks through a
// surface without changing media. In importance mode the verbs include Veach's adjoint correction
// |wo·ns||wi·ng| / (|wo·ng||wi·ns|), which makes the light paths' BSDF the adjoint of the camera
// paths' (Veach's thesis, §5.3), so every estimator sums the same integral.
template <std::size_t N>
struct SurfaceEvent {
  Frame frame;  // z: the shading normal
  Bsdf<N> bsdf;
  int medium_front = -1, medium_behind = -1;
  InsideSet inside = 0;  // the nested objects the path was inside as it arrived (scene/nested.h)
  Vec3 ng = frame.n;     // the geometric normal, on the side of frame.n

  // The medium a direction leaving the surface travels in.
  int medium_towards(const Vec3& wi) const { return dot(wi, ng) > 0.0 ? medium_front : medium_behind; }
  bool shaded() const { return !(frame.n == ng); }

  // f(wo, wi)·|cos θi| (with the adjoint correction in importance mode), world directions.
  SampledSpectrum<N> eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    const Vec3 lo = frame.to_local(wo), li = frame.to_local(wi);
    if (!shaded()) return bouguer::eval(bsdf, lo, li, mode);
    if (!sides_agree(wo, wi, lo, li)) return {};
    return bouguer::eval(bsdf, lo, li, mode) * correction(wo, wi, lo, li, mode);
  }
  // The solid-angle density of drawing wi from wo (the shading frame's).
  double pdf(const Vec3& wo, const Vec3& wi) const { return bouguer::pdf(bsdf, frame.to_local(wo), frame.to_local(wi)); }
  // A direction drawn from wo, in world coordinates; nullopt where the two frames disagree on it.
  std::optional<BsdfSampleN<N>> sample(const Vec3& wo, double uc, double u1, double u2, TransportMode mode) const {
    const Vec3 lo = frame.to_local(wo);
    auto s = bouguer::sample(bsdf, lo, uc, u1, u2, mode);
    if (!s) return s;
    const Vec3 li = s->wi;
    s->wi = frame.to_world(li);
    if (shaded()) {
      if (!sides_agree(wo, s->wi, lo, li)) return std::nullopt;
      s->weight *= correction(wo, s->wi, lo, li, mode);
    }
    return s;
  }

 private:
  bool sides_agree(const Vec3& wo, const Vec3& wi, const Vec3& lo, const Vec3& li) const {
    return (dot(wo, ng) * dot(wi, ng) > 0.0) == (lo.z * li.z > 0.0);
  }
  float correction(const Vec3& wo, const Vec3& wi, const Vec3& lo, const Vec3& li, TransportMode mode) const {
    if (mode == TransportMode::radiance) return 1.0f;
    const double den = std::abs(dot(wo, ng)) * std::abs(li.z);
    return den > 0.0 ? static_cast<float>(std::abs(lo.z) * std::abs(dot(wi, ng)) / den) : 0.0f;
  }
};

// `medium` is the one the path arrived through (the medium around an opaque surface).
// `cone_width_m`: the width at the hit of the ray cone the path carries (scene/texture.h), which
// chooses the textures' MIP level; 0 reads their finest level.
template <std::size_t N>
SurfaceEvent<N> surface_event(const SceneView<N>& v, const Hit& hit, const Surface& surface, const Vec3& wo,
                              int medium, const SampledWavelengths<N>& w, double cone_width_m = 0.0);

// Where a connection (to a light or the camera) starts: a surface hit, whose rays leave from its
// offset origin while lengths are measured from the hit point itself, or a point inside a medium.
struct PathVertex {
  Vec3 point;
  const Hit* hit = nullptr;  // null: a point inside a medium
  InsideSet inside = 0;      // the nested objects the path was inside there (at a surface: as it arrived)
  Vec3 origin_towards(const Vec3& d) const { return hit ? offset_ray_origin(*hit, d) : point; }
};

// What gets through along a connection: the transmittance (ratio-tracked in scattering media,
// exact elsewhere) and the connection's factors of the spectral MIS ratios (media/scattering.h).
template <std::size_t N>
struct Transmission {
  SampledSpectrum<N> tr = SampledSpectrum<N>::constant(1.0f);
  SpectralMis<N> ratios;
  double tau = 0.0;  // with sigma_mean given: Σ σ̄_s·∫ρ over the scattering media crossed (integrators/walk.h)
};

// The connection from `from` along wi to a point distance_m away (infinite: a distant light or
// the environment), starting in `medium`: nullopt when a surface blocks it. It crosses
// index-matched interfaces (Surface::index_matched: medium boundaries that neither reflect nor
// refract) into the medium beyond and stops at any other surface, glass included; so a medium
// inside glass or behind a water surface gets no direct light (docs/rendering.md). Surfaces of
// nested objects are seen as the path would see them (surface_seen), from the set `from.inside`.
// With `sigma_mean` (σ̄_s by medium), it also sums the segment's mean scattering optical depth for
// the MIS weights of the bidirectional estimators (Tungsten's generalised shadow ray with pdfs).
// With `by_smooth_interface`, it also says whether what blocked it was a smooth interface (glass,
// a liquid's surface): what next-event estimation through the interfaces may go on through.
template <std::size_t N>
std::optional<Transmission<N>> transmission(const SceneView<N>& v, const PathVertex& from, const Vec3& wi,
                                            double distance_m, int medium, const SampledWavelengths<N>& w, Rng& rng,
                                            std::uint64_t& rays, std::span<const double> sigma_mean = {},
                                            bool* by_smooth_interface = nullptr);

// Where next-event estimation at a surface may carry the environment map's direction on through
// smooth interfaces (the path tracer's surface exit guide, below): as many as the walk could still
// cross, and its count of index-matched crossings so far.
struct ThroughInterfaces {
  int surfaces_left = 0;
  int crossings = 0;
};

// Direct light at a non-specular surface event, towards wo: one area light drawn by power, every
// delta light and (with `environment`) one direction of the environment map; MIS-weighted
// against BSDF sampling by the power heuristic when `mis` is set. Shadow rays go as
// transmission() says; with `through`, the environment's goes on through the smooth interfaces
// that block it (below: ExitGuide at a surface). path_r_u: the path's unidirectional ratios so far
// (all 1 outside scattering media).
template <std::size_t N>
SampledSpectrum<N> direct_light(const SceneView<N>& v, const Hit& hit, const SurfaceEvent<N>& e, const Vec3& wo,
                                const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng,
                                std::uint64_t& rays, bool mis, bool environment,
                                const ThroughInterfaces* through = nullptr);

// The same at a scattering event at `x` inside scattering medium `medium`, for light travelling
// along `direction`: the phase function in place of the BSDF, always MIS-weighted against phase
// sampling.
template <std::size_t N>
SampledSpectrum<N> direct_light_in_medium(const SceneView<N>& v, const Vec3& x, const Vec3& direction,
                                          const PhaseFunction& phase, int medium, const SampledWavelengths<N>& w,
                                          const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays,
                                          InsideSet inside = 0);

// Next-event estimation deep in a dense medium (the path tracer, #20). A connection from a medium
// vertex that is R from every surface and every point or spot light crosses at least R of its
// medium, so in a homogeneous one it gets through with probability at most exp(−τ_R), τ_R =
// σ_s·ρ·R at the least-scattering carried wavelength. Deep in whole milk that is e^−100, and the
// light's sample, its shadow ray and the tracking that finds the ray blocked took half of a walk's
// time. The path tracer does next-event estimation at a medium vertex with probability
// q = min(1, max(kNeeFloor, exp(kNeeFullDepth − τ_R))) and divides what it finds by q: the
// expectation is the same for any q > 0, and the MIS weights against phase sampling keep their
// meaning (they sum to 1 over the strategies, the roulette only thins one of them). A connection
// that q thins is worth at most e^−3 of a light's unshadowed value in expectation; a rare one that
// gets through is worth up to 1/q of it in its sample. R comes from a point query
// (RayScene::distance_to_surfaces) and is reused while the triangle inequality decides: |x − c|
// from the last query point c, the distance at x lies within R(c) ± |x − c|, so a vertex within
// reach of a surface (q = 1) or far below it (q = kNeeFloor) needs no query. Media whose density
// varies keep q = 1 (their ρ along a ray has no lower bound).
inline constexpr double kNeeFullDepth = 3.0;
inline constexpr double kNeeFloor = 1.0 / 64.0;
// The last such query of a walk: a point and its distance to the nearest surface or point light
// (capped). The walk reuses it too (walk.h: a walk of one wavelength deep in a homogeneous medium
// needs no ray where the next collision falls within the bound).
struct SurfaceDistance {
  Vec3 centre;              // where the last query was made
  double radius_m = -1.0;   // the distance found there (capped); < 0: none yet
  double surface_m = -1.0;  // the same without the point lights
  Vec3 nearest;             // the nearest surface point, where surface_m is below the cap
  std::uint32_t nearest_geometry = 0;  // its surface (RenderScene::surfaces), there too
};
template <std::size_t N>
double nee_probability_in_medium(const SceneView<N>& v, int medium, const Vec3& x, const SampledWavelengths<N>& w,
                                 SurfaceDistance& last);

// Next-event estimation through the interfaces (the path tracer, #20). A connection stops at any
// surface but an index-matched one, so a dense medium inside glass or below a water surface gets
// no direct light: its light comes from walks that leave by chance in a direction that meets the
// bright part of the environment map. Under a studio map that was most of a glass of milk's noise
// (seed against seed, mean ΔE00 9.5 at 64 spp against 3.2 under a uniform sky of the same
// brightness). So a medium vertex of a walk of one wavelength (after a split or a dispersive
// interface) in a homogeneous medium, within kExitGuideDepth mean free paths of a surface, also
// draws a direction from the map carried into the medium through a refraction at a guessed plane:
// its normal points from the vertex to the nearest surface point (RayScene::distance_to_surfaces),
// its relative index is the medium's over the world's (a thin parallel wall of glass between them
// bends a ray as one refraction does). It follows that direction to the surface and through the
// smooth interfaces it meets, each transmitting (1 − F), to the map
// (environment_through_interfaces). The guess only shapes a density: where it is wrong the
// connection is noisier, never biased. The walk's own paths that leave the same way (a
// phase-function direction, no event before the surface, refractions only) are weighted against
// it by the power heuristic (the walk keeps the guide of its last medium vertex: walk.h,
// WalkState::guide).
inline constexpr double kExitGuideDepth = 3.0;
inline constexpr std::uint64_t kExitGuideStream = 0x65786974;  // "exit"
// Unless the scene says (RenderSettings::exit_guide), the guide runs where the map's contrast
// (EnvironmentMap::contrast) is at least kExitGuideContrast. Under a smooth map a walk's own exits
// already see it about as well as the map's samples do, and the connections' transmittance to the
// surface only adds noise. Measured on the whole-milk glass (docs/performance.md): the studio map
// (contrast 12) guided 1.6 times the efficiency; blended towards its mean to contrast 4, even; the
// whole-milk ball under its grey sky (1.4), half; a white map (1), a fiftieth.
inline constexpr double kExitGuideContrast = 4.0;
inline bool exit_guide_enabled(const RenderSettings& settings, const RenderScene& scene) {
  if (settings.exit_guide) return *settings.exit_guide;
  return scene.environment && scene.environment->contrast >= kExitGuideContrast;
}
// Whether either guide (medium or surface, below) runs in this render: it is on and there is a map.
template <std::size_t N>
bool exit_guide_runs(const SceneView<N>& v) {
  return v.exit_guide && v.scene.environment && v.scene.environment_light >= 0;
}
struct ExitGuide {
  Vec3 normal;       // the guessed plane's, out of the medium
  double eta = 0.0;  // the medium's index over the world's; 0: no guide here
  bool from_surface = false;  // set at a surface vertex (below): the map's own density, no plane
  bool active() const { return eta > 0.0; }
};
template <std::size_t N>
ExitGuide exit_guide_at(const SceneView<N>& v, int medium, const Vec3& x, const SampledWavelengths<N>& w,
                        SurfaceDistance& last, InsideSet inside);
// The same at a surface (#20). Next-event estimation at a non-specular surface draws a direction
// from the map, and a smooth interface in the way (glass, a liquid's surface) stopped its shadow
// ray: the light that reaches a sweep through an empty glass's walls, or a clear liquid's coloured
// shadow, came only from BSDF directions that happened to meet the map's bright parts through
// them (speckle on the sweep around the glasses of `milk-and-juice`). With the guide on, that
// shadow ray goes on through the smooth interfaces it meets, refracting and transmitting (1 − F)
// at each, through media that only absorb, to the map (direct_light's `through`). No plane is
// guessed: the map's density of the first direction is the strategy's (a thin wall, or a vessel
// seen from outside, bends a ray little; where it bends more the connection is noisier, never
// biased). The walk's own paths that leave the same way (a BSDF direction, refractions only, no
// scattering medium, no wavelength kept at a dispersive interface on the way) are weighted against
// it as unblocked ones are against next-event estimation (radiance.h, walk.h).
inline ExitGuide surface_exit_guide() { return {Vec3{}, 1.0, true}; }
// The guide's solid-angle density of the direction wi out of the vertex: the map's density of the
// direction wi refracts into at the plane, times |dω_out/dω_in| = η²·cos θin / cos θout; 0 for
// a direction into the medium or one the plane reflects totally.
double exit_guide_pdf(const RenderScene& scene, const ExitGuide& guide, const Vec3& wi);
// A direction drawn from it (the map's sample carried back through the plane), or none.
std::optional<Vec3> sample_exit_guide(const RenderScene& scene, const ExitGuide& guide, double u1, double u2);
// The connection itself at medium vertex x (as direct_light_in_medium's arguments): what reaches
// the map along a direction drawn from the guide, through at least one smooth interface,
// MIS-weighted against the phase function's direction; zero where it meets any other surface.
// It stops where the walk would: after `surfaces_left` surfaces (the walk's max_depth less the
// surfaces it has met) or once `crossings` (the walk's count so far) passes kMaxCrossings.
template <std::size_t N>
SampledSpectrum<N> environment_through_interfaces(const SceneView<N>& v, const Vec3& x, const Vec3& direction,
                                                  const PhaseFunction& phase, int medium, const ExitGuide& guide,
                                                  const SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays,
                                                  InsideSet inside, int surfaces_left, int crossings);

// The mean of a path's ratios, which its contributions are divided by (1 without scattering media,
// where the ratios are not read); with `connection`, of the path's ratios times a connection's.
template <std::size_t N>
float mean_ratio(const RenderScene& scene, const SampledSpectrum<N>& r) {
  return scene.scatters ? r.average() : 1.0f;
}
template <std::size_t N>
float mean_ratio(const RenderScene& scene, const SampledSpectrum<N>& r, const SampledSpectrum<N>& connection) {
  return scene.scatters ? (r * connection).average() : 1.0f;
}

// The MIS weight (power heuristic) of a strategy with density pdf_a and ratios r_a against one
// with pdf_b and r_b: the densities of the two one-sample mixtures over the carried wavelengths.
template <std::size_t N>
double spectral_power_heuristic(const RenderScene& scene, double pdf_a, const SampledSpectrum<N>& r_a, double pdf_b,
                                const SampledSpectrum<N>& r_b) {
  return power_heuristic(pdf_a * mean_ratio(scene, r_a), pdf_b * mean_ratio(scene, r_b));
}

// At the first dispersive interface a path meets, keep carried wavelength j = ⌊u·N⌋ with weight
// N and terminate the others (their throughput becomes 0): each wavelength's expected
// contribution is unchanged. Returns whether it happened.
template <std::size_t N>
bool keep_one_wavelength(const SceneView<N>& v, const Surface& surface, SampledWavelengths<N>& w,
                         SampledSpectrum<N>& beta, double u, Rng& rng);

// Splitting at a dense chromatic medium (the path tracer, #20). Where a camera path enters a
// scattering medium whose σ_s differs across the carried wavelengths and in which it will scatter
// many times, the spectral-MIS ratios of one walk collapse onto wavelengths near its hero, so a
// pixel's colour comes from a few wavelengths with independent radiance: colour speckle. There the
// path splits into kSplitCount<N> walks of one wavelength each (terminate_secondary), all with the
// same random numbers from the split on. In a homogeneous medium with one phase function, a walk
// with the same numbers at another σ_s is the same walk scaled about the entry point (distances
// −ln(1−u)/σ_s, directions relative to the last one), so below a flat boundary it leaves at the
// same event in the same direction: its wavelengths see the same light, and the noise left is in
// brightness, not colour. Each walk is an ordinary single-wavelength path tracer's walk for its
// wavelength, so the image's expectation does not change. Hero mode and rgb3 split into all the
// carried wavelengths (weight 1); full mode into 4 bins drawn as hero mode draws its wavelengths
// (the eye-sensitivity density at 4 equal offsets of w.split_u, a number stratified over the
// pixel's samples and independent of the hero, whose majorant drew the path's distances so far),
// each weighted 1/(4·P(j)), P(j) the density's mass over [360 + j·w, 360 + (j + 1)·w] nm, w =
// 470/96 nm, which is how a drawn wavelength picks its index (close to the bin's own whole
// nanometres; the weight has only to match the choice): the bins that matter to the colour are
// drawn more often, so a pixel's colour does not hang on how often each of 96 bins came up.
template <std::size_t N>
inline constexpr std::size_t kSplitCount = N <= 4 ? N : 4;
// A segment splits when the medium is chromatic (largest σ_s over smallest at least
// kSplitSpread) and dense (σ_s,max·∫ρ along it at least kSplitDepth: about that many events at
// the most-scattering wavelength before the path could leave); the #12 furnaces (σ_s·r ≤ 1.8)
// stay below it.
inline constexpr double kSplitSpread = 1.1;
inline constexpr double kSplitDepth = 8.0;
template <std::size_t N>
bool splits_wavelengths(const SceneView<N>& v, int medium, const SampledWavelengths<N>& w, const Vec3& start,
                        const Vec3& direction, double length_m);
// Makes `w` and `beta` those of split walk i (of kSplitCount<N>); u_nm places a full-mode bin's
// wavelength within the bin (the one its geometry follows at a dispersive interface). Returns the
// weight given to the bin (1 but in full mode), which the roulette leaves out (walk.h:
// WalkState::split_weight).
template <std::size_t N>
double keep_split_wavelength(const SceneView<N>& v, SampledWavelengths<N>& w, SampledSpectrum<N>& beta, std::size_t i,
                           double u_nm);

// Whether a path crossing `surface` splits the wavelengths: an interface with a medium whose index
// varies with wavelength on either side.
inline bool is_dispersive(const RenderScene& scene, const Surface& surface) {
  if (surface.kind != SurfaceKind::interface) return false;
  return scene.media[static_cast<std::size_t>(surface.medium_front)].dispersive ||
         scene.media[static_cast<std::size_t>(surface.medium_behind)].dispersive;
}

// Terminates all carried wavelengths but j = ⌊u·N⌋ (its value within its bin drawn in full mode)
// and returns j; the caller weighs what it carries by N.
template <std::size_t N>
int keep_wavelength(const SceneView<N>& v, SampledWavelengths<N>& w, double u, Rng& rng);


// A light path's contribution l (all carried wavelengths) at film position (x, y), in pixels.
template <std::size_t N>
void add_splat(FilmBuffer& film, const SpectralTables<N>& tables, const SampledWavelengths<N>& w, double x, double y,
               const SampledSpectrum<N>& l) {
  if (film.has_spectra())
    film.add_splat(x, y, tables.to_linear_rgb(l, w), std::span<const float>(l.v.data(), N));
  else
    film.add_splat(x, y, tables.to_linear_rgb(l, w));
}

// A light-path vertex at a non-specular surface, arrived at along wo (towards the light): the
// light it sends to the camera, through the medium on the camera's side, splatted at its film
// position. The throughput beta carries importance-mode weights; path_r_u the path's ratios.
template <std::size_t N>
void splat_surface_to_camera(const SceneView<N>& v, const Hit& hit, const SurfaceEvent<N>& e, const Vec3& wo,
                             const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w,
                             const SampledSpectrum<N>& path_r_u, Rng& rng, FilmBuffer& film, std::uint64_t& rays);

// The same for a scattering event at `x` in `medium` of a light path travelling along `direction`.
template <std::size_t N>
void splat_medium_to_camera(const SceneView<N>& v, const Vec3& x, const Vec3& direction, const PhaseFunction& phase,
                            int medium, const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w,
                            const SampledSpectrum<N>& path_r_u, Rng& rng, FilmBuffer& film, std::uint64_t& rays,
                            InsideSet inside = 0);

// A light path's first vertex on an area light (the lamp seen directly): `beta` is the emitted
// radiance over the densities of choosing the light and the point; medium is the one in front.
template <std::size_t N>
void splat_light_to_camera(const SceneView<N>& v, const Hit& at, const AreaLight& light, int medium,
                           const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w, Rng& rng,
                           FilmBuffer& film, std::uint64_t& rays);

// What undoes, for Russian roulette, the scaling of radiance by (η_o/η_i)² at each refraction
// (pbrt-v4's etaScale): (n/n_world)² in `medium` for a path carrying radiance, 1 for importance.
// Inside water a camera path's beta is 1/1.33² of what it brings back once it leaves; without
// this a white furnace lost 43 % of its paths at their first roulette, which was all its noise.
inline float roulette_scale(const RenderScene& scene, int medium, TransportMode mode) {
  if (mode != TransportMode::radiance || medium < 0) return 1.0f;
  const double n = scene.media[static_cast<std::size_t>(medium)].ior_reference;
  const double n_world = scene.media[static_cast<std::size_t>(scene.world_medium)].ior_reference;
  return static_cast<float>((n * n) / (n_world * n_world));
}

// Russian roulette from depth 4, never where the medium forbids it (inside an absorber,
// media/medium.h); the survival probability is the largest throughput over wavelengths (beta over
// the mean of the path's ratios, which is what a contribution is divided by, times
// roulette_scale), at least 5 %. Whether the path goes on (beta rescaled if it does). `single`:
// the index of the only wavelength carried (every other's throughput is 0), or −1.
template <std::size_t N>
bool survives_roulette(const RenderScene& scene, int depth, int medium, SampledSpectrum<N>& beta, Rng& rng,
                       float mean_ratio = 1.0f, float scale = 1.0f, int single = -1) {
  constexpr int kRouletteDepth = 4;
  if (depth < kRouletteDepth || (medium >= 0 && !allows_roulette(scene.media[static_cast<std::size_t>(medium)].medium)))
    return true;
  const float largest = single >= 0 ? beta[static_cast<std::size_t>(single)] : beta.max_value();
  const float survive = std::max(0.05f, std::min(1.0f, largest * scale / mean_ratio));
  if (rng.next_double() >= survive) return false;
  if (single >= 0)
    beta[static_cast<std::size_t>(single)] /= survive;
  else
    beta /= survive;
  return true;
}

// The surface a path inside the nested objects `inside` meets at `hit`: the scene's, or for a
// surface of a nested object a copy in `scratch` with the media on its two sides that the set
// gives (scene/nested.h), index-matched where they match (a false intersection: the same medium on
// both sides), so that it is crossed without a vertex, shadow rays included.
inline const Surface& surface_seen(const RenderScene& scene, const Hit& hit, InsideSet inside, Surface& scratch) {
  const Surface& s = scene.surfaces[hit.geometry];
  if (s.nested < 0) return s;
  const NestedSides sides = nested_sides(scene.nested, s.nested, inside);
  scratch = s;
  scratch.medium_front = sides.front;
  scratch.medium_behind = sides.behind;
  scratch.index_matched = indices_match(scene, sides.front, sides.behind);
  return scratch;
}

// The set of a path that leaves the surface at `hit` along d: changed only at a nested object's.
inline InsideSet inside_towards(const RenderScene& scene, const Hit& hit, InsideSet inside, const Vec3& d) {
  const int k = scene.surfaces[hit.geometry].nested;
  return k < 0 ? inside : inside_after(inside, k, dot(d, hit.normal));
}

// The medium a ray that hits `surface` has travelled through: crossing an interface, the one on
// the side it arrives from; else the path's current one.
inline int medium_arrived_through(const Surface& surface, const Ray& ray, const Hit& hit, int medium) {
  if (surface.kind != SurfaceKind::interface) return medium;
  return dot(ray.direction, hit.normal) < 0.0 ? surface.medium_front : surface.medium_behind;
}

// A path's next step from a surface event: wi drawn from the BSDF in the path's transport mode,
// beta multiplied by its weight, the medium wi travels in, the next ray from the hit, Russian
// roulette (`single` as survives_roulette's). Returns the sample's pdf (0: specular), or nullopt
// when the path ends.
template <std::size_t N>
std::optional<double> continue_path(const RenderScene& scene, const Hit& hit, const SurfaceEvent<N>& e,
                                    const Vec3& wo, TransportMode mode, int depth, SampledSpectrum<N>& beta,
                                    int& medium, Ray& ray, Rng& rng, float mean_ratio = 1.0f, int single = -1) {
  const double uc = rng.next_double(), u1 = rng.next_double(), u2 = rng.next_double();
  const auto s = e.sample(wo, uc, u1, u2, mode);
  if (!s) return std::nullopt;
  const Vec3 wi = s->wi;
  beta *= s->weight;
  medium = e.medium_towards(wi);
  if (!survives_roulette(scene, depth, medium, beta, rng, mean_ratio, roulette_scale(scene, medium, mode), single) ||
      beta.is_zero())
    return std::nullopt;
  ray = {offset_ray_origin(hit, wi), wi};
  return s->pdf;
}



// The segment a path travelled from `start` to the surface it hit, through `medium`: beta times
// the exact transmittance, or in a scattering medium, delta tracking (media/scattering.h). The
// point of a real scattering event if there was one.
template <std::size_t N>
std::optional<Vec3> through_medium(const SceneView<N>& v, int medium, const Vec3& start, const Vec3& direction,
                                   const Hit& hit, const SampledWavelengths<N>& w, Rng& rng, SampledSpectrum<N>& beta,
                                   SpectralMis<N>& mis) {
  const ScatteringMedium* sm = scattering_medium(v.scene, medium);
  if (!sm) {
    beta *= travel_to(v, medium, start, direction, hit.point, w);
    return std::nullopt;
  }
  const MediumEvent e = sample_scattering(*sm, v.tables, Ray{start, direction}, length(hit.point - start), w, rng, beta, mis);
  if (!e.scattered) return std::nullopt;
  return start + direction * e.t;
}

// A path's next step from a scattering event at x: a direction drawn from the phase function
// (weight 1), Russian roulette (`events`: the path's surface and scattering events so far;
// roulette_divisor: what survives_roulette divides the throughput by, the mean of the path's
// ratios). The phase pdf, or nullopt when the path ends.
template <std::size_t N>
std::optional<double> continue_from_medium(const RenderScene& scene, const ScatteringMedium& sm, const Vec3& x,
                                           int events, int medium, SampledSpectrum<N>& beta, float roulette_divisor,
                                           Ray& ray, Rng& rng, TransportMode mode, int single = -1) {
  const double u1 = rng.next_double(), u2 = rng.next_double();
  const PhaseSample ps = sample_phase(sm.phase, ray.direction, u1, u2);
  if (!survives_roulette(scene, events, medium, beta, rng, roulette_divisor, roulette_scale(scene, medium, mode), single))
    return std::nullopt;
  ray = {x, ps.out};
  return ps.pdf;
}

// A path at an index-matched interface (Surface::index_matched) crosses it unchanged: the medium
// beyond, a new segment from the hit point, the ray from its offset origin. It is no vertex
// (connections cross it too). False once a path has crossed kMaxCrossings.
inline bool cross_index_matched(const Surface& surface, const Hit& hit, int& crossings, int& medium, Vec3& start,
                                Ray& ray) {
  if (++crossings > kMaxCrossings) return false;
  medium = dot(ray.direction, hit.normal) > 0.0 ? surface.medium_front : surface.medium_behind;
  start = hit.point;
  ray.origin = offset_ray_origin(hit, ray.direction);
  return true;
}

// ---- small events, inline: they run at every vertex -----------------------------------------

inline const AreaLight& area_light_at(const RenderScene& scene, const Hit& hit) {
  const Surface& s = scene.surfaces[hit.geometry];
  return std::get<AreaLight>(scene.lights[static_cast<std::size_t>(s.first_light) + hit.primitive]);
}


template <std::size_t N>
inline SampledSpectrum<N> travel(const SceneView<N>& v, int medium, const Ray& ray, double t_m, const SampledWavelengths<N>& w) {
  if (medium < 0) return SampledSpectrum<N>::constant(1.0f);
  return transmittance(v.scene.media[static_cast<std::size_t>(medium)].medium, v.tables, ray, 0.0, t_m, w);
}

// The same from point `from` to point `to` along the unit direction d: the length is computed
// only where the medium absorbs.
template <std::size_t N>
inline SampledSpectrum<N> travel_to(const SceneView<N>& v, int medium, const Vec3& from, const Vec3& d, const Vec3& to,
                                    const SampledWavelengths<N>& w) {
  if (medium < 0 || !absorbs(v.scene.media[static_cast<std::size_t>(medium)].medium))
    return SampledSpectrum<N>::constant(1.0f);
  return transmittance(v.scene.media[static_cast<std::size_t>(medium)].medium, v.tables, Ray{from, d}, 0.0,
                       length(to - from), w);
}

template <std::size_t N>
inline SampledSpectrum<N> escaped(const SceneView<N>& v, int medium, const Vec3& d, const SampledWavelengths<N>& w) {
  if (absorbs(v.scene, medium)) return {};
  if (v.scene.environment) return v.tables.environment(*v.scene.environment, v.scene.environment->texel(d), w);
  const auto& b = std::get<BackgroundLight>(v.scene.lights[static_cast<std::size_t>(v.scene.background_light)]);
  return v.tables.at(b.radiance, w);
}

// An area light's radiance spectrum at texture coordinates uv: its spectrum, times its emission
// texture's lifted texel there (the finest level: light sampling has no ray cone, and the same
// lookup serves every strategy, so they agree).
template <std::size_t N>
inline SampledSpectrum<N> area_radiance(const SceneView<N>& v, int spectrum, int texture, std::array<double, 2> uv,
                                        const SampledWavelengths<N>& w) {
  const SampledSpectrum<N> l = v.tables.at(spectrum, w);
  if (texture < 0) return l;
  return l * texture_reflectance(v.scene.textures, texel_blend(v.scene.textures, texture, uv, 0.0), w);
}

// The radiance spectrum a light sample (LightLiSample, LightLeSample) carries before its factor.
template <std::size_t N, typename LightSample>
inline SampledSpectrum<N> sample_radiance(const SceneView<N>& v, const LightSample& s, const SampledWavelengths<N>& w) {
  if (s.texel >= 0) return v.tables.environment(*v.scene.environment, s.texel, w);
  return area_radiance(v, s.spectrum, s.texture, s.uv, w);
}

template <std::size_t N>
inline SampledSpectrum<N> emitted(const SceneView<N>& v, const Hit& hit, const Vec3& wo, const SampledWavelengths<N>& w) {
  const AreaLight& light = area_light_at(v.scene, hit);
  const double factor = emitted_factor(light, wo);
  if (factor == 0.0) return {};
  return area_radiance(v, light.radiance, light.texture, hit.uv, w) * static_cast<float>(factor);
}

// The indices on the two sides of an interface, as the path sees them (reference or kept wavelength).
template <std::size_t N>
inline SmoothDielectric interface_indices(const SceneView<N>& v, const Surface& surface, const SampledWavelengths<N>& w) {
  auto eta_of = [&](int m) { return eta(v.scene.media[static_cast<std::size_t>(m)], v.tables, w); };
  return {eta_of(surface.medium_front), eta_of(surface.medium_behind)};
}


// The scattering medium `medium` is, or null.
inline const ScatteringMedium* scattering_medium(const RenderScene& scene, int medium) {
  return medium < 0 ? nullptr : scattering(scene.media[static_cast<std::size_t>(medium)].medium);
}

// A new path's w.hero, the carried wavelength whose majorant draws its distances in scattering
// media (media/scattering.h): ⌊u·N⌋, uniform over the carried ones for a uniform u, which the
// spectral MIS needs (in hero mode too: there index 0 is always the bluest of the four). The path
// tracer hands it a number stratified over the pixel's samples (integrators.h:
// start_sample_wavelengths), so that each pixel's paths draw distances at every part of the
// spectrum equally often: where the carried wavelengths' tracking densities barely overlap (milk,
// hundreds of events a path), the spectral MIS gives a path's weight to the wavelengths near its
// hero, and a random hero per path left whole pixels short of some colours. 0 in scenes that do
// not scatter.
template <std::size_t N>
void draw_hero(const RenderScene& scene, SampledWavelengths<N>& w, double u) {
  w.hero = scene.scatters ? std::min(static_cast<int>(u * static_cast<double>(N)), static_cast<int>(N) - 1) : 0;
}
// The same from the path's own stream, drawn only in scenes that scatter (so other scenes' streams
// are unchanged): bdpt_mis_check's samples. The estimators draw theirs from strata
// (integrators.h: start_sample_wavelengths; vcm.cpp over its iterations).
template <std::size_t N>
void draw_hero(const RenderScene& scene, SampledWavelengths<N>& w, Rng& rng) {
  draw_hero(scene, w, scene.scatters ? rng.next_double() : 0.0);
}

// The texels of texture `id` at the hit's UV, at the level the ray cone chooses (the finest without one).
inline TexelBlend texels_at(const RenderScene& s, int id, const Hit& hit, const Vec3& wo, double cone_width_m) {
  const double cos_theta = dot(wo, hit.normal);
  const AnalyticShape* analytic = s.rays.analytic(hit.geometry);
  const double lod = analytic ? texture_level_of_detail(s.textures, id, *analytic, hit.primitive, hit.uv, cone_width_m,
                                                        cos_theta)
                              : texture_level_of_detail(s.textures, id, s.rays.mesh(hit.geometry), hit.primitive,
                                                        cone_width_m, cos_theta);
  return texel_blend(s.textures, id, hit.uv, lod);
}

// A reflectance at the hit: spectrum `spectrum`, or reflectance texture `texture` (≥ 0) at the hit's UV.
template <std::size_t N>
inline SampledSpectrum<N> reflectance_at(const SceneView<N>& v, int spectrum, int texture, const Hit& hit,
                                         const Vec3& wo, const SampledWavelengths<N>& w, double cone_width_m) {
  if (texture < 0) return v.tables.at(spectrum, w);
  return texture_reflectance(v.scene.textures, texels_at(v.scene, texture, hit, wo, cone_width_m), w);
}

// An opaque surface's material at the hit as a BSDF, its textures read at the hit's UV; `medium`
// is the one around it.
template <std::size_t N>
inline Bsdf<N> opaque_bsdf(const SceneView<N>& v, const SurfaceMaterial& m, const Hit& hit, const Vec3& wo, int medium,
                           const SampledWavelengths<N>& w, double cone_width_m) {
  const RenderScene& s = v.scene;
  if (const auto* d = std::get_if<DiffuseMaterial>(&m))
    return DiffuseReflection<N>{reflectance_at(v, d->reflectance, d->reflectance_texture, hit, wo, w, cone_width_m)};
  if (const auto* t = std::get_if<ThinDielectricMaterial>(&m))
    return ThinDielectric<N>{t->ior / eta(s.media[static_cast<std::size_t>(medium)], v.tables, w),
                             reflectance_at(v, t->tint, t->tint_texture, hit, wo, w, cone_width_m)};
  if (const auto* g = std::get_if<MetallicRoughnessMaterial>(&m)) {
    double metalness = g->metalness, roughness = g->roughness;
    if (g->metallic_roughness_texture >= 0) {
      const Vec3 t = texture_rgb(s.textures, texels_at(s, g->metallic_roughness_texture, hit, wo, cone_width_m));
      metalness = std::clamp(t.z, 0.0, 1.0);
      roughness = std::clamp(t.y, 0.0, 1.0);
    }
    return MetallicRoughness<N>{reflectance_at(v, g->base_colour, g->base_colour_texture, hit, wo, w, cone_width_m),
                                metalness, std::max(roughness * roughness, kMinMetallicRoughnessAlpha)};
  }
  const auto& c = std::get<ConductorMaterial>(m);
  double alpha = c.alpha;
  if (c.alpha_texture >= 0) {
    const Vec3 t = texture_rgb(s.textures, texels_at(s, c.alpha_texture, hit, wo, cone_width_m));
    alpha = std::clamp((t.x + t.y + t.z) / 3.0, 0.0, 1.0);
  }
  return ConductorReflection<N>{v.tables.at(c.n, w), v.tables.at(c.k, w),
                                eta(s.media[static_cast<std::size_t>(medium)], v.tables, w), alpha};
}

template <std::size_t N>
inline SurfaceEvent<N> surface_event(const SceneView<N>& v, const Hit& geometric_hit, const Surface& surface,
                                     const Vec3& wo, int medium, const SampledWavelengths<N>& w, double cone_width_m) {
  const Hit hit = normal_mapped(v.scene, surface, geometric_hit);  // its shading normal from a normal map
  const RenderScene& s = v.scene;
  const Vec3& ns = hit.shading_normal;
  if (surface.kind == SurfaceKind::opaque) {
    const double side = dot(wo, hit.normal) > 0.0 ? 1.0 : -1.0;
    const Frame frame(ns * side);
    const Vec3 ng = hit.normal * side;
    const SurfaceMaterial& m = s.materials[static_cast<std::size_t>(surface.material)];
    return {frame, opaque_bsdf(v, m, hit, wo, medium, w, cone_width_m), medium, medium, 0, ng};
  }
  const SmoothDielectric indices = interface_indices(v, surface, w);
  const Frame frame(ns);
  if (surface.roughness == 0.0) return {frame, indices, surface.medium_front, surface.medium_behind, 0, hit.normal};
  const RoughDielectricBsdf lobe{{surface.roughness}, indices.eta_front, indices.eta_behind,
                                 &s.dielectric_albedo[static_cast<std::size_t>(surface.albedo)]};
  return {frame, RoughDielectric{lobe}, surface.medium_front, surface.medium_behind, 0, hit.normal};
}

}  // namespace bouguer
