// The bidirectional estimator (#17) converges where the path tracer does, to the same image, and
// reaches what the path tracer cannot: light from a point or spot lamp into a liquid inside glass.
// Each statistical check states its tolerance and also requires it to be at least 3 standard
// errors, so it can fail.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <array>
#include <cmath>
#include <numbers>
#include <span>

#include "bouguer/integrators/bidirectional.h"
#include "bouguer/integrators/integrators.h"
#include "bouguer/render/compare.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/integrators/walk.h"
#include "bouguer/io/image_io.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "support/mis_check.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

Film render(SceneDesc desc, IntegratorType integrator, SpectralMode mode, int spp, std::uint64_t seed) {
  desc.render.integrator = integrator;
  desc.render.spectral = mode;
  desc.render.spp = spp;
  desc.render.seed = seed;
  return test::render_desc(desc);
}

// The diffuse room of #10 (bounces up to 8; each wall's light arrives by every strategy). Long
// (20 s idle, 114 s on 2 cores under a load of 18): each estimator's expectation on a diffuse and
// caustic scene is pinned in `make test` by tests/regression/test_estimators.cpp.
TEST(BidirectionalLong, ConvergesToThePathTracerInADiffuseRoom) {
  SceneDesc desc = parse_scene(test::room_scene("path", 1, 1), "room.json");
  desc.render.max_depth = 8;
  desc.render.merge_radius_m = 0.02;  // vcm: two pixel footprints of this 12×12 image would be 0.4 m
  const Film path = render(desc, IntegratorType::path, SpectralMode::full, 8192, 1);
  for (const auto& [integrator, spp] : {std::pair{IntegratorType::bdpt, 2048}, std::pair{IntegratorType::vcm, 2048}}) {
    const Film bdpt = render(desc, integrator, SpectralMode::full, spp, 2);
    const ImageDifference d = compare_images(path, bdpt);
    const char* name = integrator_info(integrator).name.data();
    std::printf("diffuse room, %s (%d spp) vs path (8192 spp): mean ΔE00 %.3f, p95 %.3f\n", name, spp, d.mean, d.p95);
    EXPECT_LT(d.mean, 0.3) << name;
    for (int c = 0; c < 3; ++c) {
      const auto p = test::channel_estimate(path, c, 0, 0, path.width, path.height);
      const auto b = test::channel_estimate(bdpt, c, 0, 0, bdpt.width, bdpt.height);
      EXPECT_NEAR(b.mean, p.mean, 0.01 * p.mean) << name << " ch " << c;
    }
  }
}

// The red glass ball's caustic on a white floor under a small lamp: every floor pixel, the
// caustic and the floor seen through the glass included. Long, as the diffuse room.
TEST(BidirectionalLong, ConvergesToThePathTracerOnACausticFloor) {
  SceneDesc desc = parse_scene(test::caustic_scene("path", 1, 1), "caustic.json");
  desc.render.merge_radius_m = 0.003;  // vcm: the floor's caustic is sharper than two footprints of this image
  const Film path = render(desc, IntegratorType::path, SpectralMode::full, 8192, 1);
  for (const auto& [integrator, spp] : {std::pair{IntegratorType::bdpt, 2048}, std::pair{IntegratorType::vcm, 2048}}) {
    const Film bdpt = render(desc, integrator, SpectralMode::full, spp, 2);
    const ImageDifference d = compare_images(path, bdpt);
    const char* name = integrator_info(integrator).name.data();
    std::printf("caustic floor, %s (%d spp) vs path (8192 spp): mean ΔE00 %.3f, p95 %.3f\n", name, spp, d.mean, d.p95);
    EXPECT_LT(d.mean, 0.3) << name;
  }
}

// The same floor under a dispersive ball (N-SF11): a bidirectional sample keeps one wavelength
// from its start in such a scene. The image means per channel agree within 4 standard errors of
// the mean pixel difference (the pixels are independent, so their differences' spread measures the
// noise of both renders), and that standard error must stay under `cap` of the path tracer's mean:
// a bias of 4 caps or more (a lost or doubled dispersion pdf, a kept wavelength weighted as if all
// four were carried) fails. Measured: 0.4–0.8 % at path 8192, bdpt 4096, vcm 2048 spp (the `long`
// test, cap 0.8 %), √2 times that at half the samples (cap 1.2 %). The regressions of
// tests/regression/test_estimators.cpp see smaller biases, without dispersion.
void expect_like_the_path_tracer_under_a_dispersive_ball(int path_spp, int bdpt_spp, int vcm_spp, double cap) {
  std::string json = test::caustic_scene("path", 1, 1);
  const std::string red = R"("red": {"absorption": {"library": "red-glass", "concentration": 0.3}})";
  ASSERT_NE(json.find(red), std::string::npos);
  json.replace(json.find(red), red.size(), R"("red": {"ior": {"library": "N-SF11"}})");
  SceneDesc desc = parse_scene(json, "dispersive.json");
  desc.render.merge_radius_m = 0.003;  // as on the caustic floor
  ASSERT_TRUE(compile(desc).dispersive);
  const Film path = render(desc, IntegratorType::path, SpectralMode::full, path_spp, 1);
  for (const auto& [integrator, spp] : {std::pair{IntegratorType::bdpt, bdpt_spp}, std::pair{IntegratorType::vcm, vcm_spp}}) {
    const Film f = render(desc, integrator, SpectralMode::full, spp, 2);
    const char* name = integrator_info(integrator).name.data();
    for (int c = 0; c < 3; ++c) {
      const double p = test::channel_estimate(path, c, 0, 0, path.width, path.height).mean;
      const auto d = test::difference_estimate(path, f, c);
      std::printf("dispersive ball, ch %d: path %.5f, %s − path %+.5f ± %.5f\n", c, p, name, d.mean, d.standard_error);
      EXPECT_LT(std::abs(d.mean), 4.0 * d.standard_error) << name << " ch " << c;
      EXPECT_LT(d.standard_error, cap * p) << name << " ch " << c << ": too noisy for the cap";
    }
  }
}

