#include "bouguer/scene/pbr_material.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "bouguer/spectra/rgb_to_spectrum.h"

namespace bouguer {
namespace {

bool emits(const PbrMaterialInput& m) { return std::max({m.emissive.x, m.emissive.y, m.emissive.z}) * m.emissive_strength > 0.0; }

// A conductor whose reflectance at normal incidence is the base colour: n = 1 and
// k(λ) = 2·sqrt(F0/(1 − F0)), F0 the smooth lift of the colour.
ConductorInput metal(const PbrMaterialInput& g) {
  const SigmoidPolynomial lifted = rgb_to_reflectance(g.base_color);
  TableInput k;
  for (double nm = 360.0; nm <= 830.0; nm += 5.0) {
    const double r = std::min(lifted(nm), 0.999);
    k.wavelength_nm.push_back(nm);
    k.value.push_back(2.0 * std::sqrt(r / (1.0 - r)));
  }
  return {1.0, k, g.roughness * g.roughness, std::nullopt};
}

MetallicRoughnessInput metallic_roughness(const PbrMaterialInput& g) {
  MetallicRoughnessInput in;
  if (const auto& t = g.base_color_texture) in.base_colour = *t;
  else in.base_colour = RgbInput{g.base_color};
  in.metalness = g.metallic;
  in.roughness = g.roughness;
  in.metallic_roughness_texture = g.metallic_roughness_texture;
  return in;
}

// Each value within what the mapping models (a front end that clamps does so before).
void check(const PbrMaterialInput& m, const Source& where) {
  auto unit_interval = [&](double v, const char* key) {
    if (!(v >= 0.0 && v <= 1.0)) (where / key).fail("must be between 0 and 1 (got {})", v);
  };
  for (std::size_t i = 0; i < 3; ++i) {
    const double c = std::array{m.base_color.x, m.base_color.y, m.base_color.z}[i];
    if (!(c >= 0.0 && c <= 1.0)) (where / "base_color")[i].fail("a reflectance must lie between 0 and 1 (got {})", c);
    const double e = std::array{m.emissive.x, m.emissive.y, m.emissive.z}[i];
    if (!(e >= 0.0 && std::isfinite(e))) (where / "emission")[i].fail("must not be negative (got {})", e);
    const double a = std::array{m.attenuation_color.x, m.attenuation_color.y, m.attenuation_color.z}[i];
    if (!(a > 0.0 && a <= 1.0))
      (where / "attenuation_color")[i].fail("must lie in (0, 1] (got {}; 0 would absorb everything)", a);
  }
  unit_interval(m.metallic, "metallic");
  unit_interval(m.roughness, "roughness");
  unit_interval(m.transmission, "transmission");
  if (!(m.emissive_strength >= 0.0 && std::isfinite(m.emissive_strength)))
    (where / "emission_strength").fail("must not be negative (got {})", m.emissive_strength);
  if (!(m.ior >= 1.0 && m.ior < 5.0)) (where / "ior").fail("must be between 1 and 5 (got {})", m.ior);
  if (!(m.dispersion >= 0.0 && std::isfinite(m.dispersion)))
    (where / "dispersion").fail("must not be negative (got {})", m.dispersion);
  if (m.attenuation_distance_m && !(*m.attenuation_distance_m > 0.0 && std::isfinite(*m.attenuation_distance_m)))
    (where / "attenuation_distance").fail("must be a positive length (got {} m)", *m.attenuation_distance_m);
}

// A transmissive solid's medium: σ_a = −ln(c)/d lifted as the internal transmittance c over d.
MediumInput volume_medium(const PbrMaterialInput& g) {
  MediumInput m;
  // V_d = 20/D; with an index of 1 there is nothing to disperse.
  if (g.dispersion > 0.0 && g.ior > 1.0) m.ior = AbbeInput{g.ior, 20.0 / g.dispersion};
  else m.ior = g.ior;
  if (g.attenuation_distance_m)
    m.absorption.push_back({AbsorptionValuesInput{attenuation_sigma_a(g.attenuation_color, *g.attenuation_distance_m),
                                                  "attenuation_per_m", std::nullopt},
                            std::nullopt});
  return m;
}

}  // namespace

PbrRole pbr_role(const PbrMaterialInput& g, const Source& where) {
  check(g, where);
  PbrRole role;
  if (emits(g)) {  // the surface's own reflection is dropped: an object has one role
    if (const auto& t = g.emissive_texture)  // texel × strength
      role.emission = resolve_emission(EmissionInput{*t, g.emissive_strength}, where / "emission_texture");
    else
      role.emission = resolve_emission(EmissionInput{RgbInput{g.emissive}, g.emissive_strength}, where / "emission");
  } else if (g.transmission > 0.0 && g.thin_walled) {  // a sheet tinted by the base colour, smooth
    ThinDielectricInput sheet{g.ior, std::nullopt};
    if (const auto& t = g.base_color_texture) sheet.tint = *t;
    else sheet.tint = RgbInput{g.base_color};
    role.material = resolve_surface_material(sheet, where / "transmission");
  } else if (g.transmission > 0.0) {
    role.volume = volume_medium(g);
    role.interface_roughness = g.roughness * g.roughness;
  } else if (g.metallic_roughness_texture || (g.metallic > 0.0 && g.metallic < 1.0)) {
    role.material = resolve_surface_material(metallic_roughness(g), where);
  } else if (g.metallic >= 0.5) {
    role.material = resolve_surface_material(metal(g), where);
  } else if (const auto& t = g.base_color_texture) {
    role.material = resolve_surface_material(DiffuseInput{*t}, where / "base_color_texture");
  } else {
    role.material = resolve_surface_material(DiffuseInput{RgbInput{g.base_color}}, where / "base_color");
  }
  return role;
}

// The Gaussians are 2 nm wide; tabulated at 1 nm and at the lines.
TableInput attenuation_sigma_a(const Vec3& c, double d) {
  constexpr std::array<double, 3> lines_nm{700.0, 546.1, 435.8};
  constexpr double width_nm = 2.0;
  const SigmoidPolynomial lifted = rgb_to_reflectance(c);
  const std::array<double, 3> want{c.x, c.y, c.z};
  auto bump = [&](std::size_t i, double nm) {
    const double x = (nm - lines_nm[i]) / width_nm;
    return std::exp(-0.5 * x * x);
  };
  // Solve Σ_j a_j bump_j(λ_i) = residual_i (optical depth over d); the matrix is the identity
  // to 1e-300 at these spacings, so one pass suffices, and a second makes it exact to rounding.
  std::array<double, 3> residual{}, a{};
  for (std::size_t i = 0; i < 3; ++i) residual[i] = std::log(lifted(lines_nm[i])) - std::log(want[i]);
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t i = 0; i < 3; ++i) {
      double others = 0.0;
      for (std::size_t j = 0; j < 3; ++j)
        if (j != i) others += a[j] * bump(j, lines_nm[i]);
      a[i] = residual[i] - others;
    }
  TableInput t;
  for (int nm = 360; nm <= 830; ++nm) {
    if (nm == 436) t.wavelength_nm.push_back(435.8);
    if (nm == 547) t.wavelength_nm.push_back(546.1);
    t.wavelength_nm.push_back(nm);
  }
  for (double nm : t.wavelength_nm) {
    double depth = -std::log(lifted(nm));
    for (std::size_t i = 0; i < 3; ++i) depth += a[i] * bump(i, nm);
    t.value.push_back(std::max(0.0, depth) / d);
  }
  return t;
}

}  // namespace bouguer
