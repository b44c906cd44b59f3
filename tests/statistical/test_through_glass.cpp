// Next-event estimation through smooth interfaces at surfaces (#20; integrators/events.h:
// surface_exit_guide): a surface's sample of the environment map goes on through the glass that
// blocks it, weighted against the walk's own directions that leave the same way. Checked by a
// furnace (every pixel exactly the background) and, under the studio map, against the image
// without it (the same expectation, less noise), in full and hero, with plain and dispersive glass.
// Also next-event estimation out of an index-matched absorber, which its second reading found.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <string>

#include "bouguer/io/image_io.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;
using test::Estimate;

// A diffuse ball inside an empty glass cup, beside a tumbler of red wine, under the map
// `environment` (no floor: the map is all around). The cup's wall stands between the ball and most
// of the map, and the camera sees the ball through it and past the wine.
std::string cup_scene(const fs::path& environment, double reflectance, const char* cup_ior, const char* exit_guide,
                      const char* spectral, int spp, std::uint64_t seed,
                      const char* liquid = R"({"absorption": {"library": "red-wine"}})") {
  return fmt::format(R"({{
    "camera": {{"position": [0, "60 mm", "150 mm"], "look_at": [0, "30 mm", 0], "fov_deg": 30, "resolution": [24, 24]}},
    "render": {{"integrator": "path", "spectral": "{}", "spp": {}, "seed": {}, "max_depth": 200, "exit_guide": {}}},
    "world_medium": "vacuum",
    "media": {{"cup": {{"ior": {}}}, "glass": {{"ior": 1.5}}, "liquid": {}}},
    "objects": [
      {{"name": "cup", "shape": {{"type": "vessel", "wall": "3 mm", "segments": 64,
                 "profile": [[0, 0], ["30 mm", 0], ["32 mm", "3 mm"], ["34 mm", "60 mm"]]}}, "inside": "cup"}},
      {{"name": "ball", "shape": {{"type": "sphere", "radius": "15 mm"}}, "transform": [{{"translate": [0, "25 mm", 0]}}],
       "material": {{"type": "diffuse", "reflectance": {}}}}},
      {{"name": "wine", "shape": {{"type": "vessel", "wall": "2 mm", "fill": 0.7, "segments": 48,
                 "profile": [[0, 0], ["15 mm", 0], ["16 mm", "2 mm"], ["17 mm", "50 mm"]]}},
       "transform": [{{"translate": ["45 mm", 0, "-30 mm"]}}], "inside": "glass", "contents": "liquid"}}
    ],
    "background": {{"environment": "{}"}}
  }})",
                     spectral, spp, seed, exit_guide, cup_ior, liquid, reflectance, environment.string());
}

// A diffuse ball under dilute red wine in a glass tumbler: the medium that the ball's samples of
// the map leave into only absorbs, so without glass around it they would get nothing (an infinite
// path), and with the guide they go on through the liquid's surface or the glass.
std::string immersed_scene(const fs::path& environment, const char* glass_ior, const char* exit_guide,
                           const char* spectral, int spp) {
  return fmt::format(R"({{
    "camera": {{"position": [0, "60 mm", "150 mm"], "look_at": [0, "20 mm", 0], "fov_deg": 30, "resolution": [24, 24]}},
    "render": {{"integrator": "path", "spectral": "{}", "spp": {}, "seed": 1, "max_depth": 200, "exit_guide": {}}},
    "world_medium": "vacuum",
    "media": {{"glass": {{"ior": {}}}, "liquid": {{"absorption": {{"library": "red-wine", "concentration": 0.05}}}}}},
    "objects": [
      {{"name": "tumbler", "shape": {{"type": "vessel", "wall": "3 mm", "fill": 0.8, "segments": 64,
                 "profile": [[0, 0], ["30 mm", 0], ["32 mm", "3 mm"], ["34 mm", "60 mm"]]}},
       "inside": "glass", "contents": "liquid"}},
      {{"name": "ball", "shape": {{"type": "sphere", "radius": "12 mm"}}, "transform": [{{"translate": [0, "18 mm", 0]}}],
       "material": {{"type": "diffuse", "reflectance": 0.8}}}}
    ],
    "background": {{"environment": "{}"}}
  }})",
                     spectral, spp, exit_guide, glass_ior, environment.string());
}