TEST(Bidirectional, ConvergesToThePathTracerUnderADispersiveBall) {
  expect_like_the_path_tracer_under_a_dispersive_ball(4096, 2048, 1024, 0.012);
}

TEST(BidirectionalLong, ConvergesToThePathTracerUnderADispersiveBall) {
  expect_like_the_path_tracer_under_a_dispersive_ball(8192, 4096, 2048, 0.008);
}

// The scattering furnaces of #12: medium vertices connected like surface vertices, with the
// spectral MIS of the camera and light subpaths and of each connection, full and hero.
void expect_bidirectional_furnace(const std::string& density, const std::string& what,
                                  IntegratorType integrator = IntegratorType::bdpt, int spp = 6144) {
  SceneDesc desc = parse_scene(test::furnace_scene(density, "bdpt"), "furnace.json");
  desc.render.merge_radius_m = 0.001;  // vcm: two footprints of this small image hold most of the photons
  for (const SpectralMode mode : {SpectralMode::full, SpectralMode::hero}) {
    const Film f = render(desc, integrator, mode, spp, 1);
    for (int c = 0; c < 3; ++c) {
      const auto e = test::channel_estimate(f, c, 0, 0, f.width, f.height);
      std::printf("%s white furnace (%s, %s) ch %d: %.5f ± %.5f\n", integrator_info(integrator).name.data(), what.c_str(),
                  mode == SpectralMode::full ? "full" : "hero", c, e.mean, e.standard_error);
      EXPECT_NEAR(e.mean, 1.0, 0.01) << what << " ch " << c;
      EXPECT_LT(3.0 * e.standard_error, 0.01) << what << " ch " << c << ": too few samples for the tolerance";
    }
  }
}

TEST(Bidirectional, ScatteringWhiteFurnaceHomogeneous) { expect_bidirectional_furnace("", "homogeneous"); }

// Merging in the medium (the ball kernel) and on no surface (the furnace has none but the sphere's).
// Every pixel of an iteration shares its wavelengths and hero (a photon meets a camera path at
// its own), so the pixels' errors are not independent. In full mode the hero is drawn from strata
// over the iterations: with one drawn at random, the blue mean spread from 0.983 to 1.026 over 12
// seeds at 1024 iterations while each image's standard error said 0.0025; with the strata, 0.996
// to 1.001, within what the pixels say, so 1024 iterations and the pixels' standard error (about
// 0.0027 in blue). Hero mode's four wavelengths are the iteration's too, and its blue spreads
// ±1.1 % over seeds at 1024 iterations where the pixels say ±0.34 %: its standard error is taken
// from 8 seeds' image means, for 2 % (3 of them 1.2 %). (Rare medium connections bring a few
// hundred times a sample's mean: at 4096 iterations, full mode, two seeds in four had one in blue.)
TEST(VertexMerging, ScatteringWhiteFurnaceHomogeneous) {
  SceneDesc desc = parse_scene(test::furnace_scene("", "vcm"), "furnace.json");
  desc.render.merge_radius_m = 0.001;  // two footprints of this small image hold most of the photons
  const Film full = render(desc, IntegratorType::vcm, SpectralMode::full, 1024, 1);
  for (int c = 0; c < 3; ++c) {
    const auto e = test::channel_estimate(full, c, 0, 0, full.width, full.height);
    std::printf("vcm white furnace (homogeneous, full) ch %d: %.5f ± %.5f\n", c, e.mean, e.standard_error);
    EXPECT_NEAR(e.mean, 1.0, 0.01) << "full ch " << c;
    EXPECT_LT(3.0 * e.standard_error, 0.01) << "full ch " << c << ": too few samples for the tolerance";
  }
}

// The same furnace in hero mode, whose error needs 8 seeds' renders (above): 45 s on 2 loaded
// cores, so `long`. test_vcm_hero.cpp's strongly chromatic furnace checks hero mode too.
TEST(VertexMergingLong, ScatteringWhiteFurnaceHomogeneousHero) {
  SceneDesc desc = parse_scene(test::furnace_scene("", "vcm"), "furnace.json");
  desc.render.merge_radius_m = 0.001;
  constexpr int kSeeds = 8;
  std::array<std::array<double, kSeeds>, 3> means{};
  for (int seed = 1; seed <= kSeeds; ++seed) {
    const Film f = render(desc, IntegratorType::vcm, SpectralMode::hero, 1024, static_cast<std::uint64_t>(seed));
    for (int c = 0; c < 3; ++c)
      means[c][seed - 1] = test::channel_estimate(f, c, 0, 0, f.width, f.height).mean;
  }
  for (int c = 0; c < 3; ++c) {
    const auto [mean, se] = test::mean_estimate(means[c]);
    std::printf("vcm white furnace (homogeneous, hero, %d seeds) ch %d: %.5f ± %.5f\n", kSeeds, c, mean, se);
    EXPECT_NEAR(mean, 1.0, 0.02) << "hero ch " << c;
    EXPECT_LT(3.0 * se, 0.02) << "hero ch " << c << ": too few samples for the tolerance";
  }
}

// Through an exponential density (the light subpaths' distances drawn by the field's majorant):
// about 6 s on an idle core, `long`; the path tracer's furnace through the same field
// (Scattering.WhiteFurnaceWithADensityField) and bdpt's homogeneous one stay in the suite.
TEST(BidirectionalLong, ScatteringWhiteFurnaceWithADensityField) {
  expect_bidirectional_furnace(
      R"(, "density": {"field": "exponential", "axis": [0, 1, 0], "value": 1, "scale_length": "10 mm"})",
      "exponential density");
}

