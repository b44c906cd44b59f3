// Next-event estimation through a flat interface (integrators/manifold.h): a point lamp under a flat
// water surface lights a diffuse ceiling above it only along refracted paths, which the path tracer
// now reaches by solving Snell's law on the plane. The closed form: a ray leaving the lamp (depth d)
// at α from the vertical meets the surface at d·tan α, leaves at β (sin β = n·sin α) and meets the
// ceiling (height h) at R(α) = d·tan α + h·tan β; the ray tube gives the ceiling the irradiance
//   E(R) = T(α)·I·sin α / (R·dR/dα),   dR/dα = d/cos²α + h·n·cos α/cos³β,
// T the Fresnel transmittance from water to air, so the ceiling of reflectance ρ shows ρ·E/π (on
// the axis: T·I/(d + n·h)², the lamp's image at the apparent depth d/n). That is the direct light
// (max_depth 1): beyond it the ceiling also sees itself in the water (R ≈ 2 %: the mean read
// 1.005 with it, pixels up to 6 % off with its noise), and light reflected inside the water.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "bouguer/integrators/manifold.h"
#include "bouguer/materials/fresnel.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

constexpr double kDepth_m = 0.05, kCeiling_m = 0.1, kN = 1.33, kRho = 0.8, kScale = 0.01, kView_m = 0.12;
constexpr int kPixels = 16;

std::string water_scene(const char* integrator, int spp) {
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0.05, 0], "look_at": [0, 1, 0], "up": [0, 0, -1],
               "width": {}, "resolution": [{}, {}]}},
    "render": {{"integrator": "{}", "spectral": "full", "spp": {}, "max_depth": 1, "seed": 5}},
    "world_medium": "vacuum",
    "media": {{"water": {{"ior": {}}}}},
    "objects": [
      {{"name": "water", "shape": {{"type": "box", "size": [2, 0.2, 2]}}, "transform": [{{"translate": [0, -0.1, 0]}}],
        "inside": "water"}},
      {{"name": "ceiling", "shape": {{"type": "quad", "size": [0.4, 0.4]}},
        "transform": [{{"rotate_deg": [90, [1, 0, 0]]}}, {{"translate": [0, {}, 0]}}],
        "material": {{"type": "diffuse", "reflectance": {}}}}}
    ],
    "lights": [{{"type": "point", "position": [0, {}, 0], "spectrum": "D65", "scale": {}}}],
    "background": {{"spectrum": "E", "scale": 0}}
  }})",
                     kView_m, kPixels, kPixels, integrator, spp, kN, kCeiling_m, kRho, -kDepth_m, kScale);
}

// The ceiling's radiance at distance r from the axis (D65 at Y = 1 is linear sRGB (1, 1, 1)).
double ceiling_radiance(double r) {
  auto reach = [](double a) {
    const double sin_b = kN * std::sin(a);
    return kDepth_m * std::tan(a) + kCeiling_m * sin_b / std::sqrt(1.0 - sin_b * sin_b);
  };
  double lo = 0.0, hi = std::asin(1.0 / kN) * (1.0 - 1e-9);
  for (int i = 0; i < 200; ++i) ((reach(0.5 * (lo + hi)) < r) ? lo : hi) = 0.5 * (lo + hi);
  const double a = 0.5 * (lo + hi), sin_b = kN * std::sin(a), cos_b = std::sqrt(1.0 - sin_b * sin_b);
  const double cos_a = std::cos(a);
  const double dr = kDepth_m / (cos_a * cos_a) + kCeiling_m * kN * cos_a / (cos_b * cos_b * cos_b);
  const double t = 1.0 - fresnel_dielectric(cos_a, cos_b, kN, 1.0);
  const double e = r > 1e-12 ? t * kScale * std::sin(a) / (r * dr)
                             : t * kScale / ((kDepth_m + kN * kCeiling_m) * (kDepth_m + kN * kCeiling_m));
  return kRho * e / std::numbers::pi;
}

