#pragma once
// Refractive index models n(λ), wavelength in nm. A closed set behind std::variant.
#include <variant>
#include <vector>

#include "bouguer/spectra/spectrum.h"

namespace bouguer {

struct ConstantIor {
  double n = 1.0;
};

// n² = 1 + Σ B_i λ² / (λ² − C_i), λ in µm, C in µm².
struct SellmeierIor {
  std::vector<double> B;
  std::vector<double> C_um2;
};

// n = A + B / λ² + C / λ⁴, λ in µm.
struct CauchyIor {
  double A = 1.5;
  double B_um2 = 0.0;
  double C_um4 = 0.0;
};

struct TabulatedIor {
  TabulatedSpectrum n;
};

using IorModel = std::variant<ConstantIor, SellmeierIor, CauchyIor, TabulatedIor>;

double sellmeier_ior(const SellmeierIor& s, double wavelength_nm);
double cauchy_ior(const CauchyIor& c, double wavelength_nm);
double ior_at(const IorModel& model, double wavelength_nm);

// The sodium d line, where a dispersive medium's single index is taken when rays do not split by
// wavelength (the Whitted integrator; see docs/rendering.md).
inline constexpr double kReferenceWavelengthNm = 587.56;

}  // namespace bouguer