// A dense furnace ball of index 1 (albedo 1, σ_s·r = 100, g = 0.85) with max_depth 2: the
// connections and merges make only the paths of at most two scattering events, and the camera
// subpaths' tails (bidirectional.h: KeepThenTrace) walk on as the path tracer does and bring back
// the rest. Every path brings back the background, so the image is 1; before the tails, what
// scattered more than max_depth times was lost (this ball came out at 0.05 with max_depth 8, a
// whole-milk ball 25 % dark with max_depth 64). vcm merges within 0.3 mm, which in this ball adds
// no measurable bias (1 mm darkens it by about 1 %).
TEST(Bidirectional, DenseFurnaceBringsBackTheLightBeyondMaxDepth) {
  SceneDesc desc = parse_scene(test::ball_furnace(0.048, "[16667, 16667]", 0.85, "6 mm", 1.0), "dense.json");
  desc.render.max_depth = 2;
  desc.render.merge_radius_m = 0.0003;
  for (const IntegratorType integrator : {IntegratorType::bdpt, IntegratorType::vcm})
    for (const SpectralMode mode : {SpectralMode::full, SpectralMode::hero}) {
      const Film f = render(desc, integrator, mode, 64, 1);
      for (int c = 0; c < 3; ++c) {
        const auto e = test::channel_estimate(f, c, 0, 0, f.width, f.height);
        std::printf("%s dense furnace, max_depth 2 (%s) ch %d: %.5f ± %.5f\n", integrator_info(integrator).name.data(),
                    mode == SpectralMode::full ? "full" : "hero", c, e.mean, e.standard_error);
        EXPECT_NEAR(e.mean, 1.0, 0.01) << integrator_info(integrator).name << " ch " << c;
        EXPECT_LT(3.0 * e.standard_error, 0.01) << "ch " << c << ": too few samples for the tolerance";
      }
    }
}

// The same for a chromatic furnace dense enough that the path tracer splits its walks into walks
// of one wavelength (σ_s 900 → 30 per m, g = 0.7, a 20 mm ball of index 1): the tails split as the
// path tracer's walks do, each wavelength's weight 1/(4·P(bin)) in full mode. The paths of at most
// two events keep the spectral MIS's noise, hence 1024 spp for 3 %.
TEST(Bidirectional, ChromaticDenseFurnaceSplitsInTheTails) {
  SceneDesc desc = parse_scene(test::ball_furnace(0.16, "[900, 30]", 0.7, "20 mm", 1.0), "chromatic.json");
  desc.render.max_depth = 2;
  for (const SpectralMode mode : {SpectralMode::full, SpectralMode::hero}) {
    const Film f = render(desc, IntegratorType::bdpt, mode, 1024, 1);
    for (int c = 0; c < 3; ++c) {
      const auto e = test::channel_estimate(f, c, 0, 0, f.width, f.height);
      std::printf("bdpt chromatic dense furnace, max_depth 2 (%s) ch %d: %.5f ± %.5f\n",
                  mode == SpectralMode::full ? "full" : "hero", c, e.mean, e.standard_error);
      EXPECT_NEAR(e.mean, 1.0, 0.03) << "ch " << c;
      EXPECT_LT(3.0 * e.standard_error, 0.03) << "ch " << c << ": too few samples for the tolerance";
    }
  }
}

// The whole-milk ball of Scattering.WholeMilkBallMatchesItsReference (about a thousand scattering
// events a path, tests/data/whole_milk_ball) with bdpt: its image mean is the reference's. The
// difference is taken pixel by pixel, so that its standard error is the noise's alone. max_depth 8
// (the scene's 64 works as well, with more colour noise: the connections' part of a path carries
// every wavelength under the spectral MIS). Before the camera tails the image came out 25 % dark
// at the scene's max_depth of 64. Measured: within 0.001 of the reference per channel, ± 0.002.
TEST(Bidirectional, WholeMilkBallMatchesThePathTracersReference) {
  SceneDesc desc = load_scene(test::test_data("whole_milk_ball/scene.json"));
  desc.render.max_depth = 8;
  const Film f = render(desc, IntegratorType::bdpt, SpectralMode::full, 128, 1);
  const Film reference = read_exr(test::test_data("whole_milk_ball/reference.exr"));
  ASSERT_EQ(f.width, reference.width);
  ASSERT_EQ(f.height, reference.height);
  for (int c = 0; c < 3; ++c) {
    const auto [mean, se] = test::difference_estimate(reference, f, c);
    const double ref = test::channel_estimate(reference, c, 0, 0, reference.width, reference.height).mean;
    std::printf("bdpt whole-milk ball (128 spp) ch %d: mean %.5f, reference %.5f, difference %+.5f ± %.5f\n", c,
                ref + mean, ref, mean, se);
    EXPECT_NEAR(mean, 0.0, 0.03 * ref) << "ch " << c;
    EXPECT_LT(3.0 * se, 0.03 * ref) << "ch " << c << ": too few samples for the tolerance";
  }
}

// The liquid seen through the glass (green), from `spp` samples per pixel of one estimator. bdpt:
// two seeds, the mean of the two renders over the region and its standard error from each
// pixel's two values (a pixel's (a − b)²/2 estimates its variance; the region's 48 pixels are
// independent). vcm, whose pixels share each iteration's photons: kVcmSeeds seeds of spp /
// kVcmSeeds iterations, the standard error from their region means' spread (test_scenes.h:
// seeds_estimate).
constexpr int kLiquidX0 = 5, kLiquidX1 = 11, kLiquidY0 = 6, kLiquidY1 = 14;
constexpr int kVcmSeeds = 16;

test::Estimate liquid_estimate(SceneDesc desc, IntegratorType integrator, int spp) {
  if (integrator == IntegratorType::vcm) {
    desc.render.integrator = integrator;
    desc.render.spectral = SpectralMode::full;
    desc.render.spp = spp / kVcmSeeds;
    return test::seeds_estimate(test::render_seeds(desc, kVcmSeeds, 1), 1, kLiquidX0, kLiquidY0, kLiquidX1, kLiquidY1);
  }
  const Film a = render(desc, integrator, SpectralMode::full, spp, 1), b = render(desc, integrator, SpectralMode::full, spp, 2);
  double sum = 0.0, variance = 0.0;
  int n = 0;
  for (int y = kLiquidY0; y < kLiquidY1; ++y)
    for (int x = kLiquidX0; x < kLiquidX1; ++x, ++n) {
      const double va = a.rgb_at(x, y)[1], vb = b.rgb_at(x, y)[1];
      sum += 0.5 * (va + vb);
      variance += 0.25 * (va - vb) * (va - vb);
    }
  return {sum / n, std::sqrt(variance) / n};
}

