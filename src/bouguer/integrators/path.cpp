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
// Scattering media: delta tracking of the scattering with spectral MIS (media/scattering.h), the
// absorption in closed form; next-event estimation at every medium vertex through the phase
// function; Russian roulette by throughput there too. Scattering events do not count against
// max_depth; a path stops after kMaxScatterings of them (integrators/events.h). Index-matched
// interfaces are crossed without a vertex.
#include "bouguer/integrators/integrators.h"

namespace bouguer {
namespace {

template <std::size_t N>
SampledSpectrum<N> path(const SceneView<N>& v, Ray ray, SampledWavelengths<N>& w, double dispersion_u, Rng& rng,
                        std::uint64_t& rays) {
  const RenderScene& scene = v.scene;
  draw_hero(scene, w, rng);
  SampledSpectrum<N> l, beta = SampledSpectrum<N>::constant(1.0f);
  SpectralMis<N> mis;     // r_u over the path; r_l since its last vertex (media/scattering.h)
  double prev_pdf = 0.0;  // 0: the last vertex was specular (or the camera)
  Vec3 vertex = ray.origin;  // the last vertex: where next-event estimation would have started
  Vec3 start = ray.origin;   // where the current segment started (a vertex or a medium boundary)
  int medium = scene.world_medium;
  int scatterings = 0, crossings = 0;
  for (int depth = 0;; ++depth) {
    ++rays;
    const auto hit = scene.rays.intersect(ray);
    if (!hit) {  // an environment map is also reached by next-event estimation: weighted against it
      const double weight = prev_pdf == 0.0 || !scene.environment
                                ? 1.0
                                : spectral_power_heuristic(scene, prev_pdf, mis.r_u, environment_pdf(scene, ray.direction), mis.r_l);
      l += beta * escaped(v, medium, ray.direction, w) * static_cast<float>(weight / mean_ratio(scene, mis.r_u));
      break;
    }
    const Surface& surface = scene.surfaces[hit->geometry];
    medium = medium_arrived_through(surface, ray, *hit, medium);
    if (const auto x = through_medium(v, medium, start, ray.direction, *hit, w, rng, beta, mis)) {
      // A vertex in the medium: direct light through the phase function, then a new direction
      // drawn from it. Scattering events do not count against max_depth.
      if (beta.is_zero() || ++scatterings > kMaxScatterings) break;
      const ScatteringMedium& sm = *scattering_medium(scene, medium);
      l += beta * direct_light_in_medium(v, *x, ray.direction, sm.phase, medium, w, mis.r_u, rng, rays);
      const auto pdf = continue_from_medium(scene, sm, *x, depth + scatterings, medium, beta, mis, ray, rng);
      if (!pdf) break;
      mis.r_l = mis.r_u;
      prev_pdf = *pdf;
      vertex = start = *x;
      --depth;
      continue;
    }
    if (beta.is_zero()) break;
    const Vec3 wo = -ray.direction;
    if (surface.kind == SurfaceKind::emitter) {
      const double weight =
          prev_pdf == 0.0
              ? 1.0
              : spectral_power_heuristic(scene, prev_pdf, mis.r_u, area_light_pdf(scene, *hit, vertex, ray.direction), mis.r_l);
      l += beta * emitted(v, *hit, wo, w) * static_cast<float>(weight / mean_ratio(scene, mis.r_u));
      break;
    }
    if (surface.index_matched) {
      if (!cross_index_matched(surface, *hit, crossings, medium, start, ray)) break;
      --depth;
      continue;
    }
    if (depth >= v.max_depth) break;
    keep_one_wavelength(v, surface, w, beta, dispersion_u, rng);
    const SurfaceEvent<N> e = surface_event(v, *hit, surface, wo, medium, w);
    if (!is_specular(e.bsdf)) l += beta * direct_light(v, *hit, e, wo, w, mis.r_u, rng, rays, true, true);
    const auto pdf = continue_path(scene, *hit, e, wo, TransportMode::radiance, depth + scatterings, beta, medium, ray,
                                   rng, mean_ratio(scene, mis.r_u));
    if (!pdf) break;
    prev_pdf = *pdf;
    if (scene.scatters) mis.r_l = mis.r_u;  // (all ones otherwise)
    vertex = start = hit->point;
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
