#include "bouguer/render/whitted.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bouguer/core/frame.h"
#include "bouguer/materials/bsdf.h"
#include "bouguer/materials/fresnel.h"

namespace bouguer {

template <std::size_t N>
SampledSpectrum<N> WhittedIntegrator<N>::radiance(const Ray& ray, int medium, int depth, float weight, Rng& rng,
                                                  std::uint64_t& rays) const {
  ++rays;
  const auto hit = scene_.rays.intersect(ray);
  if (!hit) {
    if (medium >= 0 && s_.absorbing[medium]) return {};  // an infinite path through an absorber
    return s_.background_radiance(ray.direction);
  }
  const Surface& surface = scene_.surfaces[hit->geometry];
  const bool from_front = dot(ray.direction, hit->normal) < 0.0;
  switch (surface.kind) {
    case SurfaceKind::emitter: {
      const bool lit = from_front || scene_.emissions[surface.emission].two_sided;
      if (!lit) return {};
      return s_.transmittance(medium, hit->t) * s_.emission[surface.emission] *
             static_cast<float>(emitted_factor(scene_.emissions[surface.emission], -ray.direction));
    }
    case SurfaceKind::opaque:
      return opaque(ray, *hit, surface, medium, depth, weight, rng, rays);
    case SurfaceKind::interface:
      break;
  }
  // The medium travelled is the one on the side of the surface the ray arrives from.
  const int here = from_front ? surface.medium_front : surface.medium_behind;
  const SampledSpectrum<N> tr = s_.transmittance(here, hit->t);
  const float w = weight * tr.max_value();
  if (w < kMinPathWeight || depth >= scene_.render.max_depth) return {};
  return tr * interface(ray, *hit, surface, depth, w, rng, rays);
}

template <std::size_t N>
SampledSpectrum<N> WhittedIntegrator<N>::interface(const Ray& ray, const Hit& hit, const Surface& surface, int depth,
                                                   float weight, Rng& rng, std::uint64_t& rays) const {
  const bool from_front = dot(ray.direction, hit.normal) < 0.0;
  const int medium_i = from_front ? surface.medium_front : surface.medium_behind;
  const int medium_t = from_front ? surface.medium_behind : surface.medium_front;
  const double eta_i = s_.ior[medium_i], eta_t = s_.ior[medium_t];
  const Vec3 n = from_front ? hit.normal : -hit.normal;  // on the incident side
  const Vec3 wi = -ray.direction;
  const double cos_i = std::min(1.0, dot(wi, n));
  const auto f = static_cast<float>(fresnel_dielectric(cos_i, eta_i, eta_t));

  SampledSpectrum<N> l;
  if (weight * f >= kMinPathWeight) {
    const Vec3 r = reflect(wi, n);
    l += f * radiance({offset_ray_origin(hit, r), r}, medium_i, depth + 1, weight * f, rng, rays);
  }
  if (f < 1.0f && weight * (1.0f - f) >= kMinPathWeight) {
    if (const auto t = refract(wi, n, eta_i, eta_t))
      l += (1.0f - f) * radiance({offset_ray_origin(hit, *t), *t}, medium_t, depth + 1, weight * (1.0f - f), rng, rays);
  }
  return l;
}

template <std::size_t N>
SampledSpectrum<N> WhittedIntegrator<N>::opaque(const Ray& ray, const Hit& hit, const Surface& surface, int medium,
                                                int depth, float weight, Rng& rng, std::uint64_t& rays) const {
  const SampledMaterial<N>& m = s_.materials[surface.material];
  const SampledSpectrum<N> tr = s_.transmittance(medium, hit.t);
  if (!m.conductor || m.alpha > 0.0) return tr * direct_light(hit, -ray.direction, medium, m, rng, rays);
  // A smooth conductor: a mirror with its spectral Fresnel reflectance.
  const Vec3 n = dot(ray.direction, hit.normal) < 0.0 ? hit.normal : -hit.normal;
  const Vec3 wo = -ray.direction;
  const SampledSpectrum<N> f = conductor_fresnel(std::min(1.0, dot(wo, n)), s_.ior[medium], m);
  const float w = weight * (tr * f).max_value();
  if (w < kMinPathWeight || depth >= scene_.render.max_depth) return {};
  const Vec3 r = reflect(wo, n);
  return tr * f * radiance({offset_ray_origin(hit, r), r}, medium, depth + 1, w, rng, rays);
}

// One emitter point per call, chosen by area (the camera's samples per pixel average them), and
// every point, spot and distant light.
template <std::size_t N>
SampledSpectrum<N> WhittedIntegrator<N>::direct_light(const Hit& hit, const Vec3& wo, int medium,
                                                      const SampledMaterial<N>& material, Rng& rng,
                                                      std::uint64_t& rays) const {
  const Frame frame(dot(wo, hit.normal) > 0.0 ? hit.normal : -hit.normal);  // opaque surfaces are two-sided
  // f·|cos θi| toward wi, when wi leaves the lit side and nothing blocks it over `distance_m`.
  auto shade = [&](const Vec3& wi, double distance_m) -> SampledSpectrum<N> {
    if (dot(wi, frame.n) <= 0.0 || !unoccluded(scene_, hit, wi, distance_m, rays)) return {};
    double pdf = 0.0;
    return eval_opaque(material, frame, wo, wi, s_.ior[medium], pdf);
  };
  SampledSpectrum<N> sum;
  for (std::size_t i = 0; i < scene_.delta_lights.size(); ++i) {
    const auto light = sample_delta_light(scene_.delta_lights[i], hit.point);
    if (!light) continue;
    const SampledSpectrum<N> incident = delta_light_incident(s_, i, *light, medium);
    if (!incident.is_zero()) sum += shade(light->wi, light->distance_m) * incident;
  }
  const auto light = sample_emitter_point(scene_, rng);
  if (!light) return sum;
  const Vec3 to_light = light->point - hit.point;
  const double dist = length(to_light);
  if (dist == 0.0) return sum;
  const Vec3 wi = to_light / dist;
  const int emission = scene_.surfaces[light->geometry].emission;
  const bool lit = dot(wi, light->normal) < 0.0 || scene_.emissions[emission].two_sided;
  if (!lit) return sum;
  const double pdf = emitter_pdf_solid_angle(scene_, hit.point, light->point, light->normal);
  return sum + shade(wi, dist) * s_.emission[emission] * s_.transmittance(medium, dist) *
                   static_cast<float>(emitted_factor(scene_.emissions[emission], -wi) / pdf);
}

template class WhittedIntegrator<kFullBins>;
template class WhittedIntegrator<3>;
template class WhittedIntegrator<kHeroCount>;

}  // namespace bouguer