// The lit tumbler's liquid (point and spot lamps behind the glass): the path tracer's next-event
// estimation through the glass (integrators/manifold_chain.h) is its reference, checked against the
// index-matched tumbler (test_manifold.cpp). bdpt reaches the light scattered once there by its
// next-event estimation through the glass at the first vertex in the liquid (Bdpt::through_glass),
// or, where the glass reflected that light on its way in, by its light through glass to the camera
// (Bdpt::through_glass_to_camera), and the light scattered more than once also by connecting a
// camera vertex in the liquid to a light vertex there. Asserted: bdpt's mean plus 4 of its
// standard errors is not below the path tracer's (without through_glass it read 0.61 of it: the
// light scattered once was black), and less 4 is not above 1.15 of it (a path counted by two
// strategies). Measured: 1.01 ± 0.05 of the path tracer at 1024 spp; against the ground truth
// (the path tracer with its light paths, below), 0.992 ± 0.014 from 48 seeds of 2048 spp; the
// light through glass to the camera adds 0.0252 ± 0.0003 of it (32 seeds, each against itself
// without), where bdpt had read 0.951 ± 0.014 and the path tracer alone reads 0.935. About 8 s on an
// idle core: `long` (the suite keeps bdpt's next-event estimation through glass against the path
// tracer, Bidirectional.WhatIsSeenAndLitThroughGlassIsThePathTracers, and the tumbler's images at
// any thread count).
TEST(BidirectionalLong, LightsALiquidInGlassByItsMediumConnections) {
  const SceneDesc desc = parse_scene(test::lit_tumbler("bdpt"), "tumbler.json");
  const Film path = render(desc, IntegratorType::path, SpectralMode::full, 256, 1);
  const double p = test::channel_estimate(path, 1, kLiquidX0, kLiquidY0, kLiquidX1, kLiquidY1).mean;
  const test::Estimate b = liquid_estimate(desc, IntegratorType::bdpt, 1024);
  std::printf("liquid in glass under a point and a spot (green): path %.5f, bdpt %.5f ± %.5f (%.2f of path)\n", p,
              b.mean, b.standard_error, b.mean / p);
  EXPECT_GT(b.mean + 4.0 * b.standard_error, p);
  EXPECT_LT(b.mean - 4.0 * b.standard_error, 1.15 * p);
  EXPECT_LT(4.0 * b.standard_error, 0.35 * p) << "too noisy to tell 0.61 of the reference from 1";
}

// bdpt's next-event estimation through the glass against the path tracer, on a scene where the
// camera sees everything through glass and the one point lamp lights it through glass: bdpt's
// image less the same render without it (`manifold: false`, the same seed: every other strategy's
// contribution the same bit for bit, fireflies of its medium connections included) against the
// path tracer's, the image means' difference (from the pixels' differences, the pixels being
// independent) within 4 of its standard errors and those under `cap` of the path tracer's mean,
// in each mode; and bdpt without it below `without` of the path tracer (where it has no other
// strategy there: negative, not asserted).
void expect_bdpt_through_glass_is_path(const std::string& json, const char* what, int spp, double cap, double without) {
  SceneDesc desc = parse_scene(json, "through_glass.json");
  for (const SpectralMode mode : {SpectralMode::full, SpectralMode::hero}) {
    desc.render.manifold = true;
    const Film path = render(desc, IntegratorType::path, mode, spp, 1);
    const Film on = render(desc, IntegratorType::bdpt, mode, spp, 2);
    desc.render.manifold = false;
    const Film off = render(desc, IntegratorType::bdpt, mode, spp, 2);
    Film through(on.width, on.height);
    for (int y = 0; y < on.height; ++y)
      for (int x = 0; x < on.width; ++x) through.set_rgb(x, y, on.rgb_at(x, y) - off.rgb_at(x, y));
    for (int c = 0; c < 3; ++c) {
      const double p = test::channel_estimate(path, c, 0, 0, path.width, path.height).mean;
      const test::Estimate d = test::difference_estimate(path, through, c);
      const double o = test::channel_estimate(off, c, 0, 0, off.width, off.height).mean;
      std::printf("%s (%s), ch %d: path %.4e, bdpt's through glass − path %+.2e ± %.2e, bdpt without %.4e\n", what,
                  mode == SpectralMode::full ? "full" : "hero", c, p, d.mean, d.standard_error, o);
      EXPECT_LT(std::abs(d.mean), 4.0 * d.standard_error) << what << " ch " << c;
      EXPECT_LT(4.0 * d.standard_error, cap * p) << what << " ch " << c << ": too noisy";
      if (without >= 0.0) {
        EXPECT_LT(o, without * p) << what << " ch " << c;
      }
    }
  }
}

