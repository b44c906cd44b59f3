// The unidirectional spectral path tracer. Next-event estimation (integrators/events.h) combined
// with BSDF sampling by multiple importance sampling (power heuristic). At a smooth interface the
// path reflects with probability F and refracts otherwise (weight 1: the Fresnel factor cancels),
// so the same interface and medium model as the Whitted integrator hold, and both converge to the
// same image. Shadow rays are blocked by any surface; light reaches diffuse surfaces through glass
// along BSDF-sampled paths (caustics, coloured shadows).
// Russian roulette starts at depth 4 and is never played where the medium forbids it (inside an
// absorber, media/medium.h); the survival probability is the largest throughput over
// wavelengths, at least 5 %.
// Dispersion: at the first dispersive interface the path keeps one wavelength (keep_one_wavelength;
// its choice stratified over the pixel's samples by the caller) and follows n(λ) from there on;
// each wavelength's expected contribution is unchanged.
#include "bouguer/integrators/integrators.h"

namespace bouguer {
namespace {

template <std::size_t N>
SampledSpectrum<N> path(const SceneView<N>& v, Ray ray, SampledWavelengths<N>& w, double dispersion_u, Rng& rng,
                        std::uint64_t& rays) {
  const RenderScene& scene = v.scene;
  SampledSpectrum<N> l, beta = SampledSpectrum<N>::constant(1.0f);
  double prev_pdf = 0.0;  // 0: the last event was specular (or the camera)
  Vec3 prev_point = ray.origin;
  int medium = scene.world_medium;
  for (int depth = 0;; ++depth) {
    ++rays;
    const auto hit = scene.rays.intersect(ray);
    if (!hit) {  // an environment map is also reached by next-event estimation: weighted against it
      const double mis = prev_pdf == 0.0 || !scene.environment
                             ? 1.0
                             : power_heuristic(prev_pdf, environment_pdf(scene, ray.direction));
      l += beta * escaped(v, medium, ray.direction, w) * static_cast<float>(mis);
      break;
    }
    const Surface& surface = scene.surfaces[hit->geometry];
    medium = medium_arrived_through(surface, ray, *hit, medium);
    beta *= travel_to(v, medium, prev_point, ray.direction, hit->point, w);
    const Vec3 wo = -ray.direction;
    if (surface.kind == SurfaceKind::emitter) {
      const double mis =
          prev_pdf == 0.0 ? 1.0 : power_heuristic(prev_pdf, area_light_pdf(scene, *hit, prev_point, ray.direction));
      l += beta * emitted(v, *hit, wo, w) * static_cast<float>(mis);
      break;
    }
    if (depth >= v.max_depth) break;
    keep_one_wavelength(v, surface, w, beta, dispersion_u, rng);
    const SurfaceEvent<N> e = surface_event(v, *hit, surface, wo, medium, w);
    if (!is_specular(e.bsdf)) l += beta * direct_light(v, *hit, e, wo, w, rng, rays, true, true);
    const auto pdf = continue_path(scene, *hit, e, wo, TransportMode::radiance, depth, beta, medium, ray, rng);
    if (!pdf) break;
    prev_pdf = *pdf;
    prev_point = hit->point;
  }
  return l;
}

}  // namespace

void render_path(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                 SampleRange range, const RenderControl& control, RenderStats& stats) {
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    render_camera_paths<N>(scene, settings, film, region, range, control, stats, path<N>);
  });
}

}  // namespace bouguer
