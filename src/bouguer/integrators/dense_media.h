#pragma once
// The path tracer's heuristics for dense media (#20), each leaving the expectation unchanged:
// next-event estimation thinned deep in a homogeneous medium, from a bound on the distance to
// every surface (nee_probability_in_medium, SurfaceDistance), and the split of a walk into walks
// of one wavelength at a dense chromatic medium (splits_wavelengths, keep_split_wavelength).
// Contract: each changes only how often or with which weight a path samples, never what it
// estimates.
#include "bouguer/integrators/scene_view.h"

namespace bouguer {

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
// reach of a surface (q = 1) or far below it (q = kNeeFloor) needs no query. Between, within
// kNearMfp mean free paths of c, R is read from the plane through c's nearest point
// (near_surface_m): not a bound, but q may be any function of the walk's own state, and a walk
// near a glass wall took a query at nearly every collision there (point queries, most of them
// these, took a fifth of the whole-milk glass's time). Media whose density varies keep q = 1
// (their ρ along a ray has no lower bound).
inline constexpr double kNeeFullDepth = 3.0;
inline constexpr double kNeeFloor = 1.0 / 64.0;
// A walk split into walks of one wavelength (below) scatters hundreds of times. With a forward
// phase function of mean cosine g it keeps its direction for about 1/(1 − g) collisions (a
// transport mean free path), and its connections at those collisions reach a light through nearly
// the same lobe of the phase function from nearly the same place. Where a connection goes on
// through glass (a solve of the refractions to a lamp: manifold.h, manifold_chain.h), each costs
// some ten shadow rays and adds little that its neighbours do not: so such a walk makes those
// connections with probability 1 − g (divided by it, the expectation the same), as if once a
// transport mean free path; its straight connections, a shadow ray each, keep the depth's q above.
// In whole milk (g 0.864: a share of 0.136) in a glass at 32×24 (docs/performance.md): 2.9 times
// the efficiency under a sun, 1.7 times under a point lamp; under the studio map alone, as before.
// A back-scattering medium (g < 0) keeps every connection; one nearly all forward (g near 1) keeps
// kNeeFloor of them, as deep in a medium, so that this share weighs a connection at most 64 times
// over (the depth's q comes on top of it). Only in the medium the walk split at: a split walk that
// leaves it for a thin one scatters there a few times, where its connections are worth making.
inline double split_walk_nee_share(const PhaseFunction& phase) {
  return std::clamp(1.0 - mean_cosine(phase), kNeeFloor, 1.0);
}
// The last such query of a walk: a point and its distance to the nearest surface or point light
// (capped). The walk reuses it too (walk.h: a walk of one wavelength deep in a homogeneous medium
// needs no ray where the next collision falls within the bound).
struct SurfaceDistance {
  Vec3 centre;              // where the last query was made
  double radius_m = -1.0;   // the distance found there (capped); < 0: none yet
  double cap_m = 0.0;       // how far that query looked: a radius below it is exact
  double surface_m = -1.0;  // the same without the point lights
  Vec3 nearest;             // the nearest surface point, where surface_m is below the cap
  Vec3 away;                // the unit direction from it to the centre, there too (surface_m > 0)
  std::uint32_t nearest_geometry = 0;  // its surface (RenderScene::surfaces), there too
  // σ_s·ρ of the medium at the walk's one wavelength (homogeneous_sigma_min_per_m), for the medium
  // and the wavelength it was read for: a spectral table read once a walk of one wavelength, not
  // three times at each of its collisions (walk_deep reads it too).
  int sigma_medium = -1, sigma_single = -1;
  double sigma_min_per_m = 0.0;
  bool holds_sigma(int medium, int single) const { return single >= 0 && sigma_medium == medium && sigma_single == single; }
};
// The radius about p that the bound `near` shows free of every surface and point light: its
// distance less how far p is from where it was measured, less a float margin (a ray's hit point
// lies on the double-precision triangle within float rounding of the scene's coordinates); not
// positive where the bound shows none. What walk_deep (walk.h) and a sphere of shell transport
// (shell_hops.h) may take without a ray.
inline double free_radius_m(const RayScene& rays, const SurfaceDistance& near, const Vec3& p) {
  if (!(near.radius_m > 0.0)) return -1.0;
  return near.radius_m - length(p - near.centre) - 1e-5 * rays.rounding_scale_m(p);
}
// Near the last query (within kNearMfp mean free paths of its centre, where it found the nearest
// point), the distance to the surfaces estimated without a query: to the plane through that point
// across `away` (exact below a flat face; below a curved one off by about the step aside squared
// over twice the distance to its centre of curvature; near an inner edge or corner, where another
// face is nearer, up to twice the step). Negative where the last query cannot say. What
// nee_probability_in_medium reads between queries. (The exit guide read it too, as its distance
// and its refraction plane's normal: the same efficiency on the whole-milk glass, but 3 % more
// ΔE00 between seeds, so the guide keeps its exact nearest point: docs/performance.md.)
inline constexpr double kNearMfp = 2.0;
inline double near_surface_m(const SurfaceDistance& last, const Vec3& x, double sigma_per_m) {
  if (!(last.surface_m > 0.0) || !(last.surface_m < last.cap_m)) return -1.0;
  if (length(x - last.centre) * sigma_per_m > kNearMfp) return -1.0;
  return std::max(0.0, dot(x - last.nearest, last.away));
}
template <std::size_t N>
double nee_probability_in_medium(const SceneView<N>& v, int medium, const Vec3& x, const SampledWavelengths<N>& w,
                                 SurfaceDistance& last);
// σ_s·ρ of a homogeneous scattering medium at the least-scattering carried wavelength (the walk's
// own after a split); 0 for any other medium.
template <std::size_t N>
double homogeneous_sigma_min_per_m(const SceneView<N>& v, int medium, const SampledWavelengths<N>& w);
// The same, kept in `last` for a walk of one wavelength.
template <std::size_t N>
double walk_sigma_min_per_m(const SceneView<N>& v, int medium, const SampledWavelengths<N>& w, SurfaceDistance& last) {
  if (last.holds_sigma(medium, w.single)) return last.sigma_min_per_m;
  const double sigma_per_m = homogeneous_sigma_min_per_m(v, medium, w);
  if (w.secondary_terminated()) {
    last.sigma_medium = medium;
    last.sigma_single = w.single;
    last.sigma_min_per_m = sigma_per_m;
  }
  return sigma_per_m;
}
// A fresh point query at x, as far as the thinning of next-event estimation needs to look, or as
// far as `cap_m` where that is further (shell transport: shell_hops.h).
template <std::size_t N>
void query_surface_distance(const SceneView<N>& v, const Vec3& x, double sigma_per_m, SurfaceDistance& last,
                            double cap_m = 0.0);

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
// carried wavelengths (weight 1); full mode into 4 bins drawn by the basis's split_probability
// (a density per nm as sqrt(x̄ + ȳ + z̄/2), spectral_sampling.h) at 4 equal offsets of w.split_u,
// a number stratified over the pixel's samples and independent of the hero, whose majorant drew
// the path's distances so far, each weighted 1/(4·P(j)): the bins that matter to the colour are
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
// SplitsWalks).
template <std::size_t N>
double keep_split_wavelength(const SceneView<N>& v, SampledWavelengths<N>& w, SampledSpectrum<N>& beta, std::size_t i,
                           double u_nm);

}  // namespace bouguer
