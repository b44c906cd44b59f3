#include "bouguer/render/spectral_scene.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "bouguer/materials/bsdf.h"
#include "bouguer/spectra/cie.h"

namespace bouguer {

namespace {
bool is_dispersive(const IorModel& ior) {
  const double n0 = ior_at(ior, kLambdaMinNm);
  for (double nm = kLambdaMinNm + 1.0; nm <= kLambdaMaxNm; nm += 1.0)
    if (std::abs(ior_at(ior, nm) - n0) > 1e-7) return true;
  return false;
}

template <typename F>
SpectralTables::Table tabulate(F f) {
  SpectralTables::Table t;
  for (int i = 0; i < kCmfCount; ++i) t.v.push_back(static_cast<float>(f(kLambdaMinNm + i)));
  return t;
}

SpectralTables::Table tabulate_spectrum(const Spectrum& s) {
  return tabulate([&](double nm) { return eval(s, nm); });
}
}  // namespace

float SpectralTables::Table::at(double nm) const {
  const double x = std::clamp(nm - kLambdaMinNm, 0.0, kLambdaMaxNm - kLambdaMinNm);
  const auto lo = std::min(static_cast<std::size_t>(x), v.size() - 2);
  const auto t = static_cast<float>(x - static_cast<double>(lo));
  return v[lo] + t * (v[lo + 1] - v[lo]);
}

SpectralTables make_spectral_tables(const RenderScene& scene) {
  SpectralTables t;
  for (const MediumDesc& m : scene.media) {
    t.sigma_a.push_back(tabulate_spectrum(m.sigma_a_per_m));
    t.ior.push_back(tabulate([&](double nm) { return ior_at(m.ior, nm); }));
    t.absorbing.push_back(m.absorbing);
    t.dispersive.push_back(is_dispersive(m.ior));
    t.ior_reference.push_back(ior_at(m.ior, kReferenceWavelengthNm));
  }
  for (const EmissionDesc& e : scene.emissions) t.emission.push_back(tabulate_spectrum(e.radiance));
  for (const DeltaLightDesc& l : scene.delta_lights) t.delta_intensity.push_back(tabulate_spectrum(l.intensity));
  for (const MaterialDesc& d : scene.materials) {
    const auto* diffuse = std::get_if<DiffuseDesc>(&d);
    const auto* conductor = std::get_if<ConductorDesc>(&d);
    t.conductor.push_back(conductor != nullptr);
    t.reflectance.push_back(tabulate_spectrum(diffuse ? diffuse->reflectance : Spectrum(ConstantSpectrum{0.0})));
    t.n.push_back(tabulate_spectrum(conductor ? conductor->n : Spectrum(ConstantSpectrum{1.0})));
    t.k.push_back(tabulate_spectrum(conductor ? conductor->k : Spectrum(ConstantSpectrum{0.0})));
    t.alpha.push_back(conductor ? conductor->roughness : 0.0);
  }
  t.background = tabulate_spectrum(scene.background.radiance);
  if (scene.environment) t.environment = &*scene.environment;
  return t;
}

template <std::size_t N>
void fill_spectral_scene(const SpectralTables& t, const std::array<double, N>& nm, SpectralScene<N>& out) {
  auto at = [&](const SpectralTables::Table& table) {
    SampledSpectrum<N> s;
    for (std::size_t i = 0; i < N; ++i) s[i] = table.at(nm[i]);
    return s;
  };
  auto fill = [&](std::vector<SampledSpectrum<N>>& dst, const std::vector<SpectralTables::Table>& src) {
    dst.resize(src.size());
    for (std::size_t i = 0; i < src.size(); ++i) dst[i] = at(src[i]);
  };
  out.basis.mode = SpectralMode::hero;
  out.basis.wavelength_nm = nm;
  fill(out.sigma_a_per_m, t.sigma_a);
  fill(out.ior_at, t.ior);
  fill(out.emission, t.emission);
  fill(out.delta_intensity, t.delta_intensity);
  out.absorbing = t.absorbing;
  out.dispersive = t.dispersive;
  out.ior = t.ior_reference;
  out.materials.resize(t.reflectance.size());
  for (std::size_t i = 0; i < out.materials.size(); ++i)
    out.materials[i] = {t.conductor[i], at(t.reflectance[i]), at(t.n[i]), at(t.k[i]), t.alpha[i]};
  out.background = at(t.background);
  out.environment = t.environment;
  out.env_nm = nm;
  for (std::size_t i = 0; i < N; ++i) out.env_white[i] = static_cast<float>(d65_unit_luminance(nm[i]));
}

template <std::size_t N>
SpectralScene<N> make_spectral_scene(const RenderScene& scene, const SpectralBasis<N>& basis) {
  SpectralScene<N> s;
  s.basis = basis;
  for (const MediumDesc& m : scene.media) {
    s.sigma_a_per_m.push_back(basis.at_wavelengths(m.sigma_a_per_m));
    if (basis.mode == SpectralMode::full) s.sigma_sub.push_back(basis.at_sub_bins(m.sigma_a_per_m));
    s.absorbing.push_back(m.absorbing);
    s.ior.push_back(ior_at(m.ior, kReferenceWavelengthNm));
    SampledSpectrum<N> n;
    for (std::size_t i = 0; i < N; ++i) n[i] = static_cast<float>(ior_at(m.ior, basis.wavelength_nm[i]));
    s.ior_at.push_back(n);
    s.dispersive.push_back(is_dispersive(m.ior));
  }
  for (const EmissionDesc& e : scene.emissions) s.emission.push_back(basis.emission(e.radiance));
  for (const DeltaLightDesc& l : scene.delta_lights) s.delta_intensity.push_back(basis.emission(l.intensity));
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
  if (scene.environment) {
    s.environment = &*scene.environment;
    s.env_nm = basis.wavelength_nm;
    // Full: D65's mean over each bin (the sigmoid factor is smooth, taken at the bin centre).
    if (basis.mode != SpectralMode::rgb3) s.env_white = basis.emission(tabulate_visible(d65_unit_luminance));
  }
  return s;
}

template <std::size_t N>
SampledSpectrum<N> conductor_fresnel(double cos_theta_i, double eta_i, const SampledMaterial<N>& m) {
  SampledSpectrum<N> f;
  for (std::size_t i = 0; i < N; ++i)
    f[i] = static_cast<float>(fresnel_conductor(cos_theta_i, eta_i, {double(m.n[i]), double(m.k[i])}));
  return f;
}

double spot_falloff(double cos_theta, double cone_deg, double falloff_deg) {
  const double cos_end = std::cos(cone_deg * std::numbers::pi / 180.0);
  const double cos_start = std::cos(falloff_deg * std::numbers::pi / 180.0);
  if (cos_theta <= cos_end) return 0.0;
  const double t = cos_start > cos_end ? std::clamp((cos_theta - cos_end) / (cos_start - cos_end), 0.0, 1.0) : 1.0;
  return t * t * (3.0 - 2.0 * t);
}

std::optional<DeltaLightSample> sample_delta_light(const DeltaLightDesc& light, const Vec3& point) {
  if (light.type == DeltaLightType::distant)
    return DeltaLightSample{-light.direction, std::numeric_limits<double>::infinity(), 1.0};
  const Vec3 to = light.position_m - point;
  const double d2 = dot(to, to);
  if (d2 == 0.0) return std::nullopt;
  const Vec3 wi = to / std::sqrt(d2);
  const double falloff =
      light.type == DeltaLightType::spot ? spot_falloff(dot(-wi, light.direction), light.cone_deg, light.falloff_deg) : 1.0;
  if (falloff == 0.0) return std::nullopt;
  return DeltaLightSample{wi, std::sqrt(d2), falloff / d2};
}

template <std::size_t N>
SampledSpectrum<N> delta_light_incident(const SpectralScene<N>& s, std::size_t i, const DeltaLightSample& light,
                                        int medium) {
  if (!std::isinf(light.distance_m))
    return s.delta_intensity[i] * s.transmittance(medium, light.distance_m) * static_cast<float>(light.factor);
  if (s.absorbing[medium]) return {};
  return s.delta_intensity[i] * static_cast<float>(light.factor);
}

bool unoccluded(const RenderScene& scene, const Hit& hit, const Vec3& wi, double distance_m, std::uint64_t& rays) {
  const Vec3 origin = offset_ray_origin(hit, wi);
  ++rays;
  // Stop just short of the light, so its own surface never blocks it.
  const double t_max = std::isinf(distance_m) ? distance_m : distance_m * (1.0 - 1e-4);
  return !scene.rays.intersect({origin, wi, t_max});
}

template <std::size_t N>
SampledSpectrum<N> eval_opaque(const SampledMaterial<N>& m, const Frame& frame, const Vec3& wo, const Vec3& wi,
                               double eta, double& pdf) {
  const Vec3 lo = frame.to_local(wo), li = frame.to_local(wi);
  if (!m.conductor) {
    pdf = DiffuseBsdf{}.pdf(lo, li);
    return m.reflectance * static_cast<float>(DiffuseBsdf{}.eval(lo, li));
  }
  const ConductorBsdf bsdf{{m.alpha}};
  pdf = bsdf.pdf(lo, li);
  return conductor_fresnel(std::min(1.0, dot(wi, normalize(wi + wo))), eta, m) * static_cast<float>(bsdf.eval(lo, li));
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
template SampledSpectrum<kFullBins> delta_light_incident(const SpectralScene<kFullBins>&, std::size_t, const DeltaLightSample&, int);
template SampledSpectrum<kFullBins> eval_opaque(const SampledMaterial<kFullBins>&, const Frame&, const Vec3&, const Vec3&, double,
                                        double&);
template SampledSpectrum<3> conductor_fresnel(double, double, const SampledMaterial<3>&);
template SampledSpectrum<3> delta_light_incident(const SpectralScene<3>&, std::size_t, const DeltaLightSample&, int);
template SampledSpectrum<3> eval_opaque(const SampledMaterial<3>&, const Frame&, const Vec3&, const Vec3&, double,
                                        double&);
template struct SpectralScene<kHeroCount>;
template void fill_spectral_scene(const SpectralTables&, const std::array<double, kHeroCount>&,
                                  SpectralScene<kHeroCount>&);
template SampledSpectrum<kHeroCount> conductor_fresnel(double, double, const SampledMaterial<kHeroCount>&);
template SampledSpectrum<kHeroCount> delta_light_incident(const SpectralScene<kHeroCount>&, std::size_t, const DeltaLightSample&, int);
template SampledSpectrum<kHeroCount> eval_opaque(const SampledMaterial<kHeroCount>&, const Frame&, const Vec3&, const Vec3&, double,
                                        double&);

}  // namespace bouguer
