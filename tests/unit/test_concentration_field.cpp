// Concentration fields (media/concentration_field.h): the closed-form column densities against
// numerical quadrature, along the axis, obliquely, and in the limit where a ray runs across it.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "bouguer/media/concentration_field.h"

namespace bouguer {
namespace {

// ∫ c(o + t·d) dt by composite Simpson on many intervals (a reference, independent of the closed
// forms; the layers field's steps are resolved by the interval count).
double quadrature(const ConcentrationField& f, const Vec3& o, const Vec3& d, double t0, double t1, int n = 200000) {
  const double h = (t1 - t0) / n;
  double sum = concentration_at(f, o + d * t0) + concentration_at(f, o + d * t1);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * concentration_at(f, o + d * (t0 + i * h));
  return sum * h / 3.0;
}

std::vector<std::pair<const char*, ConcentrationField>> fields() {
  const FieldAxis up{{0.0, 0.01, 0.0}, {0, 1, 0}};
  return {{"linear", LinearField{up, 2.0, -150.0}},  // reaches 0 at s = 13.3 mm
          {"exponential", ExponentialField{up, 1.5, 0.008}},
          {"diffusion", DiffusionField{up, 3.0, 0.003}},
          {"layers", LayersField{up, {-0.01, 0.005, 0.02}, {0.5, 2.0, 0.0}}},
          {"constant", ConstantField{0.7}}};
}

TEST(ConcentrationField, ColumnDensityMatchesQuadratureAlongObliqueAndAcrossTheAxis) {
  const Vec3 o{0.003, -0.03, 0.002};
  const Vec3 directions[] = {{0, 1, 0}, {0, -1, 0}, normalize(Vec3{1, 2, 0.5}), normalize(Vec3{1, 0.05, 0}),
                             normalize(Vec3{1, 1e-7, 0})};
  for (const auto& [name, f] : fields())
    for (const Vec3& d : directions) {
      const double exact = column_density(f, o, d, 0.002, 0.061), reference = quadrature(f, o, d, 0.002, 0.061);
      // Simpson's rule is off by up to about h·jump at each layer step it crosses (h = 3e-7 m).
      const double steps = std::string(name) == "layers" ? 3 * 2 * 2.0 * (0.059 / 200000) : 0.0;
      EXPECT_NEAR(exact, reference, 1e-6 * std::abs(reference) + steps + 1e-12) << name << " d.y " << d.y;
      EXPECT_GE(exact, 0.0);
    }
}

TEST(ConcentrationField, ARayAcrossTheAxisSeesTheConcentrationWhereItRuns) {
  for (const auto& [name, f] : fields()) {
    const Vec3 o{-0.02, 0.012, 0.0};
    const double c = concentration_at(f, o);
    // Exactly across, and across to within 1e-12 rad: both c times the length, continuously.
    EXPECT_NEAR(column_density(f, o, {1, 0, 0}, 0.0, 0.04), c * 0.04, 1e-14) << name;
    const Vec3 tilted = normalize(Vec3{1, 1e-12, 0});
    EXPECT_NEAR(column_density(f, o, tilted, 0.0, 0.04), c * 0.04, 1e-12) << name;
  }
}

TEST(ConcentrationField, ClosedFormsAtKnownValues) {
  const FieldAxis up{{0, 0, 0}, {0, 1, 0}};
  // Diffusion: the integral over all s of c0/2·erfc(s/w) from −L to 0 tends to c0·L for L >> w,
  // and ∫_0^∞ = c0·w/(2√π).
  const DiffusionField d{up, 1.0, 0.001};
  EXPECT_NEAR(column_density(d, {0, 0, 0}, {0, 1, 0}, 0.0, 0.05), 0.001 / (2.0 * std::sqrt(std::acos(-1.0))), 1e-12);
  EXPECT_NEAR(column_density(d, {0, 0, 0}, {0, -1, 0}, 0.0, 0.05), 0.05 - 0.001 / (2.0 * std::sqrt(std::acos(-1.0))),
              1e-12);
  // Exponential: ∫_0^∞ c0·exp(−s/H) ds = c0·H.
  EXPECT_NEAR(column_density(ExponentialField{up, 2.0, 0.01}, {0, 0, 0}, {0, 1, 0}, 0.0, 1.0), 0.02, 1e-12);
  // Below the floor the exponential stays at c0·e⁴⁰ instead of overflowing.
  const double deep = column_density(ExponentialField{up, 1.0, 1e-6}, {0, -1, 0}, {1, 0, 0}, 0.0, 1.0);
  EXPECT_NEAR(deep / std::exp(kExponentialFloor), 1.0, 1e-12);
  // Linear: the positive part only, c = max(0, 1 − 100·s) from s = 0 to 0.05: area 1/200.
  EXPECT_NEAR(column_density(LinearField{up, 1.0, -100.0}, {0, 0, 0}, {0, 1, 0}, 0.0, 0.05), 0.005, 1e-15);
  // Layers: 2 mm of 1, then 3 mm of 4, then beyond of 0.5, along a 45° ray.
  const LayersField l{up, {0.002, 0.005}, {1.0, 4.0, 0.5}};
  const Vec3 diagonal = normalize(Vec3{1, 1, 0});
  EXPECT_NEAR(column_density(l, {0, 0, 0}, diagonal, 0.0, 0.01 * std::sqrt(2.0)),
              std::sqrt(2.0) * (0.002 * 1.0 + 0.003 * 4.0 + 0.005 * 0.5), 1e-15);
}

TEST(ConcentrationField, Maxima) {
  const FieldAxis up{{0, 0, 0}, {0, 1, 0}};
  EXPECT_TRUE(std::isinf(max_concentration(LinearField{up, 1.0, 2.0})));
  EXPECT_EQ(max_concentration(LayersField{up, {0.0}, {1.0, 3.0}}), 3.0);
  EXPECT_EQ(max_concentration(DiffusionField{up, 2.5, 0.01}), 2.5);
  EXPECT_TRUE(std::isinf(max_concentration(ExponentialField{up, 1.0, 0.01})));
}

}  // namespace
}  // namespace bouguer
