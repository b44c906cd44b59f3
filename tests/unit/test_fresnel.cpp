#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bouguer/materials/fresnel.h"

namespace bouguer {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(Fresnel, NormalIncidence) {
  for (const double n : {1.33, 1.5, 2.42}) {
    const double expected = std::pow((n - 1.0) / (n + 1.0), 2.0);
    EXPECT_NEAR(fresnel_dielectric(1.0, 1.0, n), expected, 1e-12);
    EXPECT_NEAR(fresnel_dielectric(1.0, n, 1.0), expected, 1e-12);  // same from inside
  }
  EXPECT_NEAR(fresnel_dielectric(1.0, 1.0, 1.5), 0.04, 1e-12);
}

TEST(Fresnel, BrewsterAngleHasNoPReflection) {
  for (const auto& [n1, n2] : {std::pair{1.0, 1.5}, std::pair{1.5, 1.0}, std::pair{1.33, 1.52}}) {
    const double brewster = std::atan(n2 / n1);
    EXPECT_NEAR(fresnel_dielectric_p(std::cos(brewster), n1, n2), 0.0, 1e-12);
    EXPECT_GT(fresnel_dielectric_s(std::cos(brewster), n1, n2), 0.01);
    EXPECT_GT(fresnel_dielectric_p(std::cos(brewster + 0.05), n1, n2), 1e-5);
  }
}

TEST(Fresnel, TotalInternalReflectionStartsAtTheCriticalAngle) {
  const double n1 = 1.5, n2 = 1.0;
  const double critical = std::asin(n2 / n1);
  EXPECT_LT(fresnel_dielectric(std::cos(critical - 1e-4), n1, n2), 1.0);
  EXPECT_EQ(fresnel_dielectric(std::cos(critical + 1e-4), n1, n2), 1.0);
  const Vec3 n{0, 0, 1};
  const Vec3 below{std::sin(critical - 1e-4), 0, std::cos(critical - 1e-4)};
  const Vec3 above{std::sin(critical + 1e-4), 0, std::cos(critical + 1e-4)};
  EXPECT_TRUE(refract(below, n, n1, n2).has_value());
  EXPECT_FALSE(refract(above, n, n1, n2).has_value());
}

// R + T = 1 with T from the Fresnel transmission amplitudes and the flux factor
// (n_t cos θt)/(n_i cos θi), an independent formula.
TEST(Fresnel, ReflectancePlusTransmittanceIsOne) {
  for (const auto& [ni, nt] : {std::pair{1.0, 1.5}, std::pair{1.5, 1.0}, std::pair{1.0, 2.42}}) {
    for (double deg = 0.0; deg < 89.0; deg += 7.0) {
      const double ci = std::cos(deg * kPi / 180.0);
      const double s2t = (1.0 - ci * ci) * (ni / nt) * (ni / nt);
      if (s2t >= 1.0) continue;
      const double ct = std::sqrt(1.0 - s2t);
      const double ts = 2.0 * ni * ci / (ni * ci + nt * ct);
      const double tp = 2.0 * ni * ci / (nt * ci + ni * ct);
      const double flux = (nt * ct) / (ni * ci);
      EXPECT_NEAR(fresnel_dielectric_s(ci, ni, nt) + flux * ts * ts, 1.0, 1e-12) << deg;
      EXPECT_NEAR(fresnel_dielectric_p(ci, ni, nt) + flux * tp * tp, 1.0, 1e-12) << deg;
    }
  }
}

TEST(Fresnel, RefractionObeysSnellAndReflectionMirrors) {
  const Vec3 n{0, 0, 1};
  const Vec3 wi = normalize(Vec3{0.6, 0.0, 0.8});
  const auto t = refract(wi, n, 1.0, 1.5);
  ASSERT_TRUE(t);
  EXPECT_NEAR(length(*t), 1.0, 1e-12);
  EXPECT_LT(t->z, 0.0);  // into the other side
  EXPECT_NEAR(1.0 * length(cross(wi, n)), 1.5 * length(cross(*t, n)), 1e-12);
  const Vec3 r = reflect(wi, n);
  EXPECT_NEAR(r.x, -0.6, 1e-12);
  EXPECT_NEAR(r.z, 0.8, 1e-12);
}

}  // namespace
}  // namespace bouguer
