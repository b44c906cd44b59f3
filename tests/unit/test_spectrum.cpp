#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bouguer/core/error.h"
#include "bouguer/spectra/sampled_spectrum.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {
namespace {

TEST(TabulatedSpectrum, InterpolatesLinearlyAndClampsOutside) {
  const Spectrum s = make_tabulated({400, 500, 600}, {1.0, 3.0, 2.0}, "test");
  EXPECT_DOUBLE_EQ(eval(s, 450), 2.0);
  EXPECT_DOUBLE_EQ(eval(s, 500), 3.0);
  EXPECT_DOUBLE_EQ(eval(s, 575), 2.25);
  EXPECT_DOUBLE_EQ(eval(s, 360), 1.0);  // clamped below the table
  EXPECT_DOUBLE_EQ(eval(s, 830), 2.0);  // clamped above
  EXPECT_DOUBLE_EQ(min_value(s), 1.0);
  EXPECT_DOUBLE_EQ(max_value(s), 3.0);
}

TEST(TabulatedSpectrum, SinglePointIsConstant) {
  const Spectrum s = make_tabulated({550}, {0.25}, "test");
  EXPECT_DOUBLE_EQ(eval(s, 380), 0.25);
  EXPECT_DOUBLE_EQ(eval(s, 800), 0.25);
}

TEST(TabulatedSpectrum, RejectsBadTables) {
  EXPECT_THROW(make_tabulated({}, {}, "t"), Error);
  EXPECT_THROW(make_tabulated({400, 500}, {1.0}, "t"), Error);
  EXPECT_THROW(make_tabulated({500, 400}, {1.0, 1.0}, "t"), Error);
  EXPECT_THROW(make_tabulated({400, 400}, {1.0, 1.0}, "t"), Error);
  EXPECT_THROW(make_tabulated({400, 500}, {1.0, NAN}, "t"), Error);
  EXPECT_THROW(make_tabulated({-5, 500}, {1.0, 1.0}, "t"), Error);
}

TEST(Spectrum, ScaledMultipliesEveryKind) {
  EXPECT_DOUBLE_EQ(eval(scaled(ConstantSpectrum{2.0}, 1.5), 500), 3.0);
  EXPECT_DOUBLE_EQ(eval(scaled(make_tabulated({400, 600}, {1, 3}, "t"), 2.0), 500), 4.0);
  const Spectrum bb = BlackbodySpectrum{3000.0, 1.0};
  EXPECT_DOUBLE_EQ(eval(scaled(bb, 7.0), 500), 7.0 * eval(bb, 500));
}

// Wien's displacement law: the peak of B_λ lies at b / T, b = 2.897771955e-3 m·K (CODATA 2018).
TEST(Blackbody, PeakFollowsWien) {
  for (const double kelvin : {4000.0, 5000.0, 6500.0}) {
    const double expected_nm = 2.897771955e-3 / kelvin * 1e9;
    double best_nm = 0.0, best = 0.0;
    for (double nm = 360.0; nm <= 830.0; nm += 0.01) {
      const double v = planck_radiance_per_nm(nm, kelvin);
      if (v > best) best = v, best_nm = nm;
    }
    EXPECT_NEAR(best_nm, expected_nm, 0.02) << kelvin << " K";
  }
}

// Stefan–Boltzmann: ∫ B_λ dλ = σ T⁴ / π.
TEST(Blackbody, IntegratesToStefanBoltzmann) {
  constexpr double sigma = 5.670374419e-8;  // W m⁻² K⁻⁴
  const double kelvin = 5000.0;
  double integral = 0.0;  // W m⁻² sr⁻¹, midpoint rule on a log grid 10 nm .. 1 mm
  const double lo = std::log(10.0), hi = std::log(1e6);
  const int n = 200000;
  for (int i = 0; i < n; ++i) {
    const double nm = std::exp(lo + (hi - lo) * (i + 0.5) / n);
    integral += planck_radiance_per_nm(nm, kelvin) * nm * (hi - lo) / n;
  }
  EXPECT_NEAR(integral / (sigma * std::pow(kelvin, 4) / std::numbers::pi), 1.0, 1e-6);
}

TEST(SampledSpectrum, ArithmeticIsElementwise) {
  using S4 = SampledSpectrum<4>;
  S4 a{{1, 2, 3, 4}};
  const S4 b{{2, 2, 2, 2}};
  EXPECT_EQ(a * b, (S4{{2, 4, 6, 8}}));
  EXPECT_EQ(a + 1.0f, (S4{{2, 3, 4, 5}}));
  EXPECT_EQ(a / b, (S4{{0.5f, 1, 1.5f, 2}}));
  EXPECT_EQ(a - b, (S4{{-1, 0, 1, 2}}));
  EXPECT_FLOAT_EQ(a.average(), 2.5f);
  EXPECT_FLOAT_EQ(a.max_value(), 4.0f);
  EXPECT_FLOAT_EQ(a.min_value(), 1.0f);
  EXPECT_FALSE(a.is_zero());
  EXPECT_TRUE(S4{}.is_zero());
  a *= 0.5f;
  EXPECT_EQ(a, (S4{{0.5f, 1, 1.5f, 2}}));
}

TEST(SampledSpectrum, BeerLambertIsExpOfMinusSigmaLength) {
  const SampledSpectrum<3> sigma_a_per_m{{0.0f, 230.2585f, 1000.0f}};
  const auto t = beer_lambert_transmittance(sigma_a_per_m, 0.01f);  // 1 cm
  EXPECT_FLOAT_EQ(t[0], 1.0f);
  EXPECT_NEAR(t[1], 0.1f, 1e-6f);  // absorbance 1 per cm -> 10 % through 1 cm
  EXPECT_NEAR(t[2], std::exp(-10.0f), 1e-9f);
  EXPECT_EQ(exp(SampledSpectrum<2>{{0.0f, 1.0f}}), (SampledSpectrum<2>{{1.0f, std::exp(1.0f)}}));
}

}  // namespace
}  // namespace bouguer