Film render(const std::string& json) { return test::render_desc(parse_scene(json, "cup.json")); }

// The guide's image and the unguided one have the same mean, pixel by pixel: the mean difference
// within 4 of its standard errors (from the pixels' differences: they are independent), and that
// standard error under `cap` of the unguided image's mean, so that a guide whose weight against
// the walk's own directions does not sum to 1, or whose pdf is off, by more than 4 caps on the
// image fails. The caps are what 256 spp give (measured: 0.7–1.7 % with plain glass, 3–4 % with
// dense flint, whose paths that keep one wavelength are the noisy ones).
void expect_same_expectation(const Film& off, const Film& on, const std::string& what, double cap) {
  for (int c = 0; c < 3; ++c) {
    const Estimate d = test::difference_estimate(off, on, c);
    const double mean = test::channel_estimate(off, c, 0, 0, off.width, off.height).mean;
    std::printf("surface exit guide, %s, ch %d: on − off %.5f ± %.5f (%.2f %% of %.5f)\n", what.c_str(), c, d.mean,
                d.standard_error, 100.0 * d.standard_error / mean, mean);
    EXPECT_LT(std::abs(d.mean), 4.0 * d.standard_error + 1e-6) << what << " ch " << c;
    EXPECT_LT(d.standard_error, cap * mean) << what << " ch " << c << ": too noisy for the cap";
  }
}

// Under a uniform white map a lossless scene is a furnace (clear water in the tumbler): the ball
// (albedo 1) inside the cup and everything seen through the glass has the background's radiance,
// linear sRGB (1, 1, 1). With the
// guide forced on (the map's contrast is 1, where it would stay off), the ball's samples of the map
// go on through the cup's wall, and the walk's own directions through it are weighted against
// them: a weight that did not sum to 1 with the other strategy's would show here. 64 spp, 24 × 24:
// a standard error of about 0.0005 a channel, 0.2 s a mode. (With the guide and without it, the
// image is 0.1 % below the map seen directly at 1024 spp: a loss of the scene's, not the guide's.)
TEST(SurfaceExitGuide, WhiteFurnaceThroughAGlassCup) {
  const fs::path dir = test::scratch_dir("surface_exit_guide_furnace");
  Film white(16, 8);
  std::fill(white.rgb.begin(), white.rgb.end(), 1.0f);
  write_pfm(dir / "white.pfm", white);
  for (const char* spectral : {"full", "hero"}) {
    const char* water = R"({"ior": 1.33})";
    const Film on = render(cup_scene(dir / "white.pfm", 1.0, "1.5", "true", spectral, 64, 1, water));
    for (int c = 0; c < 3; ++c) {
      const Estimate e = test::channel_estimate(on, c, 0, 0, on.width, on.height);
      std::printf("surface exit guide furnace (%s) ch %d: %.5f ± %.5f\n", spectral, c, e.mean, e.standard_error);
      EXPECT_NEAR(e.mean, 1.0, 0.005) << spectral << " ch " << c;
      EXPECT_LT(3.0 * e.standard_error, 0.005) << spectral << " ch " << c;
    }
    const Film off = render(cup_scene(dir / "white.pfm", 1.0, "1.5", "false", spectral, 64, 1, water));
    EXPECT_NE(std::memcmp(on.rgb.data(), off.rgb.data(), on.rgb.size() * sizeof(float)), 0) << "the guide did not run";
  }
}

