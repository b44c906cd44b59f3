// Light tracing: paths start at the lights (one drawn by power, then a point and a direction from
// its own emission sampling) and carry importance-mode BSDF weights; every vertex on a
// non-specular surface is connected to the camera by a shadow ray and splatted at its film
// position, and a lamp's own point is connected too (the lamp seen directly). It finds caustics
// on diffuse receivers (light focused by glass), which the path tracer reaches only by chance.
// What it cannot see: anything the camera sees through a purely specular chain (mirrors, glass)
// and the background or environment seen directly, since a connection to a pinhole ends on a
// non-specular surface or a lamp. The same Russian roulette and depth limit as the path tracer.
// In scattering media: the same delta tracking as the path tracer, and every medium vertex is
// connected to the camera through the phase function.
// Light path i of pixel slot p is seeded by (seed, p, i): region and sample-range splits give the
// same splats, whose fixed-point sums (render/film.h) do not depend on the order of arrival.
#include "bouguer/integrators/integrators.h"

namespace bouguer {
namespace {

// The medium a light emits into: the one in front of an emitter surface, the world's otherwise.
int emission_medium(const RenderScene& scene, const Light& light) {
  if (const auto* a = std::get_if<AreaLight>(&light)) return scene.surfaces[a->geometry].medium_front;
  return scene.world_medium;
}

template <std::size_t N>
void trace_light_path(const SceneView<N>& v, SampledWavelengths<N>& w, double dispersion_u, Rng& rng,
                      FilmBuffer& film, std::uint64_t& rays) {
  const RenderScene& scene = v.scene;
  const double u_light = rng.next_double(), u1 = rng.next_double(), u2 = rng.next_double(), u3 = rng.next_double(),
               u4 = rng.next_double();
  const auto chosen = scene.emitters.sample(u_light);
  if (!chosen) return;
  const Light& light = scene.lights[static_cast<std::size_t>(chosen->first)];
  const auto le = sample_le(light, scene.bounds, u1, u2, u3, u4);
  if (!le) return;
  draw_hero(scene, w, rng);
  const SampledSpectrum<N> radiance =
      le->texel >= 0 ? v.tables.environment(*scene.environment, le->texel, w) : v.tables.at(le->spectrum, w);
  int medium = emission_medium(scene, light);
  Ray ray = le->ray;
  const double cos_light = le->normal == Vec3{} ? 1.0 : std::abs(dot(le->normal, ray.direction));
  if (const auto* area = std::get_if<AreaLight>(&light)) {
    Hit at;
    at.point = ray.origin;
    at.normal = le->normal;
    at.geometry = area->geometry;
    at.primitive = area->primitive;
    splat_light_to_camera(v, at, *area, medium, radiance * static_cast<float>(1.0 / (chosen->second * le->pdf_pos)), w,
                          rng, film, rays);
    ray.origin = offset_ray_origin(at, ray.direction);
  }
  SampledSpectrum<N> beta =
      radiance * static_cast<float>(le->factor * cos_light / (chosen->second * le->pdf_pos * le->pdf_dir));
  SpectralMis<N> mis;        // only r_u: a light path's splats have no competing strategy
  Vec3 start = le->ray.origin;  // where the current segment started
  int scatterings = 0, crossings = 0;
  for (int depth = 0;; ++depth) {
    ++rays;
    const auto hit = scene.rays.intersect(ray);
    if (!hit) return;
    const Surface& surface = scene.surfaces[hit->geometry];
    medium = medium_arrived_through(surface, ray, *hit, medium);
    if (const auto x = through_medium(v, medium, start, ray.direction, *hit, w, rng, beta, mis)) {
      if (beta.is_zero() || ++scatterings > kMaxScatterings) return;
      const ScatteringMedium& sm = *scattering_medium(scene, medium);
      splat_medium_to_camera(v, *x, ray.direction, sm.phase, medium, beta, w, mis.r_u, rng, film, rays);
      if (!continue_from_medium(scene, sm, *x, depth + scatterings, medium, beta, mis, ray, rng)) return;
      start = *x;
      --depth;
      continue;
    }
    if (beta.is_zero()) return;
    if (surface.kind == SurfaceKind::emitter) return;  // lamps absorb what reaches them
    if (surface.index_matched) {  // crossed unchanged, as camera paths and connections do
      if (!cross_index_matched(surface, *hit, crossings, medium, start, ray)) return;
      --depth;
      continue;
    }
    if (depth >= v.max_depth) return;
    keep_one_wavelength(v, surface, w, beta, dispersion_u, rng);
    const Vec3 wo = -ray.direction;
    const SurfaceEvent<N> e = surface_event(v, *hit, surface, wo, medium, w);
    if (!is_specular(e.bsdf)) splat_surface_to_camera(v, *hit, e, wo, beta, w, mis.r_u, rng, film, rays);
    if (!continue_path(scene, *hit, e, wo, TransportMode::importance, depth + scatterings, beta, medium, ray, rng,
                       mean_ratio(scene, mis.r_u)))
      return;
    start = hit->point;
  }
}

}  // namespace

void render_light(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                  SampleRange range, const RenderControl& control, RenderStats& stats) {
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    const SpectralTables<N> tables(scene.spectra, settings.spectral);
    const Camera camera(scene.camera);
    const SceneView<N> view{scene, tables, camera, settings.max_depth};
    for_each_pixel_sample<N>(scene, tables, settings, film.width(), region, range, control, stats, 1,
                             [&](int, int, int, Rng& rng, SampledWavelengths<N>& w, double dispersion_u,
                                 std::uint64_t& rays) { trace_light_path(view, w, dispersion_u, rng, film, rays); });
  });
}

}  // namespace bouguer
