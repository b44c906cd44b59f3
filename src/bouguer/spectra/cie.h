#pragma once
// CIE colorimetry: the standard observers, the named illuminants, and the one normalisation the
// whole renderer relies on:
//   XYZ = ∫ S(λ)·x̄(λ) dλ / ∫ ȳ(λ) dλ      (sums at 1 nm over 360–830 nm)
// so a spectrum that is 1 everywhere (illuminant E with scale 1) has Y = 1, and a named illuminant
// with scale s is scaled to luminance Y = s (luminance is defined with V(λ) = ȳ of CIE 1931, so this
// normalisation always uses the 1931 observer, whatever observer later looks at the light).
// Tables are compiled in from data/cie (see data/README.md for sources).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "bouguer/core/math.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

enum class Observer { cie1931_2deg, cie1964_10deg };

std::string_view observer_name(Observer o);

// Colour-matching functions at 1 nm, kLambdaMinNm..kLambdaMaxNm inclusive (471 values each).
struct ObserverTable {
  std::vector<double> xbar, ybar, zbar;
  double ybar_sum = 0.0;
};

const ObserverTable& observer_table(Observer o);

constexpr int kCmfCount = static_cast<int>(kLambdaMaxNm - kLambdaMinNm) + 1;

Vec3 spectrum_to_xyz(const Spectrum& s, Observer o = Observer::cie1931_2deg);

// Luminance Y (CIE 1931) of a spectrum under the normalisation above.
double luminance(const Spectrum& s);

// The spectrum scaled so that its luminance is `luminance_y`. A spectrum with zero luminance is an Error.
Spectrum normalised_to_luminance(const Spectrum& s, double luminance_y);

// Named illuminants: D65, D50, A, E, F2, F7, F11 (case-insensitive), and blackbody:<T> with T in
// kelvin (e.g. "blackbody:3200" or "blackbody:3200K"). The relative SPD as tabulated by the CIE;
// nullopt for an unknown name.
std::optional<Spectrum> named_illuminant_spd(std::string_view name);

// The named illuminant normalised to luminance Y = scale; Error for an unknown name (listing the known ones).
Spectrum named_illuminant(std::string_view name, double scale = 1.0);

std::vector<std::string> illuminant_names();

Vec3 xy_to_xyz(double x, double y, double luminance_y = 1.0);

}  // namespace bouguer
