#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "bouguer/media/mie.h"
#include "bouguer/media/milk.h"
#include "bouguer/media/scattering_library.h"
#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {
namespace {

// x → 0: Q_sca = 8/3 x⁴ |(m²−1)/(m²+2)|² (Bohren & Huffman eq. 5.8); the next term is O(x²).
TEST(Mie, RayleighLimit) {
  for (const std::complex<double> m : {std::complex<double>{1.5, 0.0}, {1.33, 0.01}, {2.0, 1.0}}) {
    const double x = 1e-3;
    const std::complex<double> f = (m * m - 1.0) / (m * m + 2.0);
    EXPECT_NEAR(mie_sphere(x, m).q_sca / (8.0 / 3.0 * std::pow(x, 4) * std::norm(f)), 1.0, 1e-4) << m;
  }
}

TEST(Mie, NonAbsorbingSphereExtinguishesOnlyByScattering) {
  for (const double x : {0.1, 1.0, 5.0, 30.0, 300.0}) {
    const MieEfficiencies e = mie_sphere(x, {1.46, 0.0});
    EXPECT_NEAR(e.q_ext, e.q_sca, 1e-9 * e.q_ext) << x;
  }
}

// The extinction paradox: Q_ext → 2 as x → ∞ (within 0.5 % at x = 10⁴: the edge term is O(x^{-2/3})).
TEST(Mie, LargeSpheresExtinguishTwiceTheirShadow) {
  EXPECT_NEAR(mie_sphere(1e4, {1.5, 0.0}).q_ext, 2.0, 0.01);
  EXPECT_NEAR(mie_sphere(1e4, {1.5, 0.1}).q_ext, 2.0, 0.01);
}

// Bohren & Huffman (1983), appendix A, the BHMIE test case: m = 1.55, r = 0.525 µm, λ = 0.6328 µm
// (x = 5.213): Q_ext = Q_sca = 3.10543, g = 0.63314 (as their program prints them).
TEST(Mie, BohrenHuffmanTestCase) {
  const MieEfficiencies e = mie_sphere(2.0 * std::numbers::pi * 0.525 / 0.6328, {1.55, 0.0});
  EXPECT_NEAR(e.q_ext, 3.10543, 1e-4);
  EXPECT_NEAR(e.q_sca, 3.10543, 1e-4);
  EXPECT_NEAR(e.g, 0.63314, 1e-4);
}

TEST(Mie, AbsorbingSpheresAbsorb) {
  const MieEfficiencies e = mie_sphere(1.0, {1.5, 1.0});
  EXPECT_GT(e.q_abs(), 0.0);
  EXPECT_LT(e.g, 1.0);
}

// A monodisperse suspension (a narrow band of radii) gives N π r² Q.
TEST(Mie, BulkOfANarrowBandIsNumberTimesCrossSection) {
  const double r = 0.5e-6, width = 1e-9, n_per_m3 = 1e15;
  SphereSuspension s{[&](double) { return n_per_m3 / width; }, r - width / 2, r + width / 2, {1.46, 0.0}};
  const MieBulk b = mie_bulk(s, 1.333, 550.0, 4);
  const MieEfficiencies e = mie_sphere(2.0 * std::numbers::pi * 1.333 * r / 550e-9, {1.46 / 1.333, 0.0});
  EXPECT_NEAR(b.sigma_s_per_m / (n_per_m3 * std::numbers::pi * r * r * e.q_sca), 1.0, 1e-3);
  EXPECT_NEAR(b.g, e.g, 1e-3);
}

// The stated quadrature: doubling its pieces changes σ_s by under 0.1 %.
TEST(Milk, QuadratureIsConverged) {
  for (const MilkComposition m : {MilkComposition{3.5, 3.4, 20.0}, MilkComposition{0.1, 3.4, 20.0}})
    for (const double nm : {360.0, 550.0, 830.0}) {
      const double a = milk_coefficients(m, nm).sigma_s_per_m;
      const double b = milk_coefficients(m, nm, 2 * kMilkIntervals).sigma_s_per_m;
      EXPECT_LT(std::abs(b / a - 1.0), 1e-3) << m.fat_wt_percent << " % fat at " << nm << " nm";
    }
}

// Against measurement: Jensen, Marschner, Levoy & Hanrahan (2001), "A practical model for subsurface
// light transport", Fig. 5, reduced scattering σ_s' = σ_s(1 − g) of whole milk (2.55, 3.21, 3.77)
// and skimmed milk (0.70, 1.22, 1.90) per mm in R, G, B, taken here at 650, 550 and 450 nm.
// Tolerances: skimmed milk within 25 %; whole milk within a factor 1.8 (their milk's fat
// content and homogenisation are not known, and σ_s' grows with both).
TEST(Milk, ReducedScatteringNearJensen2001) {
  const double nm[3] = {650.0, 550.0, 450.0};
  const double whole[3] = {2.55, 3.21, 3.77}, skimmed[3] = {0.70, 1.22, 1.90};
  for (int i = 0; i < 3; ++i) {
    const MilkCoefficients w = milk_coefficients({3.5, 3.4, 20.0}, nm[i]);
    const MilkCoefficients s = milk_coefficients({0.1, 3.4, 20.0}, nm[i]);
    const double w_reduced_per_mm = w.sigma_s_per_m * (1.0 - w.g) / 1000.0;
    const double s_reduced_per_mm = s.sigma_s_per_m * (1.0 - s.g) / 1000.0;
    EXPECT_NEAR(s_reduced_per_mm / skimmed[i], 1.0, 0.25) << nm[i];
    EXPECT_GT(w_reduced_per_mm / whole[i], 1.0 / 1.8) << nm[i];
    EXPECT_LT(w_reduced_per_mm / whole[i], 1.8) << nm[i];
  }
}

TEST(Milk, FatScattersMoreAndMoreForward) {
  const MilkCoefficients w = milk_coefficients({3.5, 3.4, 20.0}, 550.0);
  const MilkCoefficients s = milk_coefficients({0.1, 3.4, 20.0}, 550.0);
  EXPECT_GT(w.sigma_s_per_m, 10.0 * s.sigma_s_per_m);
  EXPECT_GT(w.g, s.g);
  EXPECT_GT(milk_coefficients({3.5, 3.4, 20.0}, 400.0).sigma_s_per_m, w.sigma_s_per_m);  // bluer scatters more
}

TEST(ScatteringLibrary, EveryEntryIsFiniteAndPhysical) {
  ASSERT_EQ(scattering_media().size(), 37u);  // two milks and Narasimhan's 35
  for (const ScatteringLibraryEntry& e : scattering_media()) {
    SCOPED_TRACE(e.name);
    EXPECT_FALSE(e.description.empty());
    EXPECT_FALSE(e.measured.empty());
    EXPECT_FALSE(e.citation.empty());
    for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm; nm += 5.0) {
      const double s = eval(e.sigma_s_per_m, nm), a = eval(e.sigma_a_per_m, nm);
      EXPECT_TRUE(std::isfinite(s) && s >= 0.0) << nm;
      EXPECT_TRUE(std::isfinite(a) && a >= 0.0) << nm;
    }
    EXPECT_LT(std::abs(mean_cosine(e.phase)), 1.0);
    EXPECT_EQ(find_scattering_medium(e.name), &e);
  }
  EXPECT_EQ(find_scattering_medium("no_such_medium"), nullptr);
}

