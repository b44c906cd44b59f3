#include "bouguer/spectra/spectrum.h"

#include <algorithm>
#include <cmath>

#include "bouguer/core/error.h"
#include "bouguer/spectra/cie.h"

namespace bouguer {

void require_visible_overlap(const TabulatedSpectrum& s, std::string_view what) {
  const double lo = s.wavelength_nm.front(), hi = s.wavelength_nm.back();
  if (hi < kLambdaMinNm || lo > kLambdaMaxNm)
    fail("{}: the table covers {:g}-{:g} nm, none of the range {:g}-{:g} nm that colour needs", what, lo, hi,
         kLambdaMinNm, kLambdaMaxNm);
}

TabulatedSpectrum make_tabulated(std::vector<double> wavelength_nm, std::vector<double> value,
                                 std::string_view what) {
  if (wavelength_nm.empty()) fail("{}: spectrum has no data points", what);
  if (wavelength_nm.size() != value.size())
    fail("{}: {} wavelengths but {} values", what, wavelength_nm.size(), value.size());
  for (std::size_t i = 0; i < wavelength_nm.size(); ++i) {
    if (!std::isfinite(wavelength_nm[i]) || wavelength_nm[i] <= 0.0)
      fail("{}: point {}: wavelength {} nm is not a positive number", what, i + 1, wavelength_nm[i]);
    if (!std::isfinite(value[i])) fail("{}: point {}: value is not a finite number", what, i + 1);
    if (i > 0 && wavelength_nm[i] <= wavelength_nm[i - 1])
      fail("{}: point {}: wavelength {} nm does not increase (previous {} nm)", what, i + 1, wavelength_nm[i],
           wavelength_nm[i - 1]);
  }
  return {std::move(wavelength_nm), std::move(value)};
}

double planck_radiance_per_nm(double wavelength_nm, double temperature_k) {
  constexpr double h = 6.62607015e-34;   // J·s
  constexpr double c = 299792458.0;      // m/s
  constexpr double k_b = 1.380649e-23;   // J/K
  const double lambda_m = wavelength_nm * 1e-9;
  const double per_m = 2.0 * h * c * c / (std::pow(lambda_m, 5) * std::expm1(h * c / (lambda_m * k_b * temperature_k)));
  return per_m * 1e-9;  // per metre of wavelength -> per nm
}

double eval(const TabulatedSpectrum& s, double wavelength_nm) {
  const auto& x = s.wavelength_nm;
  if (wavelength_nm <= x.front()) return s.value.front();
  if (wavelength_nm >= x.back()) return s.value.back();
  const auto hi = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), wavelength_nm) - x.begin());
  const std::size_t lo = hi - 1;
  const double t = (wavelength_nm - x[lo]) / (x[hi] - x[lo]);
  return s.value[lo] + t * (s.value[hi] - s.value[lo]);
}

double SigmoidPolynomial::operator()(double nm) const {
  const double x = (c0 * nm + c1) * nm + c2;
  if (std::isinf(x)) return x > 0.0 ? 1.0 : 0.0;
  return 0.5 + x / (2.0 * std::sqrt(1.0 + x * x));
}

double d65_unit_luminance(double wavelength_nm) {
  static const Spectrum d65 = named_illuminant("D65", 1.0);
  return eval(d65, wavelength_nm);
}

double eval(const Spectrum& s, double wavelength_nm) {
  struct Visitor {
    double nm;
    double operator()(const ConstantSpectrum& c) const { return c.value; }
    double operator()(const TabulatedSpectrum& t) const { return eval(t, nm); }
    double operator()(const BlackbodySpectrum& b) const {
      return b.scale * planck_radiance_per_nm(nm, b.temperature_k);
    }
    double operator()(const SigmoidPolynomial& p) const { return p(nm); }
    double operator()(const RgbIlluminantSpectrum& r) const { return r.scale * r.poly(nm) * d65_unit_luminance(nm); }
  };
  return std::visit(Visitor{wavelength_nm}, s);
}

Spectrum scaled(const Spectrum& s, double factor) {
  struct Visitor {
    double f;
    Spectrum operator()(const ConstantSpectrum& c) const { return ConstantSpectrum{c.value * f}; }
    Spectrum operator()(TabulatedSpectrum t) const {
      for (double& v : t.value) v *= f;
      return t;
    }
    Spectrum operator()(const BlackbodySpectrum& b) const { return BlackbodySpectrum{b.temperature_k, b.scale * f}; }
    Spectrum operator()(const SigmoidPolynomial& p) const {
      // A sigmoid times a factor is no longer a sigmoid: tabulate at 1 nm.
      return tabulate_visible([&](double nm) { return p(nm) * f; });
    }
    Spectrum operator()(const RgbIlluminantSpectrum& r) const { return RgbIlluminantSpectrum{r.scale * f, r.poly}; }
  };
  return std::visit(Visitor{factor}, s);
}

namespace {
// Extremes of a piecewise linear function lie at its knots or the domain ends; 1 nm steps cover
// every CIE-resolution knot and Planck's smooth curve.
template <typename Pick>
double extreme_over_domain(const Spectrum& s, Pick pick) {
  double best = eval(s, kLambdaMinNm);
  for (double nm = kLambdaMinNm + 1.0; nm <= kLambdaMaxNm; nm += 1.0) best = pick(best, eval(s, nm));
  if (const auto* t = std::get_if<TabulatedSpectrum>(&s)) {
    for (std::size_t i = 0; i < t->wavelength_nm.size(); ++i)
      if (t->wavelength_nm[i] >= kLambdaMinNm && t->wavelength_nm[i] <= kLambdaMaxNm) best = pick(best, t->value[i]);
  }
  return best;
}
}  // namespace

double min_value(const Spectrum& s) {
  return extreme_over_domain(s, [](double a, double b) { return std::min(a, b); });
}
double max_value(const Spectrum& s) {
  return extreme_over_domain(s, [](double a, double b) { return std::max(a, b); });
}

std::optional<std::string> beyond_limit(const Spectrum& s, double limit, std::string_view what) {
  const double peak = max_value(s), low = min_value(s);
  if (peak <= limit && low >= -limit) return std::nullopt;
  if (!std::isfinite(peak) || !std::isfinite(low))
    return fmt::format("{} is not finite (the product overflows)", what);
  return fmt::format("{} reaches {:g}, beyond the limit of {:g}", what, std::abs(peak) > std::abs(low) ? peak : low, limit);
}

}  // namespace bouguer