// Under the studio map (contrast 12: the guide's own default), the image with the guide has the
// expectation of the image without it, pixel by pixel: the mean of the pixels' differences is
// within 4 of its standard errors (the pixels are independent estimates), in full and hero, with a
// cup of plain glass and one of dispersive flint (N-SF11: a path that keeps one wavelength at it is
// not the guide's, and the guide stops there while the path carries several). And it removes most
// of the noise on the ball: the variance between two seeds is less than half of the unguided
// one's (measured: a quarter in full, a fifth in hero). The same agreement for a ball under
// dilute wine in a tumbler, whose samples of the map leave into a medium that only absorbs (they
// were skipped before they could reach the glass: 7 standard errors dark in red at 256 spp).
// (The plain glass here, the dispersive flint in SurfaceExitGuideLong: about 4 s on an idle core.)
void expect_exit_guide_same_expectation_less_noise(const char* cup) {
  const fs::path studio = fs::path(BOUGUER_SOURCE_DIR) / "scenes/examples/studio.pfm";
  for (const char* spectral : {"full", "hero"}) {
    const int spp = 256;
    const Film on = render(cup_scene(studio, 0.8, cup, "true", spectral, spp, 1));
    const Film off = render(cup_scene(studio, 0.8, cup, "false", spectral, spp, 1));
    const double cap = std::string(cup) == "1.5" ? 0.02 : 0.05;
    expect_same_expectation(off, on, fmt::format("cup {}, {}", cup, spectral), cap);
    expect_same_expectation(render(immersed_scene(studio, cup, "false", spectral, spp)),
                            render(immersed_scene(studio, cup, "true", spectral, spp)),
                            fmt::format("immersed, glass {}, {}", cup, spectral), cap);
    if (std::string(cup) != "1.5") continue;
    const Film on2 = render(cup_scene(studio, 0.8, cup, "true", spectral, spp, 2));
    const Film off2 = render(cup_scene(studio, 0.8, cup, "false", spectral, spp, 2));
    // (The standard error of the mean difference between two seeds: the pixels' noise over √n.)
    const double spread_on = test::difference_estimate(on, on2, 1).standard_error,
                 spread_off = test::difference_estimate(off, off2, 1).standard_error;
    std::printf("surface exit guide, %s: seed-to-seed spread %.5f with, %.5f without\n", spectral, spread_on,
                spread_off);
    EXPECT_LT(spread_on * spread_on, 0.5 * spread_off * spread_off) << spectral;
  }
}

TEST(SurfaceExitGuide, SameExpectationLessNoiseUnderTheStudioMap) {
  expect_exit_guide_same_expectation_less_noise("1.5");
}

TEST(SurfaceExitGuideLong, SameExpectationLessNoiseUnderTheStudioMap) {
  expect_exit_guide_same_expectation_less_noise(R"({"library": "N-SF11"})");
}

// Next-event estimation from a surface inside a medium that only absorbs, bounded by an
// index-matched sphere: its samples of the map leave the medium without a refraction, as the walk's
// own directions do. They were skipped (an infinite path through an absorber gets nothing), so the
// walk's share weighted against them was all that was left: with σ_a = 1e-6 per m, a ball 72 %
// darker than in the same sphere without absorption. Now the two images agree to float rounding
// (the same random numbers; the absorption takes 1e-7 of the light), guided or not.
TEST(NextEventEstimation, LeavesAnIndexMatchedAbsorber) {
  const fs::path studio = fs::path(BOUGUER_SOURCE_DIR) / "scenes/examples/studio.pfm";
  auto scene = [&](const char* medium, const char* exit_guide) {
    return fmt::format(R"({{
      "camera": {{"position": [0, 0, "150 mm"], "look_at": [0, 0, 0], "fov_deg": 20, "resolution": [16, 16]}},
      "render": {{"integrator": "path", "spectral": "full", "spp": 32, "seed": 1, "max_depth": 50, "exit_guide": {}}},
      "world_medium": "vacuum",
      "media": {{"tint": {}}},
      "objects": [
        {{"name": "tint", "shape": {{"type": "sphere", "radius": "40 mm"}}, "inside": "tint"}},
        {{"name": "ball", "shape": {{"type": "sphere", "radius": "15 mm"}}, "material": {{"type": "diffuse", "reflectance": 0.8}}}}
      ],
      "background": {{"environment": "{}"}}
    }})",
                       exit_guide, medium, studio.string());
  };
  const char* tinted = R"({"ior": 1.0, "absorption": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700], "value": [1e-6, 1e-6]}})";
  for (const char* guide : {"false", "true"}) {
    const Film a = render(scene(tinted, guide)), b = render(scene(R"({"ior": 1.0})", guide));
    for (int c = 0; c < 3; ++c) {
      const double ta = test::channel_estimate(a, c, 0, 0, a.width, a.height).mean,
                   tb = test::channel_estimate(b, c, 0, 0, b.width, b.height).mean;
      std::printf("index-matched absorber (guide %s) ch %d: %.6f against %.6f without absorption\n", guide, c, ta, tb);
      EXPECT_NEAR(ta / tb, 1.0, 1e-4) << "guide " << guide << " ch " << c;
    }
  }
}

}  // namespace
}  // namespace bouguer