namespace bouguer {
namespace {
// The vectorised exponential of the transmittance matches std::exp to 3e-7 relative over the
// range that matters (e^-87 is below the smallest normal float), and is 1 at 0.
TEST(SampledSpectrum, FastExponentialMatchesStdExp) {
  double worst = 0.0;
  for (double x = -87.0; x <= 0.0; x += 0.001) {
    const float fx = static_cast<float>(x);
    const double exact = std::exp(static_cast<double>(fx));
    worst = std::max(worst, std::abs(exp_nonpositive(fx) - exact) / exact);
  }
  EXPECT_LT(worst, 3e-7);
  EXPECT_EQ(exp_nonpositive(0.0f), 1.0f);
  EXPECT_EQ(exp_nonpositive(-1000.0f), exp_nonpositive(-87.0f));
}

// The ratio exponential (media/scattering.h) covers [−87, 80] with the same accuracy.
TEST(SampledSpectrum, LimitedExponentialMatchesStdExp) {
  double worst = 0.0;
  for (double x = -87.0; x <= 80.0; x += 0.001) {
    const float fx = static_cast<float>(x);
    const double exact = std::exp(static_cast<double>(fx));
    worst = std::max(worst, std::abs(exp_limited(fx) - exact) / exact);
  }
  EXPECT_LT(worst, 3e-7);
  EXPECT_EQ(exp_limited(1000.0f), exp_limited(80.0f));
}

// The vectorised logarithm matches std::log to 2e-7 (absolute near 1, relative elsewhere) from
// the smallest normal float to the largest.
TEST(SampledSpectrum, FastLogarithmMatchesStdLog) {
  double worst = 0.0;
  for (double e = -125.0; e < 127.0; e += 0.0007) {
    const auto x = static_cast<float>(std::exp2(e));
    const double exact = std::log(static_cast<double>(x));
    worst = std::max(worst, std::abs(log_positive(x) - exact) / std::max(1.0, std::abs(exact)));
  }
  EXPECT_LT(worst, 2e-7);
  EXPECT_EQ(log_positive(1.0f), 0.0f);
}
}  // namespace
}  // namespace bouguer
