#include "bouguer/render/path.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "bouguer/materials/bsdf.h"
#include "bouguer/materials/fresnel.h"

namespace bouguer {
namespace {

double power_heuristic(double pdf_a, double pdf_b) {
  const double a = pdf_a * pdf_a, b = pdf_b * pdf_b;
  return a + b > 0.0 ? a / (a + b) : 0.0;
}

constexpr int kRouletteDepth = 4;

}  // namespace

template <std::size_t N>
SampledSpectrum<N> PathIntegrator<N>::radiance(Ray ray, int medium, double wavelength_u, Rng& rng,
                                               std::uint64_t& rays) const {
  SampledSpectrum<N> l, beta = SampledSpectrum<N>::constant(1.0f);
  double prev_pdf = 0.0;  // 0: the last event was specular (or the camera)
  Vec3 prev_point = ray.origin;
  int single = -1;  // the one wavelength left after a dispersive interface
  for (int depth = 0;; ++depth) {
    ++rays;
    const auto hit = scene_.rays.intersect(ray);
    if (!hit) {
      if (medium < 0 || !s_.absorbing[medium]) {
        // An environment map is also reached by next-event estimation: weight against it.
        const double w = (prev_pdf == 0.0 || !s_.environment)
                             ? 1.0
                             : power_heuristic(prev_pdf, s_.environment->pdf(ray.direction));
        l += beta * s_.background_radiance(ray.direction) * static_cast<float>(w);
      }
      break;
    }
    const Surface& surface = scene_.surfaces[hit->geometry];
    const bool from_front = dot(ray.direction, hit->normal) < 0.0;
    if (surface.kind == SurfaceKind::interface) medium = from_front ? surface.medium_front : surface.medium_behind;
    beta *= s_.transmittance(medium, hit->t);
    if (surface.kind == SurfaceKind::emitter) {
      if (from_front || scene_.emissions[surface.emission].two_sided) {
        const double w = prev_pdf == 0.0 ? 1.0
                                         : power_heuristic(prev_pdf, emitter_pdf_solid_angle(scene_, prev_point,
                                                                                             hit->point, hit->normal));
        l += beta * s_.emission[surface.emission] *
             static_cast<float>(w * emitted_factor(scene_.emissions[surface.emission], -ray.direction));
      }
      break;
    }
    if (depth >= scene_.render.max_depth) break;
    if (surface.kind == SurfaceKind::interface && single < 0 && N > 1 &&
        (s_.dispersive[surface.medium_front] || s_.dispersive[surface.medium_behind])) {
      single = std::min(static_cast<int>(wavelength_u * N), static_cast<int>(N) - 1);
      const auto& bin = s_.basis.bin_nm[single];
      single_nm_ = bin.empty() ? s_.basis.wavelength_nm[single]
                               : bin.front() - 0.5 + rng.next_double() * static_cast<double>(bin.size());
      const float kept = beta[single] * static_cast<float>(N);
      beta = SampledSpectrum<N>{};
      beta[single] = kept;
    }
    const auto next = scatter(ray, *hit, surface, medium, single, rng, l, beta, rays);
    if (!next) break;
    beta *= next->weight;
    medium = next->medium;
    prev_pdf = next->pdf;
    prev_point = hit->point;
    if (depth >= kRouletteDepth && !s_.absorbing[medium]) {
      const float survive = std::max(0.05f, std::min(1.0f, beta.max_value()));
      if (rng.next_double() >= survive) break;
      beta /= survive;
    }
    if (beta.is_zero()) break;
    ray = {offset_ray_origin(*hit, next->wi), next->wi};
  }
  return l;
}

// One scattering event: adds next-event estimation to `light` (weighted by beta) and returns the
// sampled continuation, or nullopt when the path ends.
template <std::size_t N>
auto PathIntegrator<N>::scatter(const Ray& ray, const Hit& hit, const Surface& surface, int medium, int single,
                                Rng& rng,
                                SampledSpectrum<N>& light, const SampledSpectrum<N>& beta, std::uint64_t& rays) const
    -> std::optional<Scatter> {
  const Vec3 wo = -ray.direction;
  if (surface.kind == SurfaceKind::interface && surface.roughness == 0.0) {
    const bool from_front = dot(wo, hit.normal) > 0.0;
    const int other = from_front ? surface.medium_behind : surface.medium_front;
    const Vec3 n = from_front ? hit.normal : -hit.normal;
    const double eta_i = eta(medium, single), eta_t = eta(other, single);
    const double f = fresnel_dielectric(std::min(1.0, dot(wo, n)), eta_i, eta_t);
    if (rng.next_double() < f) return Scatter{reflect(wo, n), SampledSpectrum<N>::constant(1.0f), 0.0, medium};
    const auto t = refract(wo, n, eta_i, eta_t);
    if (!t) return std::nullopt;  // cannot happen: F = 1 under total internal reflection
    return Scatter{*t, SampledSpectrum<N>::constant(1.0f), 0.0, other};
  }
  if (surface.kind == SurfaceKind::opaque) {
    const SampledMaterial<N>& m = s_.materials[surface.material];
    const Vec3 n = dot(wo, hit.normal) > 0.0 ? hit.normal : -hit.normal;  // two-sided
    if (m.conductor && m.alpha == 0.0) {
      const auto f = conductor_fresnel(std::min(1.0, dot(wo, n)), eta(medium, single), m);
      return Scatter{reflect(wo, n), f, 0.0, medium};
    }
    const Frame frame(n);
    light += beta * next_event(hit, wo, frame, medium, medium, surface, single, rng, rays);
    const Vec3 wo_local = frame.to_local(wo);
    const double u1 = rng.next_double(), u2 = rng.next_double();
    const auto s = m.conductor ? ConductorBsdf{{m.alpha}}.sample(wo_local, u1, u2) : DiffuseBsdf{}.sample(wo_local, u1, u2);
    if (!s) return std::nullopt;
    const Vec3 wi = frame.to_world(s->wi);
    SampledSpectrum<N> weight = m.reflectance * static_cast<float>(s->weight);
    if (m.conductor)
      weight = conductor_fresnel(std::min(1.0, dot(wi, normalize(wi + wo))), eta(medium, single), m) *
               static_cast<float>(s->weight);
    return Scatter{wi, weight, s->pdf, medium};
  }
  // A rough dielectric interface: the local +z is the surface normal, the "front" medium's side.
  const Frame frame(hit.normal);
  light += beta * next_event(hit, wo, frame, surface.medium_behind, surface.medium_front, surface, single, rng, rays);
  const RoughDielectricBsdf bsdf{{surface.roughness},
                                 eta(surface.medium_front, single),
                                 eta(surface.medium_behind, single),
                                 &scene_.dielectric_albedo[surface.albedo]};
  const double uc = rng.next_double(), u1 = rng.next_double(), u2 = rng.next_double();
  const auto s = bsdf.sample(frame.to_local(wo), uc, u1, u2);
  if (!s) return std::nullopt;
  const int next_medium = s->wi.z > 0.0 ? surface.medium_front : surface.medium_behind;
  return Scatter{frame.to_world(s->wi), SampledSpectrum<N>::constant(static_cast<float>(s->weight)), s->pdf,
                 next_medium};
}

// f·|cos θi| of a non-specular surface for world directions, and the BSDF's own sampling density.
template <std::size_t N>
SampledSpectrum<N> PathIntegrator<N>::eval_bsdf(const Surface& surface, const Frame& frame, const Vec3& wo,
                                                const Vec3& wi, int medium, int single, double& pdf) const {
  const Vec3 lo = frame.to_local(wo), li = frame.to_local(wi);
  if (surface.kind == SurfaceKind::interface) {
    const RoughDielectricBsdf bsdf{{surface.roughness},
                                   eta(surface.medium_front, single),
                                   eta(surface.medium_behind, single),
                                   &scene_.dielectric_albedo[surface.albedo]};
    pdf = bsdf.pdf(lo, li);
    return SampledSpectrum<N>::constant(static_cast<float>(bsdf.eval(lo, li)));
  }
  return eval_opaque(s_.materials[surface.material], frame, wo, wi, eta(medium, single), pdf);
}

template <std::size_t N>
SampledSpectrum<N> PathIntegrator<N>::next_event(const Hit& hit, const Vec3& wo, const Frame& frame,
                                                 int medium_behind, int medium_front, const Surface& surface,
                                                 int single, Rng& rng, std::uint64_t& rays) const {
  SampledSpectrum<N> sum = area_light(hit, wo, frame, medium_behind, medium_front, surface, single, rng, rays) +
                           delta_lights(hit, wo, frame, medium_behind, medium_front, surface, single, rays);
  if (s_.environment) sum += environment_light(hit, wo, frame, medium_behind, medium_front, surface, single, rng, rays);
  return sum;
}

// Direct light from one direction of the environment map, weighted against BSDF sampling.
template <std::size_t N>
SampledSpectrum<N> PathIntegrator<N>::environment_light(const Hit& hit, const Vec3& wo, const Frame& frame,
                                                        int medium_behind, int medium_front, const Surface& surface,
                                                        int single, Rng& rng, std::uint64_t& rays) const {
  const double u1 = rng.next_double(), u2 = rng.next_double();
  const auto light = s_.environment->sample(u1, u2);
  if (!light) return {};
  const int medium = dot(light->wi, frame.n) > 0.0 ? medium_front : medium_behind;
  if (medium >= 0 && s_.absorbing[medium]) return {};  // an infinite absorber lets nothing through
  double bsdf_pdf = 0.0;
  const SampledSpectrum<N> f = eval_bsdf(surface, frame, wo, light->wi, medium, single, bsdf_pdf);
  if (f.is_zero() || !unoccluded(scene_, hit, light->wi, std::numeric_limits<double>::infinity(), rays)) return {};
  const auto w = static_cast<float>(power_heuristic(light->pdf, bsdf_pdf) / light->pdf);
  return f * s_.environment_radiance(light->texel) * w;
}

template <std::size_t N>
SampledSpectrum<N> PathIntegrator<N>::delta_lights(const Hit& hit, const Vec3& wo, const Frame& frame,
                                                   int medium_behind, int medium_front, const Surface& surface,
                                                   int single, std::uint64_t& rays) const {
  SampledSpectrum<N> sum;
  for (std::size_t i = 0; i < scene_.delta_lights.size(); ++i) {
    const auto light = sample_delta_light(scene_.delta_lights[i], hit.point);
    if (!light) continue;
    const int medium = dot(light->wi, frame.n) > 0.0 ? medium_front : medium_behind;
    const SampledSpectrum<N> incident = delta_light_incident(s_, i, *light, medium);
    if (incident.is_zero()) continue;
    double pdf = 0.0;
    const SampledSpectrum<N> f = eval_bsdf(surface, frame, wo, light->wi, medium, single, pdf);
    if (f.is_zero() || !unoccluded(scene_, hit, light->wi, light->distance_m, rays)) continue;
    sum += f * incident;
  }
  return sum;
}

// Direct light from one emitter point, weighted against BSDF sampling by the power heuristic.
template <std::size_t N>
SampledSpectrum<N> PathIntegrator<N>::area_light(const Hit& hit, const Vec3& wo, const Frame& frame,
                                                 int medium_behind, int medium_front, const Surface& surface,
                                                 int single, Rng& rng, std::uint64_t& rays) const {
  const auto light = sample_emitter_point(scene_, rng);
  if (!light) return {};
  const Vec3 to_light = light->point - hit.point;
  const double dist = length(to_light);
  if (dist == 0.0) return {};
  const Vec3 wi = to_light / dist;
  const int emission = scene_.surfaces[light->geometry].emission;
  if (dot(wi, light->normal) >= 0.0 && !scene_.emissions[emission].two_sided) return {};
  const int medium = dot(wi, frame.n) > 0.0 ? medium_front : medium_behind;
  double bsdf_pdf = 0.0;
  const SampledSpectrum<N> f = eval_bsdf(surface, frame, wo, wi, medium, single, bsdf_pdf);
  if (f.is_zero() || !unoccluded(scene_, hit, wi, dist, rays)) return {};
  const double light_pdf = emitter_pdf_solid_angle(scene_, hit.point, light->point, light->normal);
  const auto w = static_cast<float>(power_heuristic(light_pdf, bsdf_pdf) / light_pdf);
  return f * s_.emission[emission] * s_.transmittance(medium, dist) *
         (w * static_cast<float>(emitted_factor(scene_.emissions[emission], -wi)));
}

template class PathIntegrator<kFullBins>;
template class PathIntegrator<3>;
template class PathIntegrator<kHeroCount>;

}  // namespace bouguer
