#include "bouguer/render/spectral_scene.h"

#include <algorithm>
#include <cmath>

#include "bouguer/materials/bsdf.h"

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
  for (const MaterialDesc& d : scene.materials) {
    SampledMaterial<N> m;
    if (const auto* diffuse = std::get_if<DiffuseDesc>(&d)) {
      // Reflectance is a ratio, not a light: in rgb3 it is sampled at the three wavelengths.
      m.reflectance = basis.mode == SpectralMode::rgb3 ? basis.at_wavelengths(diffuse->reflectance)
                                                       : basis.emission(diffuse->reflectance);
    } else {
      const auto& c = std::get<ConductorDesc>(d);
      m.conductor = true;
      m.n = basis.at_wavelengths(c.n);
      m.k = basis.at_wavelengths(c.k);
      m.alpha = c.roughness;
    }
    s.materials.push_back(m);
  }
  s.background = basis.emission(scene.background.radiance);
  return s;
}

template <std::size_t N>
SampledSpectrum<N> conductor_fresnel(double cos_theta_i, double eta_i, const SampledMaterial<N>& m) {
  SampledSpectrum<N> f;
  for (std::size_t i = 0; i < N; ++i)
    f[i] = static_cast<float>(fresnel_conductor(cos_theta_i, eta_i, {double(m.n[i]), double(m.k[i])}));
  return f;
}

std::optional<LightSample> sample_emitter_point(const RenderScene& scene, Rng& rng) {
  if (scene.lights.empty()) return std::nullopt;
  const double u = rng.next_double();
  const auto index = static_cast<std::size_t>(
      std::lower_bound(scene.light_cdf.begin(), scene.light_cdf.end(), u) - scene.light_cdf.begin());
  const EmissiveTriangle& light = scene.lights[std::min(index, scene.lights.size() - 1)];
  const Mesh& m = scene.rays.mesh(light.geometry);
  const auto& tri = m.triangles[light.primitive];
  double b1 = rng.next_double(), b2 = rng.next_double();
  if (b1 + b2 > 1.0) b1 = 1.0 - b1, b2 = 1.0 - b2;
  const Vec3 &p0 = m.positions[tri[0]], &p1 = m.positions[tri[1]], &p2 = m.positions[tri[2]];
  return LightSample{p0 * (1.0 - b1 - b2) + p1 * b1 + p2 * b2, normalize(cross(p1 - p0, p2 - p0)), light.geometry};
}

double emitter_pdf_solid_angle(const RenderScene& scene, const Vec3& from, const Vec3& point, const Vec3& normal) {
  const Vec3 d = point - from;
  const double dist2 = dot(d, d);
  const double cos_light = std::abs(dot(normal, d)) / std::sqrt(dist2);
  if (cos_light == 0.0 || scene.light_area_m2 == 0.0) return 0.0;
  return dist2 / (cos_light * scene.light_area_m2);
}

template struct SpectralScene<kFullBins>;
template struct SpectralScene<3>;
template SpectralScene<kFullBins> make_spectral_scene(const RenderScene&, const SpectralBasis<kFullBins>&);
template SpectralScene<3> make_spectral_scene(const RenderScene&, const SpectralBasis<3>&);
template SampledSpectrum<kFullBins> conductor_fresnel(double, double, const SampledMaterial<kFullBins>&);
template SampledSpectrum<3> conductor_fresnel(double, double, const SampledMaterial<3>&);

}  // namespace bouguer
