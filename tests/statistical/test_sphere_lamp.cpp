// A diffuse floor under an emitting sphere (lights/light.h: SphereLight, sampled by the cone it
// subtends), against the closed form: a sphere of radiance L wholly above a plane gives it the
// irradiance π·L·sin²θmax·cos β = π·L·r²·h / D³ (D the distance to the centre, h its height), so
// the floor of reflectance ρ shows the radiance ρ·L·r²·h / D³. Every estimator reaches it its own
// way: the path tracer by the cone and by BSDF directions that meet the sphere (weighted against
// each other with pdf_li), the light tracer by points drawn on the sphere and cosine directions
// (sample_le), bdpt and vcm by both and by their weights' densities (pdf_le, pdf_light_origin).
// A density off by a constant, a cone sampled where pdf_li reports another, a weight that
// mixes the cone's density with the area's, or the tessellated lamp's smaller area, moves the
// floor's mean by more than the tolerance.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <vector>

#include "bouguer/render/film.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

constexpr double kHeight_m = 0.1, kWidth_m = 0.4, kReflectance = 0.8;
constexpr int kPixels = 24;

// An orthographic camera looking straight down on the floor, the lamp above its middle (so the
// image is symmetric and its orientation does not matter), D65 (linear sRGB (1, 1, 1) at Y = 1)
// at `scale`.
std::string lamp_scene(const char* integrator, int spp, std::uint64_t seed, double radius_m, double scale) {
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 1, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
               "width": {}, "resolution": [{}, {}]}},
    "render": {{"integrator": "{}", "spectral": "full", "spp": {}, "max_depth": 4, "seed": {}}},
    "world_medium": "vacuum",
    "objects": [
      {{"name": "floor", "shape": {{"type": "quad", "size": [1, 1]}}, "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}],
        "material": {{"type": "diffuse", "reflectance": {}}}}},
      {{"name": "lamp", "shape": {{"type": "sphere", "radius": {}}}, "transform": [{{"translate": [0, {}, 0]}}],
        "emission": {{"spectrum": "D65", "scale": {}}}}}
    ],
    "background": {{"spectrum": "E", "scale": 0}}
  }})",
                     kWidth_m, kPixels, kPixels, integrator, spp, seed, kReflectance, radius_m, kHeight_m, scale);
}

// The closed form's mean over pixel (i, j)'s footprint (the film's box filter), on a 16 × 16 grid.
double expected_pixel(int i, int j, double radius_m, double scale) {
  const double pixel_m = kWidth_m / kPixels;
  constexpr int kSub = 16;
  double sum = 0.0;
  for (int a = 0; a < kSub; ++a)
    for (int b = 0; b < kSub; ++b) {
      const double x = -0.5 * kWidth_m + (i + (a + 0.5) / kSub) * pixel_m;
      const double z = -0.5 * kWidth_m + (j + (b + 0.5) / kSub) * pixel_m;
      const double d = std::sqrt(x * x + z * z + kHeight_m * kHeight_m);
      sum += kReflectance * scale * radius_m * radius_m * kHeight_m / (d * d * d);
    }
  return sum / (kSub * kSub);
}

// One render's ratio to the closed form per channel: the mean over the pixels that see only the
// floor (the middle 2 × 2 see the lamp) of pixel / expected, and its standard error from their
// spread (independent pixels).
std::array<test::Estimate, 3> floor_ratio(const Film& f, double radius_m, double scale) {
  std::array<test::Estimate, 3> out;
  for (int c = 0; c < 3; ++c) {
    std::vector<double> ratios;
    for (int j = 0; j < kPixels; ++j)
      for (int i = 0; i < kPixels; ++i) {
        if ((i == kPixels / 2 - 1 || i == kPixels / 2) && (j == kPixels / 2 - 1 || j == kPixels / 2)) continue;
        ratios.push_back(f.rgb_at(i, j)[c] / expected_pixel(i, j, radius_m, scale));
      }
    out[static_cast<std::size_t>(c)] = test::mean_estimate(ratios);
  }
  return out;
}

// Within 4 standard errors of 1 and 0.1 % (D65 at Y = 1 is linear sRGB (1, 1, 1) within 0.05 % a
// channel through full mode's bins: the path tracer reads 1.0002, 1.0000, 0.9996 at both sizes),
// the standard error below 0.3 %: a 2 % bias fails. vcm's pixels share each iteration's photons,
// so its error comes from 16 seeds' mean ratios.
void expect_closed_form(const char* integrator, int spp, double radius_m, double scale) {
  std::array<test::Estimate, 3> e;
  if (std::string(integrator) == "vcm") {
    constexpr int kSeeds = 16;
    const std::vector<Film> films = test::render_seeds(
        parse_scene(lamp_scene(integrator, spp / kSeeds, 1, radius_m, scale), "lamp.json"), kSeeds, 1);
    for (int c = 0; c < 3; ++c) {
      std::vector<double> means;
      for (const Film& f : films) means.push_back(floor_ratio(f, radius_m, scale)[static_cast<std::size_t>(c)].mean);
      e[static_cast<std::size_t>(c)] = test::mean_estimate(means);
    }
  } else {
    e = floor_ratio(test::render_text(lamp_scene(integrator, spp, 1, radius_m, scale)), radius_m, scale);
  }
  for (int c = 0; c < 3; ++c) {
    const test::Estimate& r = e[static_cast<std::size_t>(c)];
    std::printf("sphere lamp r %.0f mm, %s %d spp, ch %d: floor / closed form %.5f ± %.5f\n", radius_m * 1000,
                integrator, spp, c, r.mean, r.standard_error);
    EXPECT_LT(r.standard_error, 0.003) << integrator << ": too noisy for the tolerance";
    EXPECT_NEAR(r.mean, 1.0, 4.0 * r.standard_error + 0.001) << integrator << " ch " << c;
  }
}

