#include "bouguer/render/whitted.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bouguer/materials/fresnel.h"

namespace bouguer {

template <std::size_t N>
SpectralScene<N> make_spectral_scene(const RenderScene& scene, const SpectralBasis<N>& basis) {
  SpectralScene<N> s;
  s.basis = basis;
  for (const MediumDesc& m : scene.media) {
    s.sigma_a_per_m.push_back(basis.at_wavelengths(m.sigma_a_per_m));
    s.absorbing.push_back(m.absorbing);
    s.ior.push_back(ior_at(m.ior, kReferenceWavelengthNm));
  }
  for (const EmissionDesc& e : scene.emissions) s.emission.push_back(basis.emission(e.radiance));
  for (const DiffuseDesc& d : scene.materials) {
    // Reflectance is a ratio, not a light: in rgb3 it is sampled at the three wavelengths.
    s.reflectance.push_back(basis.mode == SpectralMode::rgb3 ? basis.at_wavelengths(d.reflectance)
                                                             : basis.emission(d.reflectance));
  }
  s.background = basis.emission(scene.background.radiance);
  return s;
}

template <std::size_t N>
SampledSpectrum<N> WhittedIntegrator<N>::segment_transmittance(int medium, double length_m) const {
  if (medium < 0 || !s_.absorbing[medium]) return SampledSpectrum<N>::constant(1.0f);
  return beer_lambert_transmittance(s_.sigma_a_per_m[medium], static_cast<float>(length_m));
}

template <std::size_t N>
SampledSpectrum<N> WhittedIntegrator<N>::radiance(const Ray& ray, int medium, int depth, float weight, Rng& rng,
                                                  std::uint64_t& rays) const {
  ++rays;
  const auto hit = scene_.rays.intersect(ray);
  if (!hit) {
    if (medium >= 0 && s_.absorbing[medium]) return {};  // an infinite path through an absorber
    return s_.background;
  }
  const Surface& surface = scene_.surfaces[hit->geometry];
  const bool from_front = dot(ray.direction, hit->normal) < 0.0;
  switch (surface.kind) {
    case SurfaceKind::emitter: {
      const bool lit = from_front || scene_.emissions[surface.emission].two_sided;
      return lit ? segment_transmittance(medium, hit->t) * s_.emission[surface.emission] : SampledSpectrum<N>{};
    }
    case SurfaceKind::diffuse:
      return segment_transmittance(medium, hit->t) * direct_light(*hit, -ray.direction, medium, rng, rays);
    case SurfaceKind::interface:
      break;
  }
  // The medium travelled is the one on the side of the surface the ray arrives from.
  const int here = from_front ? surface.medium_front : surface.medium_behind;
  const SampledSpectrum<N> tr = segment_transmittance(here, hit->t);
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

// One emitter point per call, chosen by area; the camera's samples per pixel average them.
template <std::size_t N>
SampledSpectrum<N> WhittedIntegrator<N>::direct_light(const Hit& hit, const Vec3& wo, int medium, Rng& rng,
                                                      std::uint64_t& rays) const {
  if (scene_.lights.empty()) return {};
  const double u = rng.next_double();
  const auto index = static_cast<std::size_t>(
      std::lower_bound(scene_.light_cdf.begin(), scene_.light_cdf.end(), u) - scene_.light_cdf.begin());
  const EmissiveTriangle& light = scene_.lights[std::min(index, scene_.lights.size() - 1)];
  const Mesh& m = scene_.rays.mesh(light.geometry);
  const auto& tri = m.triangles[light.primitive];
  double b1 = rng.next_double(), b2 = rng.next_double();
  if (b1 + b2 > 1.0) b1 = 1.0 - b1, b2 = 1.0 - b2;
  const Vec3 p = m.positions[tri[0]] * (1.0 - b1 - b2) + m.positions[tri[1]] * b1 + m.positions[tri[2]] * b2;
  const Vec3 ln = normalize(cross(m.positions[tri[1]] - m.positions[tri[0]], m.positions[tri[2]] - m.positions[tri[0]]));

  const Vec3 n = dot(wo, hit.normal) > 0.0 ? hit.normal : -hit.normal;  // diffuse surfaces are two-sided
  const Vec3 to_light = p - hit.point;
  const double dist = length(to_light);
  const Vec3 wi = to_light / dist;
  const double cos_surface = dot(wi, n), cos_light = -dot(wi, ln);
  const int emission = scene_.surfaces[light.geometry].emission;
  const bool lit = cos_light > 0.0 || scene_.emissions[emission].two_sided;
  if (cos_surface <= 0.0 || !lit || dist == 0.0) return {};
  const Vec3 origin = offset_ray_origin(hit, wi);
  ++rays;
  const auto blocker = scene_.rays.intersect({origin, wi, length(p - origin) * (1.0 - 1e-4)});
  if (blocker) return {};
  const Surface& surface = scene_.surfaces[hit.geometry];
  const double geometry = cos_surface * std::abs(cos_light) / (dist * dist) * scene_.light_area_m2;
  const auto g = static_cast<float>(geometry / std::numbers::pi);  // Lambert: f = R / π, pdf = 1 / area
  return s_.reflectance[surface.material] * s_.emission[emission] * segment_transmittance(medium, dist) * g;
}

template struct SpectralScene<kFullBins>;
template struct SpectralScene<3>;
template SpectralScene<kFullBins> make_spectral_scene(const RenderScene&, const SpectralBasis<kFullBins>&);
template SpectralScene<3> make_spectral_scene(const RenderScene&, const SpectralBasis<3>&);
template class WhittedIntegrator<kFullBins>;
template class WhittedIntegrator<3>;

}  // namespace bouguer
