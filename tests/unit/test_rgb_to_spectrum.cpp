// RGB lifted to spectra (Jakob & Hanika 2019): the spectrum's colour, computed with the renderer's
// 1 nm CIE tables, gives back the RGB it came from.
#include <gtest/gtest.h>

#include <random>

#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"
#include "bouguer/spectra/rgb_to_spectrum.h"

namespace bouguer {
namespace {

// Reflectance r(λ) seen under D65 at Y = 1, as linear Rec.709.
Vec3 reflectance_colour(const SigmoidPolynomial& r) {
  TabulatedSpectrum lit;
  for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm; nm += 1.0) {
    lit.wavelength_nm.push_back(nm);
    lit.value.push_back(r(nm) * d65_unit_luminance(nm));
  }
  return xyz_to_linear_rgb(kRec709, spectrum_to_xyz(lit));
}

double delta_e(const Vec3& rgb_a, const Vec3& rgb_b) {
  return ciede2000(xyz_to_lab(linear_rgb_to_xyz(kRec709, rgb_a)), xyz_to_lab(linear_rgb_to_xyz(kRec709, rgb_b)));
}

TEST(RgbToSpectrum, ReflectancesGiveTheirColourBack) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.05, 1.0);
  double worst = 0.0, sum = 0.0;
  const int n = 2000;
  for (int i = 0; i < n; ++i) {
    const Vec3 rgb{u(rng), u(rng), u(rng)};
    const SigmoidPolynomial s = rgb_to_reflectance(rgb);
    for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm; nm += 10.0) {
      ASSERT_GE(s(nm), 0.0);
      ASSERT_LE(s(nm), 1.0);
    }
    const double d = delta_e(rgb, reflectance_colour(s));
    worst = std::max(worst, d);
    sum += d;
  }
  std::printf("RGB reflectance round trip: mean ΔE00 %.4f, worst %.4f over %d colours\n", sum / n, worst, n);
  EXPECT_LT(sum / n, 0.1);  // measured 0.049: trilinear interpolation between the 32³ nodes
  EXPECT_LT(worst, 0.5);
}

TEST(RgbToSpectrum, PrimariesAndGreys) {
  for (const Vec3& rgb : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}, Vec3{1, 1, 0}, Vec3{0.5, 0.5, 0.5},
                          Vec3{0.18, 0.18, 0.18}, Vec3{1, 1, 1}})
    EXPECT_LT(delta_e(rgb, reflectance_colour(rgb_to_reflectance(rgb))), 0.5) << rgb.x << " " << rgb.y << " " << rgb.z;
  // Greys are exactly flat.
  const SigmoidPolynomial grey = rgb_to_reflectance({0.3, 0.3, 0.3});
  EXPECT_NEAR(grey(400.0), 0.3, 1e-12);
  EXPECT_NEAR(grey(700.0), 0.3, 1e-12);
  EXPECT_EQ(rgb_to_reflectance({0, 0, 0})(550.0), 0.0);
}

TEST(RgbToSpectrum, IlluminantsGiveTheirRadianceBack) {
  // White (1, 1, 1) is D65 at Y = 1 exactly; colours and values above 1 round-trip.
  const Vec3 white = xyz_to_linear_rgb(kRec709, spectrum_to_xyz(Spectrum{rgb_to_illuminant({1, 1, 1})}));
  EXPECT_NEAR(white.x, 1.0, 2e-3);
  EXPECT_NEAR(white.y, 1.0, 2e-3);
  EXPECT_NEAR(white.z, 1.0, 2e-3);
  for (const Vec3& rgb : {Vec3{4.0, 2.0, 0.5}, Vec3{0.1, 0.3, 0.9}, Vec3{20.0, 18.0, 15.0}}) {
    const Vec3 back = xyz_to_linear_rgb(kRec709, spectrum_to_xyz(Spectrum{rgb_to_illuminant(rgb)}));
    const double m = std::max({rgb.x, rgb.y, rgb.z});
    EXPECT_LT(delta_e(rgb / m, back / m), 0.3) << rgb.x << " " << rgb.y << " " << rgb.z;
  }
}

}  // namespace
}  // namespace bouguer