// The camera's rays and a point lamp's light both cross glass, so bdpt has no strategy for the
// light scattered once behind it but its next-event estimation through the glass
// (Bdpt::through_glass; a connection needs two non-specular vertices side by side), which must
// then give the path tracer's image. A floor under a slab of coloured glass (4 mm: a chain of two
// faces; the camera's rays keep 85–98 % of their light through it; the floor dark and the slab small and high, so
// that the light the slab reflects back to the floor, which the path tracer has and bdpt not, is
// about 10⁻⁴ of it): without the camera path's own weight, 4–14 % bright; without the strategy,
// black. A thin chromatic haze under the same slab (index 1, σ_s 0.2 to 0.05 per m over 100 mm: the
// light scattered more than once, which the path tracer's image has and bdpt's estimation through
// the glass does not, is about 1 % of it): the medium vertex's phase function and spectral-MIS
// ratios, in hero mode too; 2 % of the camera's rays scatter, so at 256 spp 4 standard errors are
// a fifth of the light, enough for the phase function read the wrong way round (5 times too
// bright) or a factor of the chromatic σ_s (up to 4) in the ratios. A floor seen and lit
// through an exact glass ball (a caster): through_casters. And max_depth 2 leaves the slab's floor
// (the third surface) black in both, where a vertex past it had been lit.
TEST(Bidirectional, WhatIsSeenAndLitThroughGlassIsThePathTracers) {
  auto scene = [](const char* objects, const char* media, int max_depth) {
    return fmt::format(R"({{
      "camera": {{"type": "orthographic", "position": [0, 1.5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
                 "width": 0.05, "resolution": [16, 16]}},
      "render": {{"integrator": "path", "max_depth": {}}},
      "world_medium": "vacuum",
      "media": {{"glass": {{"ior": 1.5, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                                                    "value": [5, 40]}}}}{}}},
      "objects": [
        {{"name": "slab", "shape": {{"type": "box", "size": [0.2, 0.004, 0.2]}}, "transform": [{{"translate": [0, 1, 0]}}],
         "inside": "glass"}},
        {}
      ],
      "lights": [{{"type": "point", "position": [0.1, 2, 0.02], "spectrum": "D65", "scale": 1}}],
      "background": {{"spectrum": "E", "scale": 0}}
    }})",
                       max_depth, media, objects);
  };
  const char* floor = R"({"name": "floor", "shape": {"type": "quad", "size": [2, 2]},
      "transform": [{"rotate_deg": [-90, [1, 0, 0]]}], "material": {"type": "diffuse", "reflectance": 0.3}})";
  expect_bdpt_through_glass_is_path(scene(floor, "", 64), "floor through a glass slab", 64, 0.02, 1e-3);
  expect_bdpt_through_glass_is_path(
      scene(R"({"name": "haze", "shape": {"type": "box", "size": [0.3, 0.1, 0.3]},
                "transform": [{"translate": [0, 0.5, 0]}], "inside": "haze"})",
            R"(, "haze": {"ior": 1.0, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                         "value": [0.2, 0.05], "phase": {"type": "henyey_greenstein", "g": 0.3}}})",
            64),
      "thin haze under a glass slab", 256, 0.25, -1.0);
  expect_bdpt_through_glass_is_path(R"({
      "camera": {"type": "orthographic", "position": [0, 0.3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
                 "width": 0.016, "resolution": [16, 16]},
      "render": {"integrator": "path", "max_depth": 64},
      "world_medium": "vacuum",
      "media": {"glass": {"ior": 1.5, "absorption": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                                                    "value": [5, 40]}}},
      "objects": [
        {"name": "ball", "shape": {"type": "sphere", "radius": 0.02}, "transform": [{"translate": [0, 0.05, 0]}],
         "inside": "glass"},
        {"name": "floor", "shape": {"type": "quad", "size": [2, 2]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
         "material": {"type": "diffuse", "reflectance": 0.3}}
      ],
      "lights": [{"type": "point", "position": [0.02, 0.6, 0.01], "spectrum": "D65", "scale": 1}],
      "background": {"spectrum": "E", "scale": 0}
    })",
                                    "floor through a glass ball", 64, 0.03, 0.01);
  const SceneDesc shallow = parse_scene(scene(floor, "", 2), "shallow.json");
  for (const IntegratorType integrator : {IntegratorType::path, IntegratorType::bdpt}) {
    const Film f = render(shallow, integrator, SpectralMode::full, 4, 1);
    EXPECT_EQ(test::channel_estimate(f, 1, 0, 0, f.width, f.height).mean, 0.0) << "max_depth 2";
  }
}

// The ground truth of the liquid (green): the path tracer with its light paths (render.light_paths):
// its next-event estimation through the glass makes the paths that refract on their way from a
// lamp to their first vertex in the liquid, and light paths connected to the camera (through the
// glass, as next-event estimation solves it) add those it does not make (light the glass or the
// liquid's surface reflected on the way), each path once. kSeeds seeds of spp / kSeeds samples,
// the standard error from their spread (a light path's splats spread over pixels).
test::Estimate ground_truth_estimate(SceneDesc desc, int spp) {
  constexpr int kSeeds = 8;
  desc.render.integrator = IntegratorType::path;
  desc.render.spectral = SpectralMode::full;
  desc.render.light_paths = true;
  desc.render.spp = spp / kSeeds;
  return test::seeds_estimate(test::render_seeds(desc, kSeeds, 1), 1, kLiquidX0, kLiquidY0, kLiquidX1, kLiquidY1);
}

// vcm reaches the light in the liquid by connections and merges, with finite variance, and the
// light scattered once from the glass's reflections by merges alone. Asserted: vcm's mean, from 16
// seeds of 64 spp, has a standard error under 4 % (measured 2.6 %: it converges where bdpt's 1/d²
// connections do not) and is within 4 of them of the ground truth (ground_truth_estimate, 2048 spp:
// before merges right after a specular vertex were weighed, vcm read 0.62 of the path tracer); the
// ground truth is above the path tracer alone by more than 4 of its own standard errors (the light
// reflected inside the glass before it scatters: 6.5 %, 14 of them), which vcm's error could not tell.
// Measured: ground truth 0.06309 ± 0.00030, the path tracer 0.05898, vcm 0.966 ± 0.025 of it.
// About 17 s on an idle core, most of it the ground truth: `long` (the suite keeps vcm's regression
// on a liquid behind glass, EstimatorRegression.VcmMatchesItsReferenceInALiquidBehindGlass).
TEST(VertexMergingLong, LightsALiquidInGlassAndConverges) {
  const SceneDesc desc = parse_scene(test::lit_tumbler("vcm"), "tumbler.json");
  const Film path = render(desc, IntegratorType::path, SpectralMode::full, 256, 1);
  const double p = test::channel_estimate(path, 1, kLiquidX0, kLiquidY0, kLiquidX1, kLiquidY1).mean;
  const test::Estimate g = ground_truth_estimate(desc, 2048);
  const test::Estimate v = liquid_estimate(desc, IntegratorType::vcm, 1024);
  std::printf("liquid in glass (green): ground truth %.5f ± %.5f, path alone %.5f, vcm (1024 spp) %.5f ± %.5f (%.3f "
              "of the ground truth)\n",
              g.mean, g.standard_error, p, v.mean, v.standard_error, v.mean / g.mean);
  EXPECT_LT(v.standard_error, 0.04 * v.mean) << "vcm does not converge";
  EXPECT_LT(std::abs(v.mean - g.mean), 4.0 * std::hypot(v.standard_error, g.standard_error));
  EXPECT_GT(g.mean - p, 4.0 * g.standard_error);
}

