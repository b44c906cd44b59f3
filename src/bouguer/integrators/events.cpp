#include "bouguer/integrators/events.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bouguer/scene/environment.h"

namespace bouguer {

double power_heuristic(double pdf_a, double pdf_b) {
  const double a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0.0 ? a / (a + b) : 0.0;
}

double area_light_pdf(const RenderScene& scene, const Hit& hit, const Vec3& from, const Vec3& wi) {
  const Surface& s = scene.surfaces[hit.geometry];
  const auto index = static_cast<std::size_t>(s.first_light) + hit.primitive;
  return scene.area_lights.pmf[index] * pdf_li(scene.lights[index], from, wi, hit.point);
}

double environment_pdf(const RenderScene& scene, const Vec3& d) {
  return scene.environment ? scene.environment->pdf(d) : 0.0;
}

bool unoccluded(const RenderScene& scene, const Hit& hit, const Vec3& wi, double distance_m, std::uint64_t& rays) {
  const Vec3 origin = offset_ray_origin(hit, wi);
  ++rays;
  // Stop just short of the target, so its own surface never blocks it.
  const double t_max = std::isinf(distance_m) ? distance_m : distance_m * (1.0 - 1e-4);
  return !scene.rays.intersect({origin, wi, t_max});
}

template <std::size_t N>
SampledSpectrum<N> direct_light(const SceneView<N>& v, const Hit& hit, const SurfaceEvent<N>& e, const Vec3& wo,
                                const SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays, bool mis,
                                bool environment) {
  const RenderScene& s = v.scene;
  const Vec3 wo_local = e.frame.to_local(wo);
  // f·|cos θi| towards wi and the BSDF's density for it, or nothing when f is zero.
  auto bsdf_towards = [&](const Vec3& wi, double& bsdf_pdf) {
    const Vec3 wi_local = e.frame.to_local(wi);
    bsdf_pdf = pdf(e.bsdf, wo_local, wi_local);
    return eval(e.bsdf, wo_local, wi_local, TransportMode::radiance);
  };
  SampledSpectrum<N> sum;
  const double u_light = rng.next_double(), u1 = rng.next_double(), u2 = rng.next_double();
  if (const auto chosen = s.area_lights.sample(u_light)) {
    const auto& [index, p_choice] = *chosen;
    if (const auto li = sample_li(s.lights[static_cast<std::size_t>(index)], hit.point, u1, u2)) {
      double bsdf_pdf = 0.0;
      const SampledSpectrum<N> f = bsdf_towards(li->wi, bsdf_pdf);
      if (!f.is_zero() && unoccluded(s, hit, li->wi, li->distance_m, rays)) {
        const double light_pdf = p_choice * li->pdf;
        const double weight = (mis ? power_heuristic(light_pdf, bsdf_pdf) : 1.0) * li->factor / light_pdf;
        const Ray segment{hit.point, li->wi};
        sum += f * v.tables.at(li->spectrum, w) * travel(v, e.medium_towards(li->wi), segment, li->distance_m, w) *
               static_cast<float>(weight);
      }
    }
  }
  for (const int index : s.delta_lights) {
    const auto li = sample_li(s.lights[static_cast<std::size_t>(index)], hit.point, 0.0, 0.0);
    if (!li) continue;
    double bsdf_pdf = 0.0;
    const Ray segment{hit.point, li->wi};
    const SampledSpectrum<N> incident = v.tables.at(li->spectrum, w) *
                                        travel(v, e.medium_towards(li->wi), segment, li->distance_m, w) *
                                        static_cast<float>(li->factor);
    if (incident.is_zero()) continue;
    const SampledSpectrum<N> f = bsdf_towards(li->wi, bsdf_pdf);
    if (f.is_zero() || !unoccluded(s, hit, li->wi, li->distance_m, rays)) continue;
    sum += f * incident;
  }
  if (environment && s.environment_light >= 0) {
    const double ue1 = rng.next_double(), ue2 = rng.next_double();
    const auto li = sample_li(s.lights[static_cast<std::size_t>(s.environment_light)], hit.point, ue1, ue2);
    if (li && !absorbs(s, e.medium_towards(li->wi))) {
      double bsdf_pdf = 0.0;
      const SampledSpectrum<N> f = bsdf_towards(li->wi, bsdf_pdf);
      if (!f.is_zero() && unoccluded(s, hit, li->wi, li->distance_m, rays)) {
        const double weight = (mis ? power_heuristic(li->pdf, bsdf_pdf) : 1.0) / li->pdf;
        sum += f * v.tables.environment(*s.environment, li->texel, w) * static_cast<float>(weight);
      }
    }
  }
  return sum;
}

template <std::size_t N>
bool keep_one_wavelength(const SceneView<N>& v, const Surface& surface, SampledWavelengths<N>& w,
                         SampledSpectrum<N>& beta, double u, Rng& rng) {
  if (N == 1 || surface.kind != SurfaceKind::interface || w.secondary_terminated()) return false;
  const auto& media = v.scene.media;
  if (!media[static_cast<std::size_t>(surface.medium_front)].dispersive &&
      !media[static_cast<std::size_t>(surface.medium_behind)].dispersive)
    return false;
  const int j = std::min(static_cast<int>(u * N), static_cast<int>(N) - 1);
  w.terminate_secondary(j, v.tables.kept_wavelength_nm(w, j, rng.next_double()));
  const float kept = beta[static_cast<std::size_t>(j)] * static_cast<float>(N);
  beta = SampledSpectrum<N>{};
  beta[static_cast<std::size_t>(j)] = kept;
  return true;
}

namespace {

// Adds `value` (already multiplied by everything but the medium and the camera's factor) at the
// camera's film position when nothing blocks the way.
template <std::size_t N>
void splat_towards(const SceneView<N>& v, const Hit& hit, const CameraConnection& c, int medium,
                   const SampledSpectrum<N>& value, const SampledWavelengths<N>& w, FilmBuffer& film,
                   std::uint64_t& rays) {
  if (value.is_zero() || !unoccluded(v.scene, hit, c.wi, c.distance_m, rays)) return;
  const SampledSpectrum<N> l =
      value * travel(v, medium, Ray{hit.point, c.wi}, c.distance_m, w) * static_cast<float>(c.factor);
  if (film.has_spectra()) {
    film.add_splat(c.film_x, c.film_y, v.tables.to_linear_rgb(l, w), std::span<const float>(l.v.data(), N));
  } else {
    film.add_splat(c.film_x, c.film_y, v.tables.to_linear_rgb(l, w));
  }
}

}  // namespace

template <std::size_t N>
void splat_surface_to_camera(const SceneView<N>& v, const Hit& hit, const SurfaceEvent<N>& e, const Vec3& wo,
                             const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w, FilmBuffer& film,
                             std::uint64_t& rays) {
  const auto c = v.camera.connect(hit.point);
  if (!c) return;
  const SampledSpectrum<N> f =
      eval(e.bsdf, e.frame.to_local(wo), e.frame.to_local(c->wi), TransportMode::importance);
  splat_towards(v, hit, *c, e.medium_towards(c->wi), beta * f, w, film, rays);
}

template <std::size_t N>
void splat_light_to_camera(const SceneView<N>& v, const Hit& at, const AreaLight& light, int medium,
                           const SampledSpectrum<N>& beta, const SampledWavelengths<N>& w, FilmBuffer& film,
                           std::uint64_t& rays) {
  const auto c = v.camera.connect(at.point);
  if (!c) return;
  const double factor = emitted_factor(light, c->wi) * std::abs(dot(c->wi, light.normal));
  splat_towards(v, at, *c, medium, beta * static_cast<float>(factor), w, film, rays);
}

#define BOUGUER_EVENTS_INSTANTIATE(N)                                                                                 \
  template SampledSpectrum<N> direct_light(const SceneView<N>&, const Hit&, const SurfaceEvent<N>&, const Vec3&,      \
                                           const SampledWavelengths<N>&, Rng&, std::uint64_t&, bool, bool);           \
  template bool keep_one_wavelength(const SceneView<N>&, const Surface&, SampledWavelengths<N>&, SampledSpectrum<N>&, \
                                    double, Rng&);                                                                    \
  template void splat_surface_to_camera(const SceneView<N>&, const Hit&, const SurfaceEvent<N>&, const Vec3&,         \
                                        const SampledSpectrum<N>&, const SampledWavelengths<N>&, FilmBuffer&,         \
                                        std::uint64_t&);                                                              \
  template void splat_light_to_camera(const SceneView<N>&, const Hit&, const AreaLight&, int,                         \
                                      const SampledSpectrum<N>&, const SampledWavelengths<N>&, FilmBuffer&,           \
                                      std::uint64_t&);
BOUGUER_EVENTS_INSTANTIATE(kFullBins)
BOUGUER_EVENTS_INSTANTIATE(3)
BOUGUER_EVENTS_INSTANTIATE(kHeroCount)
#undef BOUGUER_EVENTS_INSTANTIATE

}  // namespace bouguer