// Every pixel within 0.3 % of the closed form averaged over its footprint (8 × 8 points), and
// their mean within 0.05 %: the path tracer's next-event estimation of a point lamp draws no
// random number but the pixel position (64 jittered strata), so only the footprint's variation
// is left. A missing Fresnel factor (2 % on the axis), a radiance scaled by n² across the surface
// (77 %), a ray tube taken at the straight line's distance (the lamp's image at depth d instead of
// d/n: 27 % on the axis) or no light at all (before: the shadow ray stopped at the water) fails.
TEST(ManifoldNextEvent, PointLampUnderFlatWaterLightsTheCeilingAsTheClosedFormSays) {
  const Film film = test::render_text(water_scene("path", 64));
  const double pixel_m = kView_m / kPixels;
  double worst = 0.0, sum = 0.0;
  for (int j = 0; j < kPixels; ++j)
    for (int i = 0; i < kPixels; ++i) {
      double expected = 0.0;
      constexpr int kSub = 8;
      for (int a = 0; a < kSub; ++a)
        for (int b = 0; b < kSub; ++b) {
          const double x = -0.5 * kView_m + (i + (a + 0.5) / kSub) * pixel_m;
          const double z = -0.5 * kView_m + (j + (b + 0.5) / kSub) * pixel_m;
          expected += ceiling_radiance(std::hypot(x, z));
        }
      expected /= kSub * kSub;
      for (int c = 0; c < 3; ++c) {
        const double ratio = film.rgb_at(i, j)[c] / expected;
        worst = std::max(worst, std::abs(ratio - 1.0));
        sum += ratio;
      }
    }
  const double mean = sum / (3.0 * kPixels * kPixels);
  std::printf("point lamp under flat water: ceiling / closed form, mean %.5f, worst pixel %.2e (axis %.4g)\n", mean,
              worst, ceiling_radiance(0.0));
  EXPECT_LT(worst, 0.003);
  EXPECT_NEAR(mean, 1.0, 0.0005);
}

// The plane's solution itself: Snell's law holds at the point found, to 1e-12, for random points
// on both sides and both orders of the indices.
TEST(ManifoldNextEvent, TheRefractionPointObeysSnellsLaw) {
  const Vec3 n = normalize(Vec3{0.2, 1.0, -0.3}), on_plane{0.1, -0.2, 0.05};
  double worst = 0.0;
  for (int k = 0; k < 200; ++k) {
    const double u = 0.618034 * k - std::floor(0.618034 * k), v = 0.414214 * k - std::floor(0.414214 * k);
    auto along_plane = [&](const Vec3& d) { return d - n * dot(d, n); };
    const Vec3 x = on_plane + n * (0.01 + 0.3 * u) + along_plane({0.3 * v - 0.15, 0.0, 0.2 * u - 0.1});
    const Vec3 p = on_plane - n * (0.02 + 0.1 * v) + along_plane({0.1 * u, 0.05, -0.2 * v});
    for (const auto& [ex, ep] : {std::pair{1.0, 1.33}, std::pair{1.5, 1.0}}) {
      const auto y = refraction_point(x, p, on_plane, n, ex, ep);
      ASSERT_TRUE(y);
      EXPECT_NEAR(dot(*y - on_plane, n), 0.0, 1e-12);
      const Vec3 a = normalize(*y - x), b = normalize(p - *y);
      const double sin_a = length(cross(a, n)), sin_b = length(cross(b, n));
      worst = std::max(worst, std::abs(ex * sin_a - ep * sin_b));
      // In the plane of incidence: x, y, p and the normal coplanar.
      EXPECT_NEAR(dot(cross(a, b), n), 0.0, 1e-9);
    }
  }
  EXPECT_LT(worst, 1e-12);
  EXPECT_FALSE(refraction_point(Vec3{0, 1, 0}, Vec3{0, 2, 0}, Vec3{}, Vec3{0, 1, 0}, 1.0, 1.33));  // one side
}

}  // namespace
}  // namespace bouguer