// vcm against the ground truth, closer, under the point lamp alone (its light comes through the
// liquid's flat surface or the wall; 23 % of it reflected on the way, which the path tracer alone
// leaves out): vcm's mean (8192 iterations) within 4 standard errors of the ground truth's (8192
// spp), those under 10 % of it (the path tracer alone would be 23 % low). Measured: 1.026 ± 0.023
// of it (0.01941 ± 0.00039 against 0.01891 ± 0.00020); with 4 seeds of 2048, vcm reads 0.01888 ±
// 0.00015. Merges lost after specular vertices read 0.6 of it, merges counted
// twice about 1.6. Under
// the spot lamp, whose beam the tumbler focuses, vcm's first merging radius (two pixel footprints,
// 12.6 mm here) blurs it into 3.2 % more light than the ground truth's (0.04597 ± 0.00023 against
// 0.04455 ± 0.00012); at half that radius they agree (0.04463 ± 0.00044), so it is left out here.
// About 40 s on one idle core (106 s beside a build): `long`.
TEST(VertexMergingLong, AgreesWithTheGroundTruthInALiquidInGlass) {
  SceneDesc desc = parse_scene(test::lit_tumbler("vcm"), "tumbler.json");
  desc.lights.pop_back();  // the spot
  const test::Estimate v = liquid_estimate(desc, IntegratorType::vcm, 8192);
  const test::Estimate g = ground_truth_estimate(desc, 8192);
  const double se = std::hypot(v.standard_error, g.standard_error);
  std::printf("liquid in glass under the point lamp (green): vcm (8192 spp) %.5f ± %.5f, ground truth %.5f ± %.5f "
              "(%.3f of it)\n",
              v.mean, v.standard_error, g.mean, g.standard_error, v.mean / g.mean);
  EXPECT_LT(4.0 * se, 0.1 * g.mean) << "too noisy to compare";
  EXPECT_LT(std::abs(v.mean - g.mean), 4.0 * se);
}

// vcm keeps its light subpaths without their surface events (VertexCore) and builds each again for
// its pixel's connections (rebuilt_light_vertex): it must be the walk's event bit for bit, or
// vcm's images change. Light subpaths traced as an iteration of vcm traces them (begin_sample's
// wavelengths and kept wavelength), over a dispersive ball (deferred dispersion: events built for
// the kept wavelength), the busy scene (rough and smooth dielectrics, a thin pane, a medium behind
// an index-matched boundary, dispersive too) and the textured bottle (textures, not dispersive),
// in full, hero and rgb3: each surface vertex's rebuilt event gives the same BSDF samples, values
// and densities, bit for bit.
template <std::size_t N>
void expect_kept_light_vertices_rebuilt(const SceneDesc& desc, SpectralMode mode, bool dispersive) {
  const RenderScene scene = compile(desc);
  ASSERT_EQ(scene.dispersive, dispersive);
  const SpectralTables<N> tables(scene.spectra, mode);
  const Camera camera(scene.camera);
  const SceneView<N> view{scene, tables, camera, desc.render.max_depth, false};
  int surfaces = 0, dispersed = 0;
  Rng directions(3, 1);
  auto direction = [&] {
    const double z = 2.0 * directions.next_double() - 1.0, phi = 2.0 * std::numbers::pi * directions.next_double();
    const double r = std::sqrt(1.0 - z * z);
    return Vec3{r * std::cos(phi), r * std::sin(phi), z};
  };
  for (int k = 0; k < 1000; ++k) {
    Rng irng(static_cast<std::uint64_t>(k), 7);
    SampledWavelengths<N> w = tables.wavelengths(0.0);
    tables.restart(w, mode == SpectralMode::hero ? irng.next_double() / static_cast<double>(N) : 0.0);
    draw_hero(scene, w, irng.next_double());
    SampledWavelengths<N> kept = w;
    std::vector<double> sigma_mean;
    bidir::begin_sample(view, w, irng.next_double(), irng, sigma_mean, kept);
    const WalkMedia media{sigma_mean};
    Rng rng(static_cast<std::uint64_t>(k), 11);
    std::uint64_t rays = 0;
    bidir::Bdpt<N> b(view, media, w, scene.dispersive ? &kept : nullptr, rng, rays);
    std::vector<Vertex<N>> traced;
    b.append_light_subpath(traced, rng);
    for (const Vertex<N>& x : traced) {
      if (x.kind != VertexKind::surface) continue;
      ++surfaces;
      dispersed += x.dispersed;
      const Vertex<N> y = rebuilt_light_vertex(view, static_cast<const VertexCore<N>&>(x), w, kept);
      EXPECT_EQ(is_specular(y.event.bsdf), is_specular(x.event.bsdf));
      EXPECT_EQ(y.event.inside, x.event.inside);
      // (A specular event's BSDF is zero between random directions: its samples are compared.)
      for (int j = 0; j < 4; ++j) {
        const double uc = directions.next_double(), u1 = directions.next_double(), u2 = directions.next_double();
        const auto sy = y.event.sample(x.wo, uc, u1, u2, TransportMode::importance);
        const auto sx = x.event.sample(x.wo, uc, u1, u2, TransportMode::importance);
        ASSERT_EQ(sy.has_value(), sx.has_value()) << "path " << k;
        if (!sx) continue;
        EXPECT_EQ(sy->wi, sx->wi) << "path " << k;
        EXPECT_EQ(sy->pdf, sx->pdf) << "path " << k;
        for (std::size_t i = 0; i < N; ++i) EXPECT_EQ(sy->weight[i], sx->weight[i]) << "path " << k << " bin " << i;
      }
      for (int j = 0; j < 4; ++j) {
        const Vec3 a = direction(), c = direction();
        EXPECT_EQ(y.event.pdf(a, c), x.event.pdf(a, c)) << "path " << k;
        for (const TransportMode m : {TransportMode::importance, TransportMode::radiance}) {
          const SampledSpectrum<N> fy = y.event.eval(a, c, m), fx = x.event.eval(a, c, m);
          for (std::size_t i = 0; i < N; ++i) EXPECT_EQ(fy[i], fx[i]) << "path " << k << " bin " << i;
        }
      }
    }
  }
  std::printf("kept light vertices: %d surface vertices rebuilt (%d after a dispersive interface)\n", surfaces,
              dispersed);
  EXPECT_GT(surfaces, 200);
  if (dispersive) {
    EXPECT_GT(dispersed, 50);
  }
}

