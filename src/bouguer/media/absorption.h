#pragma once
// Every way users state absorption, converted to the one quantity the renderer uses: the
// natural-log attenuation coefficient σ_a per metre, T(l) = exp(−σ_a·l). Concentration scales σ_a
// linearly (Beer's law).
#include <optional>
#include <string_view>

#include "bouguer/spectra/spectrum.h"

namespace bouguer {

enum class AbsorptionUnit {
  attenuation_per_m,       // σ_a itself (natural log, 1/m)
  absorbance_per_cm,       // decadic absorbance of 1 cm: T = 10^(−A·l/cm)
  internal_transmittance,  // T at a stated thickness (needs thickness_m)
  molar_absorptivity,      // ε in L·mol⁻¹·cm⁻¹, decadic (needs concentration in mol/L)
  extinction_coefficient,  // k, imaginary part of the refractive index: σ_a = 4πk/λ
};

std::optional<AbsorptionUnit> absorption_unit_from_name(std::string_view name);
std::string_view absorption_unit_name(AbsorptionUnit unit);

double absorbance_per_cm_to_sigma_a_per_m(double absorbance_per_cm);
double internal_transmittance_to_sigma_a_per_m(double transmittance, double thickness_m);
double molar_absorptivity_to_sigma_a_per_m(double epsilon_l_per_mol_cm, double concentration_mol_per_l);
double extinction_coefficient_to_sigma_a_per_m(double k, double wavelength_nm);

// Converts a tabulated spectrum of `unit` values into σ_a per metre, times `concentration`
// (for molar_absorptivity the concentration in mol/L, otherwise a relative factor).
// `what` names the data for errors (e.g. "scene.json: media.probe.absorption").
TabulatedSpectrum to_sigma_a_per_m(const TabulatedSpectrum& values, AbsorptionUnit unit, double concentration,
                                   std::optional<double> thickness_m, std::string_view what);

}  // namespace bouguer
