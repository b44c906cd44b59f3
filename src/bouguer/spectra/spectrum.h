#pragma once
// Spectral functions of wavelength (nm). A closed set of plain structs behind one std::variant;
// `eval` gives the value at a wavelength. Values carry whatever unit their owner states
// (relative radiance, transmittance, sigma_a per metre, ...).
#include <string_view>
#include <variant>
#include <optional>
#include <string>
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

// f(nm) at every whole nanometre of [kLambdaMinNm, kLambdaMaxNm], as a table.
template <typename F>
TabulatedSpectrum tabulate_visible(F&& f) {
  TabulatedSpectrum t;
  for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm; nm += 1.0) {
    t.wavelength_nm.push_back(nm);
    t.value.push_back(f(nm));
  }
  return t;
}

// Planck's law: spectral radiance in W·m⁻²·sr⁻¹·nm⁻¹ at temperature_k, times scale.
struct BlackbodySpectrum {
  double temperature_k = 6500.0;
  double scale = 1.0;
};

// S(c0 λ² + c1 λ + c2) with the sigmoid S(x) = 1/2 + x / (2 √(1 + x²)), λ in nm: a smooth
// spectrum with values in [0, 1], the form RGB reflectances are lifted to (rgb_to_spectrum.h).
struct SigmoidPolynomial {
  double c0 = 0.0, c1 = 0.0, c2 = 0.0;
  double operator()(double wavelength_nm) const;
};

// scale · S(poly(λ)) · D65(λ), D65 normalised to luminance 1: an RGB radiance lifted to a spectrum
// (rgb_to_spectrum.h).
struct RgbIlluminantSpectrum {
  double scale = 0.0;
  SigmoidPolynomial poly;
};

using Spectrum = std::variant<ConstantSpectrum, TabulatedSpectrum, BlackbodySpectrum, SigmoidPolynomial,
                              RgbIlluminantSpectrum>;

// D65 normalised to luminance Y = 1, at 1 nm (the white of RgbIlluminantSpectrum).
double d65_unit_luminance(double wavelength_nm);

// Validates the invariants above (and finite values); `what` names the data in the error message.
TabulatedSpectrum make_tabulated(std::vector<double> wavelength_nm, std::vector<double> value,
                                 std::string_view what);

// For user tables: one that lies wholly outside kLambdaMinNm..kLambdaMaxNm would be held at one
// flat value over all of it, which is never what was meant; an Error naming `what` instead.
void require_visible_overlap(const TabulatedSpectrum& s, std::string_view what);

double planck_radiance_per_nm(double wavelength_nm, double temperature_k);

double eval(const TabulatedSpectrum& s, double wavelength_nm);
double eval(const Spectrum& s, double wavelength_nm);

// The same spectrum multiplied by a constant factor.
Spectrum scaled(const Spectrum& s, double factor);

// Smallest and largest value over the domain [kLambdaMinNm, kLambdaMaxNm].
double min_value(const Spectrum& s);
double max_value(const Spectrum& s);

// Why `s` is not finite or not within ±limit ("WHAT reaches 3e+20, beyond the limit of 1e+12"),
// or nothing: for products (scale × spectrum, concentration × absorptivity) checked once formed.
std::optional<std::string> beyond_limit(const Spectrum& s, double limit, std::string_view what);

}  // namespace bouguer