TEST(VertexMerging, ALightVertexKeptWithoutItsEventGetsItBack) {
  std::string ball = test::caustic_scene("vcm", 1, 1);
  const std::string red = R"("red": {"absorption": {"library": "red-glass", "concentration": 0.3}})";
  ASSERT_NE(ball.find(red), std::string::npos);
  ball.replace(ball.find(red), red.size(), R"("red": {"ior": {"library": "N-SF11"}})");
  const SceneDesc dispersive = parse_scene(ball, "dispersive.json");
  expect_kept_light_vertices_rebuilt<kFullBins>(dispersive, SpectralMode::full, true);
  expect_kept_light_vertices_rebuilt<kHeroCount>(dispersive, SpectralMode::hero, true);
  expect_kept_light_vertices_rebuilt<3>(dispersive, SpectralMode::rgb3, true);
  expect_kept_light_vertices_rebuilt<kFullBins>(parse_scene(test::busy_scene("vcm", "full", 1), "busy.json"),
                                                SpectralMode::full, true);
  const SceneDesc bottle =
      load_scene(std::filesystem::path(BOUGUER_SOURCE_DIR) / "scenes" / "examples" / "textured-bottle.json");
  expect_kept_light_vertices_rebuilt<kFullBins>(bottle, SpectralMode::full, false);
  expect_kept_light_vertices_rebuilt<kHeroCount>(bottle, SpectralMode::hero, false);
  expect_kept_light_vertices_rebuilt<3>(bottle, SpectralMode::rgb3, false);
}

// For every full path that a connection of one camera sample makes, the weights of all the
// strategies that could have made it sum to 1, and the weight the renderer gave it equals the
// one recomputed from the geometry (the walk's density records are right). A scene with every
// kind of vertex: diffuse and rough dielectric surfaces, smooth glass, a thin dielectric pane, a
// scattering medium behind an index-matched boundary, an area lamp, a point light and a spot.
using MisCheck = BdptMisCheck (*)(const RenderScene&, const RenderSettings&, int, int, int);

// The checks of every camera sample of an 8 × 8 image at 16 samples, totalled: the paths and the
// worst |Σ weights − 1| and renderer-vs-recomputed weight over all of them.
struct MisTotals {
  std::size_t paths = 0, lens_through_media = 0, merge_paths = 0, merge_only = 0;
  double worst_sum = 0.0, worst_difference = 0.0;
};
MisTotals check_every_sample(MisCheck check, const SceneDesc& desc) {
  const RenderScene scene = compile(desc);
  MisTotals t;
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int sample = 0; sample < 16; ++sample) {
        const BdptMisCheck c = check(scene, desc.render, x, y, sample);
        for (const double sum : c.sums) t.worst_sum = std::max(t.worst_sum, std::abs(sum - 1.0));
        t.worst_difference = std::max(t.worst_difference, c.max_weight_difference);
        t.paths += c.sums.size();
        t.lens_through_media += c.lens_through_media;
        t.merge_paths += c.merge_paths;
        t.merge_only += c.merge_only_paths;
      }
  return t;
}

void expect_weights_sum_to_one(MisCheck check, const char* what) {
  const std::string json = R"({
    "camera": {"position": [0, 0.3, 0.5], "look_at": [0, 0.05, 0], "fov_deg": 40, "resolution": [8, 8]},
    "render": {"integrator": "bdpt", "spectral": "hero", "spp": 16, "max_depth": 12},
    "world_medium": "vacuum",
    "media": {"glass": {"ior": 1.5},
              "haze": {"ior": 1.0, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                                                  "value": [40, 10], "phase": {"type": "henyey_greenstein", "g": 0.4}}}},
    "objects": [
      {"name": "floor", "shape": {"type": "quad", "size": [1, 1]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
       "material": {"type": "diffuse", "reflectance": 0.7}},
      {"name": "rough ball", "shape": {"type": "sphere", "radius": "40 mm", "segments": 24}, "roughness": 0.3,
       "transform": [{"translate": [-0.06, 0.04, 0]}], "inside": "glass"},
      {"name": "smooth ball", "shape": {"type": "sphere", "radius": "30 mm", "segments": 24},
       "transform": [{"translate": [0.08, 0.03, 0.05]}], "inside": "glass"},
      {"name": "haze", "shape": {"type": "box", "size": [0.1, 0.1, 0.1]}, "transform": [{"translate": [0.05, 0.05, -0.1]}],
       "inside": "haze"},
      {"name": "lamp", "shape": {"type": "quad", "size": [0.1, 0.1]},
       "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0, 0.4, 0]}], "emission": {"spectrum": "D65", "scale": 5}},
      {"name": "pane", "shape": {"type": "quad", "size": [0.12, 0.12]},
       "transform": [{"rotate_deg": [-80, [1, 0, 0]]}, {"translate": [-0.03, 0.2, 0.02]}],
       "material": {"type": "thin_dielectric", "ior": 1.5, "tint": 0.8}}
    ],
    "lights": [{"type": "point", "position": [0.2, 0.2, 0.1], "spectrum": "A", "scale": 0.01},
               {"type": "spot", "position": [-0.2, 0.3, 0], "look_at": [0, 0, 0], "spectrum": "D65", "scale": 0.02}],
    "background": {"spectrum": "D65", "scale": 0.1}
  })";
  const MisTotals t = check_every_sample(check, parse_scene(json, "mis.json"));
  std::printf("%s MIS over %zu full paths (%zu lens connections through the haze; %zu made by merges, %zu by merges "
              "alone): largest |Σ weights − 1| %.2e, largest renderer-vs-recomputed weight %.2e\n",
              what, t.paths, t.lens_through_media, t.merge_paths, t.merge_only, t.worst_sum, t.worst_difference);
  EXPECT_GT(t.paths, 800u);
  EXPECT_GT(t.lens_through_media, 10u);  // t = 1 through a medium is checked, not skipped
  EXPECT_LT(t.worst_sum, 1e-9);
  EXPECT_LT(t.worst_difference, 1e-3);  // hit points are rounded: measured 1.1e-4 (bdpt), 2e-5 (vcm)
}

