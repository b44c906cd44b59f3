#pragma once
// Spectral functions of wavelength (nm). A closed set of plain structs behind one std::variant;
// `eval` gives the value at a wavelength. Values carry whatever unit their owner states
// (relative radiance, transmittance, sigma_a per metre, ...).
#include <string_view>
#include <variant>
#include <vector>

namespace bouguer {

// The wavelength domain every spectral computation in Bouguer covers (CIE CMF range).
inline constexpr double kLambdaMinNm = 360.0;
inline constexpr double kLambdaMaxNm = 830.0;

struct ConstantSpectrum {
  double value = 0.0;
};

// Piecewise linear through (wavelength_nm[i], value[i]); constant (clamped) outside the table.
// Invariant (checked by make_tabulated): same sizes, at least one point, wavelengths strictly increasing.
struct TabulatedSpectrum {
  std::vector<double> wavelength_nm;
  std::vector<double> value;
};

// Planck's law: spectral radiance in W·m⁻²·sr⁻¹·nm⁻¹ at temperature_k, times scale.
struct BlackbodySpectrum {
  double temperature_k = 6500.0;
  double scale = 1.0;
};

using Spectrum = std::variant<ConstantSpectrum, TabulatedSpectrum, BlackbodySpectrum>;

// Validates the invariants above (and finite values); `what` names the data in the error message.
TabulatedSpectrum make_tabulated(std::vector<double> wavelength_nm, std::vector<double> value,
                                 std::string_view what);

double planck_radiance_per_nm(double wavelength_nm, double temperature_k);

double eval(const TabulatedSpectrum& s, double wavelength_nm);
double eval(const Spectrum& s, double wavelength_nm);

// The same spectrum multiplied by a constant factor.
Spectrum scaled(const Spectrum& s, double factor);

// Smallest and largest value over the domain [kLambdaMinNm, kLambdaMaxNm].
double min_value(const Spectrum& s);
double max_value(const Spectrum& s);

}  // namespace bouguer
