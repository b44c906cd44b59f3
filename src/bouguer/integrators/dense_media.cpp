#include "bouguer/integrators/dense_media.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace bouguer {

template <std::size_t N>
bool splits_wavelengths(const SceneView<N>& v, int medium, const SampledWavelengths<N>& w, const Vec3& start,
                        const Vec3& direction, double length_m) {
  if (N == 1 || w.secondary_terminated()) return false;
  const ScatteringMedium* sm = scattering_medium(v.scene, medium);
  if (!sm) return false;
  const SampledSpectrum<N> sigma_s = v.tables.at(sm->sigma_s, w);
  float lo = sigma_s[0], hi = sigma_s[0];
  for (std::size_t k = 1; k < N; ++k) {
    lo = std::min(lo, sigma_s[k]);
    hi = std::max(hi, sigma_s[k]);
  }
  if (!(hi > 0.0f) || static_cast<double>(hi) < kSplitSpread * static_cast<double>(lo)) return false;
  return static_cast<double>(hi) * scattering_column_density(*sm, Ray{start, direction}, 0.0, length_m) >= kSplitDepth;
}

template <std::size_t N>
double keep_split_wavelength(const SceneView<N>& v, SampledWavelengths<N>& w, SampledSpectrum<N>& beta, std::size_t i,
                           double u_nm) {
  constexpr std::size_t kCount = kSplitCount<N>;
  std::size_t j = i;
  double weight = 1.0;
  if constexpr (N > kCount) {  // full mode: bins by the basis's split density (dense_media.h)
    const SpectralBasis<N>& basis = v.tables.basis();
    double u = w.split_u + static_cast<double>(i) / kCount;
    if (u >= 1.0) u -= 1.0;
    j = std::min(static_cast<std::size_t>(std::upper_bound(basis.split_cdf.begin(), basis.split_cdf.end(), u) -
                                          basis.split_cdf.begin()),
                 N - 1);
    weight = 1.0 / (kCount * basis.split_probability[j]);
  }
  w.terminate_secondary(static_cast<int>(j), v.tables.kept_wavelength_nm(w, static_cast<int>(j), u_nm));
  const float kept = beta[j] * static_cast<float>(weight);
  beta = SampledSpectrum<N>{};
  beta[j] = kept;
  return weight;
}

// σ_s·ρ of a homogeneous scattering medium at the least-scattering carried wavelength (the walk's
// own after a split); 0 for any other medium.
template <std::size_t N>
double homogeneous_sigma_min_per_m(const SceneView<N>& v, int medium, const SampledWavelengths<N>& w) {
  const ScatteringMedium* sm = scattering_medium(v.scene, medium);
  const auto* constant = sm ? std::get_if<ConstantField>(&sm->density) : nullptr;
  if (!constant) return 0.0;
  float lo;
  if (w.secondary_terminated()) {
    lo = v.tables.at_index(sm->sigma_s, w, static_cast<std::size_t>(w.single));
  } else {
    const SampledSpectrum<N> sigma_s = v.tables.at(sm->sigma_s, w);
    lo = sigma_s[0];
    for (std::size_t k = 1; k < N; ++k) lo = std::min(lo, sigma_s[k]);
  }
  const double sigma_per_m = static_cast<double>(lo) * constant->value;
  return sigma_per_m > 0.0 ? sigma_per_m : 0.0;
}

namespace {

// The distance beyond which the thinning of next-event estimation is at its floor.
double nee_floor_m(double sigma_per_m) { return (kNeeFullDepth - std::log(kNeeFloor)) / sigma_per_m; }

// The distance from x to the nearest point or spot lamp (infinite without one): next-event
// estimation connects in full near one, as near a surface.
double point_lamp_distance_m(const RenderScene& scene, const Vec3& x) {
  double d = std::numeric_limits<double>::infinity();
  for (const int index : scene.delta_lights) {
    const Light& light = scene.lights[static_cast<std::size_t>(index)];
    if (const auto* p = std::get_if<PointLight>(&light)) d = std::min(d, length(x - p->position_m));
    if (const auto* s = std::get_if<SpotLight>(&light)) d = std::min(d, length(x - s->position_m));
  }
  return d;
}
}  // namespace

// A fresh point query at x, as far as the thinning of next-event estimation needs to look.
template <std::size_t N>
void query_surface_distance(const SceneView<N>& v, const Vec3& x, double sigma_per_m, SurfaceDistance& last,
                            double cap_m) {
  cap_m = std::max(cap_m, 2.0 * nee_floor_m(sigma_per_m));
  last.centre = x;
  last.cap_m = cap_m;
  last.surface_m = v.scene.rays.distance_to_surfaces(x, cap_m, &last.nearest, &last.nearest_geometry);
  // (|x − nearest|, not surface_m: an analytic shape's distance is a lower bound where it is
  // stretched unevenly.)
  const double apart_m = length(x - last.nearest);
  if (last.surface_m > 0.0 && last.surface_m < cap_m && apart_m > 0.0) last.away = (x - last.nearest) / apart_m;
  last.radius_m = std::min(last.surface_m, point_lamp_distance_m(v.scene, x));
}

template <std::size_t N>
double nee_probability_in_medium(const SceneView<N>& v, int medium, const Vec3& x, const SampledWavelengths<N>& w,
                                 SurfaceDistance& last) {
  const double sigma_per_m = walk_sigma_min_per_m(v, medium, w, last);
  if (!(sigma_per_m > 0.0)) return 1.0;
  const double full_m = kNeeFullDepth / sigma_per_m;
  const double floor_m = nee_floor_m(sigma_per_m);
  if (last.radius_m >= 0.0) {
    const double moved = length(x - last.centre);
    if (last.radius_m + moved <= full_m) return 1.0;  // (a capped radius is larger than full_m)
    if (last.radius_m - moved >= floor_m) return kNeeFloor;
    // Where the bound cannot decide, near the last query: the distance to its nearest point's plane
    // (near_surface_m), as a probability of the walk's own state needs no more to stay exact.
    const double near_m = near_surface_m(last, x, sigma_per_m);
    if (near_m >= 0.0) {
      const double r = std::min(near_m, point_lamp_distance_m(v.scene, x));
      return std::clamp(std::exp(kNeeFullDepth - sigma_per_m * r), kNeeFloor, 1.0);
    }
  }
  query_surface_distance(v, x, sigma_per_m, last);
  return std::clamp(std::exp(kNeeFullDepth - sigma_per_m * last.radius_m), kNeeFloor, 1.0);
}

#define BOUGUER_DENSE_MEDIA_INSTANTIATE(N) \
  template double homogeneous_sigma_min_per_m(const SceneView<N>&, int, const SampledWavelengths<N>&); \
  template void query_surface_distance(const SceneView<N>&, const Vec3&, double, SurfaceDistance&, double); \
  template double nee_probability_in_medium(const SceneView<N>&, int, const Vec3&, const SampledWavelengths<N>&, \
      SurfaceDistance&); \
  template bool splits_wavelengths(const SceneView<N>&, int, const SampledWavelengths<N>&, const Vec3&, \
      const Vec3&, double); \
  template double keep_split_wavelength(const SceneView<N>&, SampledWavelengths<N>&, SampledSpectrum<N>&, \
      std::size_t, double);
BOUGUER_DENSE_MEDIA_INSTANTIATE(kFullBins)
BOUGUER_DENSE_MEDIA_INSTANTIATE(3)
BOUGUER_DENSE_MEDIA_INSTANTIATE(kHeroCount)
#undef BOUGUER_DENSE_MEDIA_INSTANTIATE

}  // namespace bouguer