TEST(Bidirectional, StrategyWeightsOfEveryPathSumToOne) { expect_weights_sum_to_one(bdpt_mis_check, "bdpt"); }

// With merging: the connections' weights and the merges' (at every vertex where a path can merge,
// surfaces and the medium alike) of every full path sum to 1.
// vcm keeps each pixel's light subpath for its iteration and states the memory (--stats-json's
// vcm.light_subpath_bytes): under a spot aimed at a floor that catches all of its cone, with
// max_depth 1, every light subpath is its lamp vertex and one floor vertex, so an iteration keeps
// exactly two vertices and a span per pixel, in full (2000-byte vertices) and hero (528). A
// subpath kept twice, or not counted, reads otherwise.
TEST(VertexMerging, KeepsTwoVerticesAPixelUnderASpotAndSaysSo) {
  for (const char* spectral : {"full", "hero"}) {
    SceneDesc desc = parse_scene(fmt::format(R"({{
      "camera": {{"type": "orthographic", "position": [0, 1, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
                 "width": "100 mm", "resolution": [12, 10]}},
      "render": {{"integrator": "vcm", "spectral": "{}", "spp": 3, "max_depth": 1}},
      "world_medium": "vacuum",
      "objects": [{{"name": "floor", "shape": {{"type": "quad", "size": [2, 2]}},
                    "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}], "material": {{"type": "diffuse", "reflectance": 0.5}}}}],
      "lights": [{{"type": "spot", "position": [0, 0.2, 0], "look_at": [0, 0, 0], "cone_deg": 10, "spectrum": "D65", "scale": 4}}]
    }})",
                                             spectral),
                                 "spot.json");
    const RenderScene scene = compile(desc);
    FilmBuffer film = make_film(scene, false);
    RenderStats stats;
    render_into(scene, desc.render, film, PixelRegion::whole(scene.camera), {0, 3}, RenderControl{}, stats);
    const std::uint64_t vertex =
        std::string(spectral) == "full" ? sizeof(VertexCore<kFullBins>) : sizeof(VertexCore<kHeroCount>);
    EXPECT_EQ(stats.iterations, 3) << spectral;
    EXPECT_EQ(stats.light_paths, 3u * 120u) << spectral;
    EXPECT_EQ(stats.photons, 3u * 120u) << spectral << ": one floor photon a subpath";
    EXPECT_EQ(stats.light_subpath_bytes, 120u * (2u * vertex + sizeof(std::span<const VertexCore<kFullBins>>))) << spectral;
  }
}

TEST(VertexMerging, StrategyWeightsOfEveryPathSumToOne) { expect_weights_sum_to_one(vcm_mis_check, "vcm"); }

// A scattering liquid in a box with a refracting boundary (n = 1.33) under a point lamp: a path that
// scatters once in it has two specular vertices around its one medium vertex and a delta lamp at
// its end, so no connection makes it and a merge there is its only strategy, whose weight must be
// 1. Checked over the paths merges make (each photon standing in for each camera vertex it could
// be merged with). Before: those merges weighed 0 (the photon's density after a specular vertex is
// 0, and the weight was 0/0), so vcm lost the once-scattered light (on a thin liquid, 84 % of it).
TEST(VertexMerging, AMergeThatAloneMakesAPathWeighsOne) {
  const SceneDesc desc = parse_scene(R"({
    "camera": {"position": [0, 0.05, 0.3], "look_at": [0, 0.04, 0], "fov_deg": 20, "resolution": [8, 8]},
    "render": {"integrator": "vcm", "spectral": "hero", "spp": 16, "max_depth": 12},
    "world_medium": "vacuum",
    "media": {"juice": {"ior": 1.33, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                                                    "value": [40, 20], "phase": {"type": "henyey_greenstein", "g": 0.3}}}},
    "objects": [{"name": "juice", "shape": {"type": "box", "size": [0.06, 0.07, 0.06]},
                 "transform": [{"translate": [0, 0.04, 0]}], "inside": "juice"}],
    "lights": [{"type": "point", "position": [0.05, 0.05, 0], "spectrum": "D65", "scale": 0.05}]
  })", "juice.json");
  const MisTotals t = check_every_sample(vcm_mis_check, desc);
  std::printf("vcm MIS over %zu paths merges make, %zu by merges alone: largest |Σ weights − 1| %.2e\n", t.merge_paths,
              t.merge_only, t.worst_sum);
  EXPECT_GT(t.merge_only, 50u);  // merges alone are checked, not skipped
  EXPECT_LT(t.worst_sum, 1e-9);
}

}  // namespace
}  // namespace bouguer
