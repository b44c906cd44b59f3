#include "bouguer/integrators/splats.h"

#include <cmath>

namespace bouguer {

namespace {

// Adds `value` (already multiplied by everything but the connection and the camera's factor) at
// the camera's film position when the connection gets through; the light tracer has no other
// strategy for it, so only its own ratios divide it.
template <std::size_t N>
void splat_towards(const SceneView<N>& v, const PathVertex& at, const CameraConnection& c, int medium,
                   const SampledSpectrum<N>& value, const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u,
                   Rng& rng, FilmBuffer& film, std::uint64_t& rays) {
  if (value.is_zero()) return;
  const auto t = transmission(v, at, c.wi, c.distance_m, medium, w, rng, rays);
  if (!t) return;
  const SampledSpectrum<N> l =
      value * t->tr * static_cast<float>(c.factor / mean_ratio(v.scene, path_r_u, t->ratios.r_l));
  add_splat(film, v.tables, w, c.film_x, c.film_y, l);
}

}  // namespace

template <std::size_t N>
void splat_surface_to_camera(const SceneView<N>& v, const Hit& hit, const SurfaceEvent<N>& e, const Vec3& wo,
                             const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w,
                             const SampledSpectrum<N>& path_r_u, Rng& rng, FilmBuffer& film, std::uint64_t& rays) {
  const auto c = v.camera.connect(hit.point);
  if (!c) return;
  const SampledSpectrum<N> f = e.eval(wo, c->wi, TransportMode::importance);
  splat_towards(v, PathVertex{hit.point, &hit, e.inside}, *c, e.medium_towards(c->wi), beta * f, w, path_r_u, rng, film, rays);
}

template <std::size_t N>
void splat_medium_to_camera(const SceneView<N>& v, const MediumPoint& at, const SampledSpectrum<N>& beta,
                            const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng,
                            FilmBuffer& film, std::uint64_t& rays) {
  const auto c = v.camera.connect(at.x);
  if (!c) return;
  const auto p = static_cast<float>(phase_value(at.phase, at.direction, c->wi));
  splat_towards(v, PathVertex{at.x, nullptr, at.inside}, *c, at.medium, beta * p, w, path_r_u, rng, film, rays);
}

template <std::size_t N>
void splat_light_to_camera(const SceneView<N>& v, const Hit& at, const Light& light, int medium,
                           const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w, Rng& rng,
                           FilmBuffer& film, std::uint64_t& rays) {
  const auto c = v.camera.connect(at.point);
  if (!c) return;
  const double factor = emitted_factor(light, c->wi, at.normal) * std::abs(dot(c->wi, at.normal));
  splat_towards(v, PathVertex{at.point, &at}, *c, medium, beta * static_cast<float>(factor), w,
                SampledSpectrum<N>::constant(1.0f), rng, film, rays);
}

#define BOUGUER_SPLATS_INSTANTIATE(N) \
  template void splat_surface_to_camera(const SceneView<N>&, const Hit&, const SurfaceEvent<N>&, const Vec3&, \
      const SampledSpectrum<N>&, const SampledWavelengths<N>&, const SampledSpectrum<N>&, Rng&, FilmBuffer&, \
      std::uint64_t&); \
  template void splat_medium_to_camera(const SceneView<N>&, const MediumPoint&, const SampledSpectrum<N>&, \
      const SampledWavelengths<N>&, const SampledSpectrum<N>&, Rng&, FilmBuffer&, std::uint64_t&); \
  template void splat_light_to_camera(const SceneView<N>&, const Hit&, const Light&, int, \
      const SampledSpectrum<N>&, const SampledWavelengths<N>&, Rng&, FilmBuffer&, std::uint64_t&);
BOUGUER_SPLATS_INSTANTIATE(kFullBins)
BOUGUER_SPLATS_INSTANTIATE(3)
BOUGUER_SPLATS_INSTANTIATE(kHeroCount)
#undef BOUGUER_SPLATS_INSTANTIATE

}  // namespace bouguer
