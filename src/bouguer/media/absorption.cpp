#include "bouguer/media/absorption.h"

#include <array>
#include <cmath>
#include <numbers>

#include "bouguer/core/error.h"

namespace bouguer {
namespace {
constexpr std::array<std::pair<AbsorptionUnit, std::string_view>, 5> kUnitNames = {{
    {AbsorptionUnit::attenuation_per_m, "attenuation_per_m"},
    {AbsorptionUnit::absorbance_per_cm, "absorbance_per_cm"},
    {AbsorptionUnit::internal_transmittance, "internal_transmittance"},
    {AbsorptionUnit::molar_absorptivity, "molar_absorptivity"},
    {AbsorptionUnit::extinction_coefficient, "extinction_coefficient"},
}};
constexpr double kCmPerM = 100.0;
}  // namespace

std::optional<AbsorptionUnit> absorption_unit_from_name(std::string_view name) {
  for (const auto& [unit, n] : kUnitNames)
    if (n == name) return unit;
  return std::nullopt;
}

std::string_view absorption_unit_name(AbsorptionUnit unit) {
  for (const auto& [u, n] : kUnitNames)
    if (u == unit) return n;
  return "?";
}

double absorbance_per_cm_to_sigma_a_per_m(double absorbance_per_cm) {
  return absorbance_per_cm * std::numbers::ln10 * kCmPerM;
}

double internal_transmittance_to_sigma_a_per_m(double transmittance, double thickness_m) {
  return -std::log(transmittance) / thickness_m;
}

double molar_absorptivity_to_sigma_a_per_m(double epsilon_l_per_mol_cm, double concentration_mol_per_l) {
  return absorbance_per_cm_to_sigma_a_per_m(epsilon_l_per_mol_cm * concentration_mol_per_l);
}

double extinction_coefficient_to_sigma_a_per_m(double k, double wavelength_nm) {
  return 4.0 * std::numbers::pi * k / (wavelength_nm * 1e-9);
}

TabulatedSpectrum to_sigma_a_per_m(const TabulatedSpectrum& values, AbsorptionUnit unit, double concentration,
                                   std::optional<double> thickness_m, std::string_view what) {
  if (!(concentration >= 0.0) || !std::isfinite(concentration))
    fail("{}: concentration must be a finite number >= 0 (got {})", what, concentration);
  if (unit == AbsorptionUnit::internal_transmittance && !(thickness_m && *thickness_m > 0.0))
    fail("{}: unit 'internal_transmittance' needs a positive 'thickness'", what);
  if (unit != AbsorptionUnit::internal_transmittance && thickness_m)
    fail("{}: 'thickness' applies only to unit 'internal_transmittance'", what);
  TabulatedSpectrum sigma = values;
  for (std::size_t i = 0; i < values.value.size(); ++i) {
    const double v = values.value[i], nm = values.wavelength_nm[i];
    if (v < 0.0) fail("{}: value at {} nm is negative ({})", what, nm, v);
    double s = 0.0;
    switch (unit) {
      case AbsorptionUnit::attenuation_per_m: s = v; break;
      case AbsorptionUnit::absorbance_per_cm: s = absorbance_per_cm_to_sigma_a_per_m(v); break;
      case AbsorptionUnit::molar_absorptivity: s = molar_absorptivity_to_sigma_a_per_m(v, 1.0); break;
      case AbsorptionUnit::extinction_coefficient: s = extinction_coefficient_to_sigma_a_per_m(v, nm); break;
      case AbsorptionUnit::internal_transmittance:
        if (v <= 0.0 || v > 1.0)
          fail("{}: internal transmittance at {} nm must be in (0, 1] (got {})", what, nm, v);
        s = internal_transmittance_to_sigma_a_per_m(v, *thickness_m);
        break;
    }
    sigma.value[i] = s * concentration;
    if (!std::isfinite(sigma.value[i]))
      fail("{}: the value at {} nm gives σ_a = {} per metre, not a finite number", what, nm, sigma.value[i]);
  }
  return sigma;
}

}  // namespace bouguer
