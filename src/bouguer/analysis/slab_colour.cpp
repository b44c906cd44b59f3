#include "bouguer/analysis/slab_colour.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {
namespace {

constexpr std::array<double, 3> kRgb3Nm = {700.0, 546.1, 435.8};

SlabColour colour_of_xyz(const Vec3& xyz) {
  const Vec3 rgb = xyz_to_linear_rgb(kRec709, xyz);
  return {xyz, rgb, srgb_hex(rgb)};
}

SlabColour colour_of_rgb(const Vec3& rgb) { return {linear_rgb_to_xyz(kRec709, rgb), rgb, srgb_hex(rgb)}; }

// The τ that gives slab transmittance t: R² t τ² + (1 − R)² τ − t = 0.
double tau_of_slab(double t, double r) {
  const double a = (1.0 - r) * (1.0 - r);
  const double t_max = a / (1.0 - r * r);  // τ = 1
  t = std::clamp(t, 1e-9, t_max);
  if (r == 0.0) return t;
  return (-a + std::sqrt(a * a + 4.0 * r * r * t * t)) / (2.0 * r * r * t);
}

}  // namespace

std::vector<double> default_thickness_series(const Spectrum& sigma) {
  double mean = 0.0;
  for (int nm = 400; nm <= 700; ++nm) mean += eval(sigma, nm) / 301.0;
  const double d = mean > 0.0 ? 1.0 / mean : 1.0;
  std::vector<double> out;
  for (const double f : {0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0}) {
    const double x = d * f, step = std::pow(10.0, std::floor(std::log10(x)) - 1.0);
    out.push_back(std::round(x / step) * step);
  }
  return out;
}

std::string format_thickness(double m, bool ascii_only) {
  if (m >= 1.0) return fmt::format("{:g} m", m);
  if (m >= 0.01) return fmt::format("{:g} cm", m * 100.0);
  if (m >= 1e-3) return fmt::format("{:g} mm", m * 1e3);
  return fmt::format("{:g} {}", m * 1e6, ascii_only ? "um" : "µm");
}

double slab_transmittance(double sigma_a_per_m, double thickness_m, double r) {
  const double tau = std::exp(-sigma_a_per_m * thickness_m);
  return (1.0 - r) * (1.0 - r) * tau / (1.0 - r * r * tau * tau);
}

ThicknessAnalysis analyse_thicknesses(const Spectrum& sigma_a_per_m, double ior,
                                      const std::vector<double>& thicknesses_m, const Spectrum& illuminant,
                                      double reference_thickness_m, std::vector<double> probe_nm) {
  ThicknessAnalysis a;
  a.probe_nm = std::move(probe_nm);
  a.reference_thickness_m = reference_thickness_m;
  a.ior = ior;
  a.reflectance = (ior - 1.0) * (ior - 1.0) / ((ior + 1.0) * (ior + 1.0));
  const Spectrum light = normalised_to_luminance(illuminant, 1.0);
  const Vec3 white_xyz = spectrum_to_xyz(light);
  a.illuminant_linear_srgb = xyz_to_linear_rgb(kRec709, white_xyz);

  // The slab's spectral colour at 1 nm.
  auto spectral = [&](double d) {
    return colour_of_xyz(spectrum_to_xyz(tabulate_visible([&](double nm) {
      return eval(light, nm) * slab_transmittance(eval(sigma_a_per_m, nm), d, a.reflectance);
    })));
  };
  auto per_channel = [&](const Vec3& sigma, double d) {
    const Vec3& w = a.illuminant_linear_srgb;
    return colour_of_rgb({w.x * slab_transmittance(sigma.x, d, a.reflectance),
                          w.y * slab_transmittance(sigma.y, d, a.reflectance),
                          w.z * slab_transmittance(sigma.z, d, a.reflectance)});
  };
  a.rgb3_sigma_a_per_m = {eval(sigma_a_per_m, kRgb3Nm[0]), eval(sigma_a_per_m, kRgb3Nm[1]),
                          eval(sigma_a_per_m, kRgb3Nm[2])};
  // The fitted renderer: per channel, the σ_a whose slab reproduces the spectral colour at d_ref.
  const SlabColour at_reference = spectral(reference_thickness_m);
  double fitted[3];
  for (int c = 0; c < 3; ++c) {
    const double t = at_reference.linear_srgb[c] / a.illuminant_linear_srgb[c];
    fitted[c] = -std::log(tau_of_slab(t, a.reflectance)) / reference_thickness_m;
  }
  a.fitted_sigma_a_per_m = {fitted[0], fitted[1], fitted[2]};

  for (const double d : thicknesses_m) {
    ThicknessRow row;
    row.thickness_m = d;
    for (const double nm : a.probe_nm) row.internal_transmittance.push_back(std::exp(-eval(sigma_a_per_m, nm) * d));
    row.spectral = spectral(d);
    row.rgb3 = per_channel(a.rgb3_sigma_a_per_m, d);
    row.fitted = per_channel(a.fitted_sigma_a_per_m, d);
    const Lab lab = xyz_to_lab(row.spectral.xyz, white_xyz);
    row.delta_e_rgb3 = ciede2000(lab, xyz_to_lab(row.rgb3.xyz, white_xyz));
    row.delta_e_fitted = ciede2000(lab, xyz_to_lab(row.fitted.xyz, white_xyz));
    a.rows.push_back(std::move(row));
  }
  return a;
}

}  // namespace bouguer