// A 5 mm lamp 100 mm above the floor (θmax 2.9°) and a 2 mm one (1.1°: where pbrt-v4 takes 1 − cos
// θmax from its Taylor term).
TEST(SphereLamp, PathTracerLightsTheFloorAsTheClosedFormSays) {
  expect_closed_form("path", 16, 0.005, 400.0);
  expect_closed_form("path", 16, 0.002, 2500.0);
}
TEST(SphereLamp, LightTracerLightsTheFloorAsTheClosedFormSays) { expect_closed_form("light", 1536, 0.005, 400.0); }
TEST(SphereLamp, BidirectionalLightsTheFloorAsTheClosedFormSays) { expect_closed_form("bdpt", 128, 0.005, 400.0); }
TEST(SphereLamp, VertexMergingLightsTheFloorAsTheClosedFormSays) { expect_closed_form("vcm", 1024, 0.005, 400.0); }

// #37's hard region: the caustic and the shadow a red glass ball casts under a 5 mm spherical lamp
// (test::red_ball_from_above: the lamp beside the ball, the floor seen from above). Each estimator
// reaches that light its own way: the path tracer by its connections through the sphere
// (integrators/manifold.h) and walks that refract onto the lamp, the light tracer by splats of
// paths refracted through the ball, bdpt by those and its camera paths that meet the lamp through
// the glass, vcm by merges as well. Their red channel's mean over the caustic (10 × 7 pixels) and
// over the shadow beyond it (14 × 15 pixels, lit only by light the glass let through) must agree
// pairwise within 4 standard errors, each from 8 seeds' spread (bdpt's and vcm's caustic is
// heavy-tailed: 4 seeds understated it 5-fold), each below 3 % of the mean so that a
// disagreement of 17 % (what #37 saw against another renderer) or a path tracer's lamp made 10 %
// brighter in this scene alone fails. vcm is consistent, not unbiased: at 256 iterations its radius
// (0.5 mm) is a quarter of a pixel.
TEST(SphereLampLong, EveryEstimatorAgreesOnTheCausticAndTheShadowUnderARedBall) {
  struct Region {
    const char* name;
    int x0, x1, y0, y1;
  };
  const Region regions[] = {{"caustic", 24, 34, 24, 31}, {"shadow", 34, 48, 33, 48}};
  struct Run {
    const char* integrator;
    int spp;
  };
  const Run runs[] = {{"path", 32}, {"light", 512}, {"bdpt", 256}, {"vcm", 256}};
  constexpr int kSeeds = 8;
  std::vector<std::array<test::Estimate, 2>> found;
  for (const Run& r : runs) {
    SceneDesc desc = parse_scene(test::red_ball_from_above(r.integrator), "red_ball.json");
    desc.render.spp = r.spp;
    const std::vector<Film> films = test::render_seeds(desc, kSeeds, 1);
    std::array<test::Estimate, 2> e;
    for (std::size_t k = 0; k < 2; ++k) {
      const Region& g = regions[k];
      std::vector<double> means;
      for (const Film& f : films) means.push_back(test::channel_estimate(f, 0, g.x0, g.y0, g.x1, g.y1).mean);
      e[k] = test::mean_estimate(means);
      std::printf("red ball, %s %d spp x %d seeds, %s: red %.5f ± %.5f\n", r.integrator, r.spp, kSeeds, g.name,
                  e[k].mean, e[k].standard_error);
      EXPECT_LT(e[k].standard_error, 0.03 * e[k].mean) << r.integrator << ", " << g.name << ": too noisy";
    }
    found.push_back(e);
  }
  for (std::size_t a = 0; a < found.size(); ++a)
    for (std::size_t b = a + 1; b < found.size(); ++b)
      for (std::size_t k = 0; k < 2; ++k) {
        const test::Estimate &ea = found[a][k], &eb = found[b][k];
        const double se = std::sqrt(ea.standard_error * ea.standard_error + eb.standard_error * eb.standard_error);
        EXPECT_NEAR(ea.mean, eb.mean, 4.0 * se) << runs[a].integrator << " against " << runs[b].integrator << ", "
                                                << regions[k].name;
      }
}

}  // namespace
}  // namespace bouguer