// A coefficient spectrum seen as a reflectance under D65 at Y = 1, as linear Rec.709: the inverse of
// the RGB lift.
Vec3 rgb_of(const Spectrum& s) {
  TabulatedSpectrum lit;
  for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm; nm += 1.0) {
    lit.wavelength_nm.push_back(nm);
    lit.value.push_back(eval(s, nm) * d65_unit_luminance(nm));
  }
  return xyz_to_linear_rgb(kRec709, spectrum_to_xyz(lit));
}

// The table's values are in 10⁻² per mm: 10 per metre.
void expect_rgb_per_mm(const Spectrum& s, const Vec3& published_per_mm) {
  const Vec3 got = rgb_of(s) / 10.0;
  const double tol = 0.01 * std::max({published_per_mm.x, published_per_mm.y, published_per_mm.z});
  EXPECT_NEAR(got.x, published_per_mm.x, tol);
  EXPECT_NEAR(got.y, published_per_mm.y, tol);
  EXPECT_NEAR(got.z, published_per_mm.z, tol);
}

// Two published rows of Narasimhan et al. (2006) Table 1 (in 10⁻² per mm): Regular Milk σ_t (1.1874,
// 1.3296, 1.4602), σ_s (1.1873, 1.3293, 1.4589), g (0.750, 0.714, 0.681); Espresso σ_t (0.4376,
// 0.5115, 0.6048), σ_s (0.2707, 0.2828, 0.2970), g (0.907, 0.896, 0.880). The lifted spectra
// lifted spectra give back those RGB values (σ_a = σ_t − σ_s) within 1 % of the largest channel.
TEST(ScatteringLibrary, NarasimhanEntriesMatchThePaper) {
  const ScatteringLibraryEntry* milk = find_scattering_medium("regular_milk");
  const ScatteringLibraryEntry* espresso = find_scattering_medium("espresso");
  ASSERT_TRUE(milk && espresso);
  EXPECT_TRUE(milk->rgb_measured);
  EXPECT_NEAR(mean_cosine(milk->phase), (0.750 + 0.714 + 0.681) / 3.0, 1e-9);
  EXPECT_NEAR(mean_cosine(espresso->phase), (0.907 + 0.896 + 0.880) / 3.0, 1e-9);
  expect_rgb_per_mm(milk->sigma_s_per_m, {1.1873, 1.3293, 1.4589});
  expect_rgb_per_mm(milk->sigma_a_per_m, {1.1874 - 1.1873, 1.3296 - 1.3293, 1.4602 - 1.4589});
  expect_rgb_per_mm(espresso->sigma_s_per_m, {0.2707, 0.2828, 0.2970});
  expect_rgb_per_mm(espresso->sigma_a_per_m, {0.4376 - 0.2707, 0.5115 - 0.2828, 0.6048 - 0.2970});
}

TEST(ScatteringLibrary, MilkEntriesAreTheModel) {
  const ScatteringLibraryEntry* whole = find_scattering_medium("whole_milk");
  ASSERT_TRUE(whole);
  EXPECT_FALSE(whole->rgb_measured);
  EXPECT_NEAR(eval(whole->sigma_s_per_m, 550.0), milk_coefficients({3.5, 3.4, 20.0}, 550.0).sigma_s_per_m, 1e-6);
  EXPECT_GT(mean_cosine(whole->phase), 0.8);
  ASSERT_TRUE(find_scattering_medium("skimmed_milk"));
}

}  // namespace
}  // namespace bouguer
