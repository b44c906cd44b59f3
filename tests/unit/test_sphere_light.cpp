// An emitting sphere (lights/light.h: SphereLight) sampled by the cone of directions it subtends,
// against closed forms: every drawn point lies on the cap that faces the shading point and is the
// first the ray meets, the density is the cone's 1/(2π(1 − cos θmax)) and is the one pdf_li
// reports, and the irradiance it estimates on a plane is π·L·sin²θmax·cos β (the sphere wholly
// above the plane, β the angle between the plane's normal and the direction to the centre), for
// cones from 0.1° to 56°. Emission sampling draws points on the sphere and directions about their
// normal with the densities pdf_le reports.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "bouguer/core/frame.h"
#include "bouguer/lights/light.h"

namespace bouguer {
namespace {

constexpr double kPi = std::numbers::pi;

// The near root of |p + t·wi − c| = r (wi unit), or −1 where the ray misses.
double first_hit(const Vec3& p, const Vec3& wi, const Vec3& c, double r) {
  const Vec3 o = p - c;
  const double b = dot(o, wi), q = dot(o, o) - r * r, disc = b * b - q;
  if (disc < 0.0) return -1.0;
  // (q / (−b + √disc): the near root without cancellation, b < 0 towards the sphere)
  return q / (-b + std::sqrt(disc));
}

TEST(SphereLight, DrawsTheConeItSubtendsAndEstimatesTheIrradianceExactly) {
  const Vec3 centre{0.1, 0.2, -0.3};
  struct Case {
    double radius_m, distance_m;
  };
  // sin θmax from 0.002 (0.11°, where 1 − cos θmax = 2e-6 cancels in double's 1 − √(1 − s²)
  // to about 1e-10 relative) to 0.83.
  for (const Case c : {Case{0.002, 1.0}, Case{0.005, 0.1}, Case{0.05, 0.2}, Case{0.5, 0.6}}) {
    const SphereLight sphere{0, centre, c.radius_m, 0};
    const Light light = sphere;
    const Vec3 axis = normalize(Vec3{0.3, -0.5, 0.8});
    const Vec3 p = centre - axis * c.distance_m;  // axis: from p towards the centre
    const double sin2_max = c.radius_m * c.radius_m / (c.distance_m * c.distance_m);
    const double cone_pdf = 1.0 / (2.0 * kPi * (sin2_max / (1.0 + std::sqrt(1.0 - sin2_max))));
    // A plane through p tilted by β from the axis, within the horizon: β + θmax < 90°.
    const double beta = 0.5 * (kPi / 2.0 - std::asin(std::sqrt(sin2_max)));
    const Frame f(axis);
    const Vec3 tilted = axis * std::cos(beta) + f.s * std::sin(beta);
    constexpr int kStrata = 256;
    double facing = 0.0, tilted_sum = 0.0, worst_radius = 0.0, worst_hit = 0.0, worst_pdf = 0.0;
    for (int i = 0; i < kStrata; ++i)
      for (int j = 0; j < kStrata; ++j) {
        const double u1 = (i + 0.5) / kStrata, u2 = (j + 0.5) / kStrata;
        const auto li = sample_li(light, p, u1, u2);
        ASSERT_TRUE(li) << i << " " << j;
        const Vec3 q = p + li->wi * li->distance_m;
        worst_radius = std::max(worst_radius, std::abs(length(q - centre) - c.radius_m) / c.radius_m);
        worst_hit = std::max(worst_hit, std::abs(first_hit(p, li->wi, centre, c.radius_m) - li->distance_m) / li->distance_m);
        worst_pdf = std::max(worst_pdf, std::abs(li->pdf / cone_pdf - 1.0));
        EXPECT_DOUBLE_EQ(pdf_li(light, p, li->wi, q), li->pdf);
        EXPECT_EQ(li->factor, 1.0);
        EXPECT_FALSE(li->delta);
        facing += dot(li->wi, axis) * li->factor / li->pdf;
        tilted_sum += std::max(0.0, dot(li->wi, tilted)) * li->factor / li->pdf;
      }
    const double n = double(kStrata) * kStrata;
    std::printf("sphere r %.3f m at %.2f m (sin² θmax %.2g): irradiance / (π sin² θmax) %.9f facing, %.9f at β %.1f°; "
                "worst |q − c| − r %.1e, first hit %.1e, pdf %.1e (relative)\n",
                c.radius_m, c.distance_m, sin2_max, facing / n / (kPi * sin2_max),
                tilted_sum / n / (kPi * sin2_max * std::cos(beta)), beta * 180.0 / kPi, worst_radius, worst_hit,
                worst_pdf);
    EXPECT_LT(worst_radius, 1e-9);
    EXPECT_LT(worst_hit, 1e-7);  // the drawn point is the first the ray meets: on the near cap
    EXPECT_LT(worst_pdf, 1e-9);
    // Stratified in cos θ, the facing plane's integrand is linear in it: exact but for rounding;
    // the tilted plane's to the strata's error.
    EXPECT_NEAR(facing / n / (kPi * sin2_max), 1.0, 1e-9);
    EXPECT_NEAR(tilted_sum / n / (kPi * sin2_max * std::cos(beta)), 1.0, 1e-4);
  }
}

TEST(SphereLight, EmitsNothingInwardAndIsNotSampledFromInside) {
  const SphereLight sphere{0, Vec3{}, 0.1, 0};
  const Light light = sphere;
  EXPECT_FALSE(sample_li(light, Vec3{0.05, 0, 0}, 0.3, 0.7));
  EXPECT_FALSE(sample_li(light, Vec3{0.1, 0, 0}, 0.3, 0.7));  // on it
  EXPECT_EQ(pdf_li(light, Vec3{0.05, 0, 0}, Vec3{1, 0, 0}, Vec3{0.1, 0, 0}), 0.0);
  EXPECT_EQ(emitted_factor(light, Vec3{1, 0, 0}, Vec3{1, 0, 0}), 1.0);
  EXPECT_EQ(emitted_factor(light, Vec3{-1, 0, 0}, Vec3{1, 0, 0}), 0.0);
  EXPECT_TRUE(on_a_surface(light));
}

// Emission sampling: origins on the sphere, directions in the hemisphere of their outward normal,
// the densities pdf_le gives back; the cosine-weighted mean of 1/pdf_dir is π (every direction of
// a Lambertian emitter counted), and the power is π·4πr²·L.
TEST(SphereLight, EmissionSamplingDrawsTheDensitiesItReports) {
  const SphereLight sphere{0, Vec3{1, 2, 3}, 0.25, 0};
  const Light light = sphere;
  const SceneBounds bounds{Vec3{}, 10.0};
  double mean_cos_over_pdf = 0.0, mean_normal_x = 0.0;
  constexpr int kStrata = 64;
  for (int i = 0; i < kStrata; ++i)
    for (int j = 0; j < kStrata; ++j) {
      const double u = (i + 0.5) / kStrata, v = (j + 0.5) / kStrata;
      const auto le = sample_le(light, bounds, u, v, v, u);
      ASSERT_TRUE(le);
      EXPECT_NEAR(length(le->ray.origin - sphere.centre_m), sphere.radius_m, 1e-12);
      EXPECT_NEAR(dot(le->normal, normalize(le->ray.origin - sphere.centre_m)), 1.0, 1e-12);
      const double cos_out = dot(le->ray.direction, le->normal);
      EXPECT_GT(cos_out, 0.0);
      const LightLePdf pdf = pdf_le(light, bounds, le->ray.direction, le->normal);
      EXPECT_DOUBLE_EQ(pdf.pos, le->pdf_pos);
      EXPECT_NEAR(pdf.dir, le->pdf_dir, 1e-12);
      EXPECT_DOUBLE_EQ(le->pdf_pos, 1.0 / (4.0 * kPi * sphere.radius_m * sphere.radius_m));
      mean_cos_over_pdf += cos_out / le->pdf_dir;
      mean_normal_x += le->normal.x;
    }
  EXPECT_NEAR(mean_cos_over_pdf / (kStrata * kStrata), kPi, 1e-9);
  EXPECT_NEAR(mean_normal_x / (kStrata * kStrata), 0.0, 1e-3);  // uniform over the sphere
  EXPECT_NEAR(power(light, bounds, [](int) { return 2.0; }), kPi * 4.0 * kPi * 0.0625 * 2.0, 1e-12);
}

// pdf_point, the density per m² of the point sample_li draws (integrators/manifold.h goes on from
// that point through refracting faces, and the walks weigh themselves against it): over the
// sphere it integrates to 1 (the cone's points, each counted once; a far side counted too, or the
// cone's density left per steradian, would not), it is the cone's density times cos θ_q / d² at
// the points sample_li draws and 0 on the far side; on a one-sided triangle 1/A in front, 0 behind.
TEST(SphereLight, ThePointDensityIsTheConesPerSquareMetre) {
  const Vec3 centre{0.1, 0.2, -0.3};
  const Light light = SphereLight{0, centre, 0.05, 0};
  const Vec3 p = centre + normalize(Vec3{0.3, -0.5, 0.8}) * 0.2;
  // ∫ pdf_point dA over the sphere, by a midpoint rule in (cos θ, φ) (area element r² dcos θ dφ).
  constexpr int kSteps = 800;
  double integral = 0.0;
  for (int i = 0; i < kSteps; ++i)
    for (int j = 0; j < kSteps; ++j) {
      const double mu = -1.0 + 2.0 * (i + 0.5) / kSteps, phi = 2.0 * kPi * (j + 0.5) / kSteps;
      const double r = std::sqrt(1.0 - mu * mu);
      const Vec3 q = centre + Vec3{r * std::cos(phi), r * std::sin(phi), mu} * 0.05;
      integral += pdf_point(light, p, q) * 0.05 * 0.05 * (2.0 / kSteps) * (2.0 * kPi / kSteps);
    }
  EXPECT_NEAR(integral, 1.0, 2e-3);
  for (const double u : {0.1, 0.5, 0.9}) {
    const auto li = sample_li(light, p, u, 1.0 - u);
    ASSERT_TRUE(li);
    const Vec3 q = p + li->wi * li->distance_m;
    const double cos_q = -dot(normalize(q - centre), li->wi);
    EXPECT_NEAR(pdf_point(light, p, q) / (li->pdf * cos_q / (li->distance_m * li->distance_m)), 1.0, 1e-9);
    EXPECT_EQ(pdf_point(light, p, centre * 2.0 - q), 0.0);  // the point opposite: the far side
  }
  AreaLight a;
  a.p0 = Vec3{0, 0, 0}, a.p1 = Vec3{1, 0, 0}, a.p2 = Vec3{0, 2, 0}, a.normal = Vec3{0, 0, 1}, a.area_m2 = 1.0;
  const Vec3 on{0.2, 0.3, 0.0};
  EXPECT_DOUBLE_EQ(pdf_point(a, Vec3{0.5, 0.5, 1.0}, on), 1.0);
  EXPECT_EQ(pdf_point(a, Vec3{0.5, 0.5, -1.0}, on), 0.0);
  a.two_sided = true;
  EXPECT_DOUBLE_EQ(pdf_point(a, Vec3{0.5, 0.5, -1.0}, on), 1.0);
}

}  // namespace
}  // namespace bouguer
