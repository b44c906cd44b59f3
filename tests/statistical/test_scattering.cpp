// Scattering media (#12): the null-scattering path tracer with spectral MIS against closed forms.
// Tolerances follow from the sample count: each test measures its own standard error and also
// requires it to be small enough that the stated tolerance is at least 3 standard errors.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>
#include <span>
#include <stdexcept>

#include "bouguer/io/image_io.h"
#include "bouguer/media/scattering.h"
#include "bouguer/render/compare.h"
#include "bouguer/integrators/integrators.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/spectra/spectral_sampling.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"
#include "support/vdb_files.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;
using test::channel_estimate;
using test::Estimate;
using test::ball_furnace;
using test::kChromaticSigmaS;


Film render(SceneDesc desc, SpectralMode mode, int spp, std::uint64_t seed = 1) {
  desc.render.spectral = mode;
  desc.render.spp = spp;
  desc.render.seed = seed;
  return test::render_desc(desc);
}



void expect_white_furnace(const SceneDesc& desc, const std::string& what, int spp = 8192, double tolerance = 0.005) {
  for (const SpectralMode mode : {SpectralMode::full, SpectralMode::hero}) {
    const Film f = render(desc, mode, spp);
    for (int c = 0; c < 3; ++c) {
      const Estimate e = channel_estimate(f, c, 0, 0, f.width, f.height);
      std::printf("white furnace (%s, %s) ch %d: %.5f ± %.5f\n", what.c_str(),
                  mode == SpectralMode::full ? "full" : "hero", c, e.mean, e.standard_error);
      EXPECT_NEAR(e.mean, 1.0, tolerance) << what << " ch " << c;
      EXPECT_LT(3.0 * e.standard_error, tolerance) << what << " ch " << c << ": too few samples for the tolerance";
    }
  }
}
void expect_white_furnace(const std::string& json, const std::string& what, int spp = 8192,
                          double tolerance = 0.005) {
  expect_white_furnace(parse_scene(json, "furnace.json"), what, spp, tolerance);
}

TEST(Scattering, WhiteFurnaceHomogeneous) { expect_white_furnace(test::furnace_scene("", "path"), "homogeneous"); }

TEST(Scattering, WhiteFurnaceWithADensityField) {
  expect_white_furnace(
      test::furnace_scene(R"(, "density": {"field": "exponential", "axis": [0, 1, 0], "value": 1, "scale_length": "10 mm"})",
                          "path"),
      "exponential density");
}

// A furnace scene made index-matched (n = 1, so next-event estimation reaches the lights through
// the ball's boundary; unless keep_index) and lit by a uniform white environment map written into
// `dir`.
std::string under_a_white_map(std::string json, const fs::path& dir, bool keep_index = false) {
  Film white(16, 8);
  std::fill(white.rgb.begin(), white.rgb.end(), 1.0f);
  write_pfm(dir / "white.pfm", white);
  auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = json.find(from);
    if (at == std::string::npos) throw std::runtime_error("furnace scene without " + from);
    json.replace(at, from.size(), to);
  };
  if (!keep_index) replace("\"ior\": 1.33", "\"ior\": 1.0");
  replace("\"background\": {\"spectrum\": \"D65\", \"scale\": 1}",
          fmt::format("\"background\": {{\"environment\": \"{}\"}}", (dir / "white.pfm").string()));
  return json;
}

// The dense white furnace (#20): albedo 1, σ_s·r = 500, g = 0.85, in a sphere of index 1.33, about
// 550 scattering events a path. Every path brings back exactly the background, so with the
// roulette of integrators/events.h, which undoes the (η_o/η_i)² of refraction (roulette_scale),
// 4 spp are within 1 % in both modes. Bounded time, measured as work rather than seconds (which
// load changes): fewer than 2000 rays a camera sample (a walk that the roulette let run on, or a
// split that never ended, takes more). (Before the roulette's scale, it killed 43 % of the paths
// at their first check inside, at β = 1/1.33²: 2.7 % noise a pixel at 16 spp.)
TEST(Scattering, DenseWhiteFurnaceInBoundedWork) {
  SceneDesc desc = parse_scene(ball_furnace(0.048, "[83334, 83334]", 0.85, "6 mm"), "dense.json");
  expect_white_furnace(desc, "dense", 4, 0.01);
  desc.render.spp = 4;
  RenderStats stats;
  bouguer::render(compile(desc), desc.render, RenderControl{}, stats);
  const double samples = 4.0 * desc.camera.width_px * desc.camera.height_px;
  std::printf("dense white furnace: %.0f rays a camera sample\n", double(stats.rays) / samples);
  EXPECT_LT(double(stats.rays), 2000.0 * samples);
  EXPECT_GT(double(stats.rays), 100.0 * samples) << "the walk did not go deep: not the dense furnace";
}

// A dense ball (grey σ_s·r = 100, g = 0.85) of index 1 under a uniform environment map: the
// boundary is index-matched, so next-event estimation from every medium vertex reaches the map and
// shares it with phase sampling. Deep inside, where a connection crosses more than 3 mean free
// paths, it is thinned (integrators/events.h: nee_probability_in_medium), down to 1 in 64 at the
// centre; what it finds is divided by its probability, so the furnace stays white.
TEST(Scattering, DenseFurnaceUnderAnEnvironmentMapThinsNextEventEstimation) {
  const std::string json = under_a_white_map(ball_furnace(0.048, "[16667, 16667]", 0.85, "6 mm"),
                                             test::scratch_dir("scattering_dense_env_furnace"));
  const auto start = std::chrono::steady_clock::now();
  expect_white_furnace(json, "dense, environment map", 256, 0.015);
  std::printf("dense environment furnace: %.2f s for both modes\n",
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
}

// The strongly chromatic furnace of #20 (σ_s 900 → 30 per m over 400–700 nm, g = 0.7, a 20 mm ball
// of index 1.33): dense enough at the blue end that the path tracer splits into walks of one
// wavelength each (integrators/events.h: kSplitCount). Each is the analog walk of its wavelength
// at albedo 1, so each brings back exactly the background at that wavelength: in hero mode, where
// the split keeps all four carried wavelengths at weight 1, the furnace's image equals the sky's
// (rendered with the same seed, so the same wavelengths) to float rounding, in every pixel. With
// the spectral MIS that the split replaces, this furnace's pixels were 3–9 % apart at 64 spp
// (mean ΔE00 12). Full mode keeps 4 of the 96 bins per sample, weighted 24 each: exact in
// expectation, with the noise of choosing bins; the image mean is checked against 1 per channel.
TEST(Scattering, ChromaticDenseFurnaceSplitsIntoExactWalks) {
  const std::string furnace = ball_furnace(0.16, "[900, 30]", 0.7, "20 mm");
  SceneDesc desc = parse_scene(furnace, "furnace.json");
  const Film ball = render(desc, SpectralMode::hero, 16);
  desc.objects.clear();
  const Film sky = render(desc, SpectralMode::hero, 16);
  const double worst = test::largest_relative_difference(ball, sky);
  std::printf("chromatic dense furnace, hero, 16 spp: largest relative difference from the sky %.2e\n", worst);
  EXPECT_LT(worst, 1e-4);
  expect_white_furnace(furnace, "chromatic dense", 64, 0.01);
}

// The strongly chromatic dense furnace under a white environment map, its index kept at 1.33: with
// `"exit_guide": true` the walks of one wavelength near the boundary also connect to the map
// through it (integrators/events.h: ExitGuide), weighted against the walks that leave the same way.
// The two strategies' weights sum to 1 and the guide's density is the one it draws with, so the
// furnace stays white in both modes; the render differs from one with `"exit_guide": false` (so the
// guide ran). Noisier than the walks alone, which under a uniform map each bring back exactly 1:
// 512 spp, about 2 s a mode. Left unset, the guide stays off under this map (its contrast is 1,
// below kExitGuideContrast): the image is the unguided one, bit for bit.
TEST(Scattering, ChromaticDenseFurnaceUnderAMapConnectsThroughTheBoundary) {
  const std::string json = under_a_white_map(ball_furnace(0.16, "[900, 30]", 0.7, "20 mm"),
                                             test::scratch_dir("scattering_exit_guide_furnace"), true);
  auto guide = [&](const std::string& setting) {
    std::string j = json;
    j.replace(j.find("\"max_depth\": 1000"), 17, "\"max_depth\": 1000, \"exit_guide\": " + setting);
    return parse_scene(j, "furnace.json");
  };
  const SceneDesc guided = guide("true"), unguided = guide("false"), automatic = parse_scene(json, "furnace.json");
  ASSERT_EQ(guided.render.exit_guide, std::optional<bool>(true));
  ASSERT_EQ(unguided.render.exit_guide, std::optional<bool>(false));
  ASSERT_FALSE(automatic.render.exit_guide.has_value());
  expect_white_furnace(guided, "chromatic dense under a map, guided", 512, 0.015);
  const Film on = render(guided, SpectralMode::full, 4), off = render(unguided, SpectralMode::full, 4),
             unset = render(automatic, SpectralMode::full, 4);
  const std::size_t bytes = on.rgb.size() * sizeof(float);
  EXPECT_NE(std::memcmp(on.rgb.data(), off.rgb.data(), bytes), 0);
  EXPECT_EQ(std::memcmp(unset.rgb.data(), off.rgb.data(), bytes), 0);
}

// The same dense ball inside a thin chromatic haze (σ_s 60 → 6 per m, index 1, a 45 mm sphere of
// lower priority around it: nested media): camera paths scatter in the haze with the spectral MIS
// before they split at the ball, so the split's bins must be drawn independently of the hero that
// drew those distances (integrators/integrators.h: start_sample_wavelengths). Albedo 1 and no
// refraction outside the ball: every pixel is the background, within 1 % at 2048 spp in full and
// hero (their largest standard error, hero's blue, about 0.0025). About 6 s on an idle core: `long`
// (the suite keeps the same ball split under a map, ChromaticDenseFurnaceUnderAMapConnectsThroughTheBoundary).
TEST(ScatteringLong, ChromaticDenseFurnaceAfterAThinHaze) {
  const std::string json = R"({
    "camera": {"position": [0, 0, 0.16], "look_at": [0, 0, 0], "fov_deg": 5, "resolution": [8, 8]},
    "render": {"integrator": "path", "max_depth": 1000},
    "world_medium": "vacuum",
    "media": {"haze": {"ior": 1.0, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
              "value": [60, 6], "phase": {"type": "henyey_greenstein", "g": 0.7}}},
              "milky": {"ior": 1.33, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
              "value": [900, 30], "phase": {"type": "henyey_greenstein", "g": 0.7}}}},
    "objects": [{"name": "haze", "shape": {"type": "sphere", "radius": "45 mm"}, "inside": "haze", "priority": 1},
                {"name": "ball", "shape": {"type": "sphere", "radius": "20 mm"}, "inside": "milky", "priority": 2}],
    "background": {"spectrum": "D65", "scale": 1}
  })";
  expect_white_furnace(json, "chromatic dense after haze", 2048, 0.01);
}

// The furnace with a sparse voxel grid as the density (media/majorant.h: the majorant of each
// cell the ray crosses): three balls of densities 1 to 3 in a 24³ grid of 0.5 mm voxels that
// fills the sphere, empty elsewhere, so paths cross empty cells, cell edges and dense cells.
TEST(Scattering, WhiteFurnaceWithAGridDensity) {
  const fs::path dir = test::scratch_dir("scattering_grid_furnace");
  test::VdbTestGrid g;
  g.voxel_m = {0.5e-3, 0.5e-3, 0.5e-3};
  g.origin_m = {0.25e-3, 0.25e-3, 0.25e-3};  // voxel centres at ±0.25 mm, ±0.75 mm, ...
  g.first = {-12, -12, -12};
  g.count = {24, 24, 24};
  g.value = [](const Vec3& x) {
    const Vec3 centres[] = {{0.0015, 0.001, 0.0}, {-0.002, -0.0015, 0.001}, {0.0, 0.0025, -0.002}};
    const double radii[] = {0.0015, 0.002, 0.001}, densities[] = {3.0, 2.0, 1.0};
    for (int i = 0; i < 3; ++i)
      if (length(x - centres[i]) <= radii[i]) return densities[i];
    return 0.0;
  };
  test::write_vdb_file(dir / "balls.vdb", {g});
  expect_white_furnace(
      test::furnace_scene(
          fmt::format(R"(, "density": {{"field": "grid", "file": "{}"}})", (dir / "balls.vdb").string()), "path"),
      "grid density");
}

// The same furnace lit by a uniform environment map instead of the background, around a ball of
// the medium whose index is that of the vacuum outside (n = 1): next-event estimation from the
// medium vertices reaches the map through the index-matched boundary and is weighted against
// phase sampling, so this checks that the two strategies share the light without loss or excess.
TEST(Scattering, WhiteFurnaceUnderAnEnvironmentMapWithNextEventEstimation) {
  const std::string json =
      under_a_white_map(test::furnace_scene("", "path"), test::scratch_dir("scattering_env_furnace"));
  const SceneDesc desc = parse_scene(json, "furnace.json");
  ASSERT_TRUE(desc.environment.has_value());
  for (const SpectralMode mode : {SpectralMode::full, SpectralMode::hero}) {
    const Film f = render(desc, mode, 12288);  // blue's standard error: 0.0010 in full, 0.0012 in hero
    for (int c = 0; c < 3; ++c) {
      const Estimate e = channel_estimate(f, c, 0, 0, f.width, f.height);
      std::printf("environment furnace (%s) ch %d: %.5f ± %.5f\n", mode == SpectralMode::full ? "full" : "hero", c,
                  e.mean, e.standard_error);
      EXPECT_NEAR(e.mean, 1.0, 0.005) << "ch " << c;
      EXPECT_LT(3.0 * e.standard_error, 0.005) << "ch " << c << ": too few samples for the tolerance";
    }
  }
}

// Single scattering: a slab (n = 1, so its faces neither reflect nor refract) with σ_s·d = 0.01 at
// 550 nm, against black, lit from below by a distant light at μ = cos 45° to the slab's normal;
// the camera looks straight down. Once-scattered radiance at depth z (from the top face):
//   L = E σ_s p(μ) ∫₀^d e^{−σ_s z} e^{−σ_s (d − z)/μ} dz,
// per bin; light scattered more than once adds about σ_s·d (1 %) more, inside the 2 % tolerance.
TEST(Scattering, ThinSlabMatchesSingleScattering) {
  const double d_m = 0.01, mu = std::cos(std::numbers::pi / 4);
  const std::string json = fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0.5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
                "width": "10 mm", "resolution": [32, 32]}},
    "render": {{"integrator": "path", "spectral": "full", "spp": 2048, "max_depth": 64}},
    "world_medium": "vacuum",
    "media": {{"haze": {{"ior": 1.0, "scattering": {{"rayleigh": {{"at_nm": 550, "value_per_m": 1.0}},
                                                  "phase": {{"type": "henyey_greenstein", "g": 0.3}}}}}}}},
    "objects": [{{"name": "slab", "shape": {{"type": "box", "size": ["40 mm", "10 mm", "40 mm"]}}, "inside": "haze"}}],
    "lights": [{{"type": "distant", "direction": [0, {}, {}], "spectrum": "E", "scale": 1}}]
  }})",
                                       mu, -mu);
  const SceneDesc desc = parse_scene(json, "slab.json");
  const Film f = test::render_desc(desc);
  const auto basis = make_full_basis();
  const auto sigma = basis.emission(desc.media.at("haze").scattering->sigma_s_per_m);
  const auto e = basis.emission(desc.lights.at(0).intensity);
  const double g = 0.3, cos_theta = mu;  // between the light's direction of travel (up, tilted) and +y
  const double p = (1 - g * g) / (4 * std::numbers::pi * std::pow(1 + g * g - 2 * g * cos_theta, 1.5));
  SampledSpectrum<kFullBins> l;
  for (std::size_t i = 0; i < kFullBins; ++i) {
    const double s = sigma[i];
    const double a = s * (1.0 - 1.0 / mu);  // exponent rate in z
    const double integral = std::exp(-s * d_m / mu) * -std::expm1(-a * d_m) / a;
    l[i] = static_cast<float>(e[i] * s * p * integral);
  }
  const Vec3 expected = basis.to_linear_srgb(l);
  for (int c = 0; c < 3; ++c) {
    const Estimate got = channel_estimate(f, c, 0, 0, f.width, f.height);
    std::printf("single scattering ch %d: %.6f ± %.6f, closed form %.6f\n", c, got.mean, got.standard_error, expected[c]);
    EXPECT_NEAR(got.mean, expected[c], 0.02 * expected[c]) << "ch " << c;
    EXPECT_LT(3.0 * got.standard_error, 0.02 * expected[c]) << "ch " << c << ": too few samples";
  }
}

// A scattering medium with σ_s = 0 is its absorbing medium: docs/rendering.md's claim that it
// "renders as the absorbing one". A red-wine tumbler over a white floor under a lamp, once with the
// liquid's scattering block at σ_s = 0 and once without the block, by the path tracer and bdpt in
// both modes. The two walks draw different random numbers (the scattering medium's tracking draws
// its own), so the images are compared as estimates: the mean pixel difference per channel within
// 4 of its standard errors (the pixels are independent), which must stay under 0.5 % of the image
// mean, so that a σ_s = 0 medium that lost or gained 2 % of the light (its transmittance applied
// twice, a tracking weight that is not 1) fails.
TEST(Scattering, ZeroScatteringRendersAsTheAbsorbingMedium) {
  auto scene = [](const char* scattering) {
    return fmt::format(R"({{
      "camera": {{"position": [0, "80 mm", "200 mm"], "look_at": [0, "30 mm", 0], "fov_deg": 30, "resolution": [16, 16]}},
      "render": {{"max_depth": 32, "seed": 3}},
      "media": {{"glass": {{"ior": 1.5}},
                 "wine": {{"ior": 1.34, "absorption": {{"library": "red-wine", "concentration": 0.3}}{}}}}},
      "objects": [
        {{"name": "tumbler", "shape": {{"type": "vessel", "wall": "2 mm", "fill": 0.8, "segments": 32,
                   "profile": [[0, 0], ["25 mm", 0], ["27 mm", "70 mm"]]}}, "inside": "glass", "contents": "wine"}},
        {{"name": "floor", "shape": {{"type": "quad", "size": [1, 1]}}, "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}],
          "material": {{"type": "diffuse", "reflectance": 0.8}}}},
        {{"name": "lamp", "shape": {{"type": "disk", "radius": "40 mm", "segments": 32}},
          "transform": [{{"rotate_deg": [90, [1, 0, 0]]}}, {{"translate": [0.05, 0.3, 0.05]}}],
          "emission": {{"spectrum": "D65", "scale": 10}}}}
      ],
      "background": {{"spectrum": "D65", "scale": 0.2}}
    }})",
                       scattering);
  };
  const char* zero = R"(, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700], "value": [0, 0],
                                          "phase": {"type": "henyey_greenstein", "g": 0.5}})";
  for (const IntegratorType integrator : {IntegratorType::path, IntegratorType::bdpt})
    for (const SpectralMode mode : {SpectralMode::full, SpectralMode::hero}) {
      SceneDesc with = parse_scene(scene(zero), "zero.json"), without = parse_scene(scene(""), "absorbing.json");
      ASSERT_TRUE(with.media.at("wine").scattering.has_value());
      for (SceneDesc* d : {&with, &without}) {
        d->render.integrator = integrator, d->render.spectral = mode;
        d->render.spp = integrator == IntegratorType::bdpt ? 512 : 256;  // bdpt's colour noise is larger here
      }
      const Film a = test::render_desc(with), b = test::render_desc(without);
      for (int c = 0; c < 3; ++c) {
        const Estimate d = test::difference_estimate(b, a, c);
        const double mean = channel_estimate(b, c, 0, 0, b.width, b.height).mean;
        std::printf("σ_s = 0 − absorbing (%s, %s) ch %d: %+.5f ± %.5f (%.2f %% of %.5f)\n",
                    integrator_info(integrator).name.data(), mode == SpectralMode::full ? "full" : "hero", c, d.mean,
                    d.standard_error, 100.0 * d.standard_error / mean, mean);
        EXPECT_LT(std::abs(d.mean), 4.0 * d.standard_error) << integrator_info(integrator).name << " ch " << c;
        EXPECT_LT(d.standard_error, 0.005 * mean) << integrator_info(integrator).name << " ch " << c << ": too noisy";
      }
    }
}

// Full and hero carry different wavelengths but estimate the same image: a ball of a chromatic
// scattering and absorbing medium (index 1) under a grey sky, lit by an area lamp above. Each
// channel's image mean of hero's pixels less full's within 4 standard errors of it (from the
// pixels' differences: every pixel's has mean 0, and the pixels are independent), those under
// 1.5 % of the mean: a hero-mode bias in the spectral MIS of chromatic scattering that shifts the
// ball's colour, by more than about 0.5 % in red and green or 1.5 % in blue, would show (one that
// shifted it one way at the centre and the other at the rim, keeping the mean, would not).
// Measured at 4096 spp: +0.16 %, +0.04 % and +0.21 % of the means (red, green, blue), 4 standard
// errors 0.45 %, 0.45 % and 1.3 %. (It compared the images by mean ΔE00 below 0.5 at 16384 spp,
// whose noise floor was 0.25, in four times the time.)
TEST(Scattering, FullAndHeroConvergeOnAChromaticScatteringScene) {
  const std::string json = fmt::format(R"({{
    "camera": {{"position": [0, 0.03, 0.12], "look_at": [0, 0.0, 0], "fov_deg": 16, "resolution": [8, 8]}},
    "render": {{"integrator": "path", "max_depth": 64}},
    "world_medium": "vacuum",
    "media": {{"milky": {{"ior": 1.0, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                                                    "value": [5, 40]}},
                        "scattering": {{{}, "phase": {{"type": "henyey_greenstein", "g": 0.5}}}}}}}},
    "objects": [
      {{"name": "ball", "shape": {{"type": "sphere", "radius": "15 mm", "segments": 48}}, "inside": "milky"}},
      {{"name": "lamp", "shape": {{"type": "quad", "size": [0.06, 0.06]}},
        "transform": [{{"rotate_deg": [90, [1, 0, 0]]}}, {{"translate": [0.03, 0.08, 0.0]}}],
        "emission": {{"spectrum": "D65", "scale": 8}}}}
    ],
    "background": {{"spectrum": "D65", "scale": 0.5}}
  }})",
                                       kChromaticSigmaS);
  const SceneDesc desc = parse_scene(json, "ball.json");
  const Film full = render(desc, SpectralMode::full, 4096, 1), hero = render(desc, SpectralMode::hero, 4096, 2);
  for (int c = 0; c < 3; ++c) {
    const double m = test::channel_estimate(full, c, 0, 0, full.width, full.height).mean;
    const test::Estimate d = test::difference_estimate(full, hero, c);
    std::printf("chromatic scattering ball, ch %d: full %.5f, hero − full %+.5f ± %.5f (%+.2f %%)\n", c, m, d.mean,
                d.standard_error, 100.0 * d.mean / m);
    EXPECT_LT(std::abs(d.mean), 4.0 * d.standard_error) << "ch " << c;
    EXPECT_LT(4.0 * d.standard_error, 0.015 * m) << "ch " << c << ": too noisy";
  }
}

// The mean colour of each b × b block of pixels: a whole-milk ball's pixels are too noisy at a
// test's sample count for a per-pixel ΔE00 to say anything (colour speckle, #20), so the test
// compares blocks.
Film block_means(const Film& f, int b) {
  Film out(f.width / b, f.height / b);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      Vec3f sum{};
      for (int j = 0; j < b; ++j)
        for (int i = 0; i < b; ++i) sum = sum + f.rgb_at(x * b + i, y * b + j);
      out.set_rgb(x, y, sum * (1.0f / static_cast<float>(b * b)));
    }
  return out;
}

// A sealed medium (SceneMedium::sealed): enclosed, and of an index no other medium of the scene
// shares, so the map's straight shadow ray from inside it always stops at its refracting boundary.
// The whole-milk ball of tests/data/whole_milk_ball under its sky: sealed; the same with the milk's
// index that of the vacuum around it, or beside a skimmed-milk ball (the same host index), not;
// the world's medium never. The path tracer's image of the sealed ball is bit for bit the one
// with the flag cleared (the rays it skipped brought nothing), with fewer rays; the index-matched
// ball's image, whose map light comes through its surface by those rays, changes when the flag is
// forced on. What it catches: a medium called sealed whose shadow rays leave it (the index-matched
// ball: its image changes), a skip that moves the random numbers (the sealed ball's image changes
// wherever a path scatters in the milk: measured, 25 of its 64 pixels), and a rule that seals
// nothing or too much (the flag checks).
TEST(Scattering, ASealedMediumSkipsTheMapsShadowRaysAndNothingElse) {
  auto ball = [](const char* milk, const char* beside = "") {
    return parse_scene(fmt::format(R"({{
      "camera": {{"position": [0, "2 mm", "24 mm"], "look_at": [0, 0, 0], "fov_deg": 12, "resolution": [8, 8]}},
      "render": {{"integrator": "path", "spectral": "hero", "spp": 4, "max_depth": 64, "seed": 3}},
      "world_medium": "vacuum",
      "media": {{"milk": {{{}"scattering": {{"library": "whole_milk"}}}},
                 "skimmed": {{"scattering": {{"library": "skimmed_milk"}}}}}},
      "objects": [{{"name": "ball", "shape": {{"type": "sphere", "radius": "1.5 mm"}}, "inside": "milk"}}{}],
      "background": {{"environment": "{}"}}
    }})", milk, beside, test::test_data("whole_milk_ball/sky.pfm").string()), "sealed.json");
  };
  auto render_with = [](const SceneDesc& desc, RenderScene& scene, bool sealed, std::uint64_t& rays) {
    const int milk = scene.surfaces[0].medium_behind;
    scene.media[static_cast<std::size_t>(milk)].sealed = sealed;
    RenderStats stats;
    const Film f = render(scene, desc.render, RenderControl{}, stats);
    rays = stats.rays;
    return f;
  };
  auto same_pixels = [](const Film& a, const Film& b) {
    int same = 0;
    for (int y = 0; y < a.height; ++y)
      for (int x = 0; x < a.width; ++x) {
        const Vec3f pa = a.rgb_at(x, y), pb = b.rgb_at(x, y);
        same += std::memcmp(&pa, &pb, sizeof(Vec3f)) == 0;
      }
    return same;
  };
  {
    const SceneDesc desc = ball("");
    RenderScene scene = compile(desc);
    const int milk = scene.surfaces[0].medium_behind;
    ASSERT_GE(milk, 0);
    EXPECT_TRUE(scene.media[static_cast<std::size_t>(milk)].sealed);
    EXPECT_FALSE(scene.media[static_cast<std::size_t>(scene.world_medium)].sealed);
    std::uint64_t skipped = 0, traced = 0;
    const Film a = render_with(desc, scene, true, skipped), b = render_with(desc, scene, false, traced);
    std::printf("sealed milk ball: %d of %d pixels the same with the flag cleared; rays %llu against %llu\n",
                same_pixels(a, b), a.width * a.height, static_cast<unsigned long long>(skipped),
                static_cast<unsigned long long>(traced));
    EXPECT_EQ(same_pixels(a, b), a.width * a.height);
    EXPECT_LT(skipped, traced);
  }
  {
    const SceneDesc desc = ball(R"("ior": 1, )");
    RenderScene scene = compile(desc);
    EXPECT_FALSE(scene.media[static_cast<std::size_t>(scene.surfaces[0].medium_behind)].sealed);
    std::uint64_t rays = 0;
    const Film a = render_with(desc, scene, false, rays), b = render_with(desc, scene, true, rays);
    const int same = same_pixels(a, b);
    std::printf("index-matched milk ball: %d of %d pixels the same with the flag forced on\n", same,
                a.width * a.height);
    EXPECT_GE(a.width * a.height - same, a.width * a.height / 4) << "the ball covers about 0.28 of the picture";
  }
  {
    const RenderScene scene = compile(ball("", R"(, {"name": "skimmed", "shape": {"type": "sphere", "radius": "1 mm"},
      "inside": "skimmed", "transform": [{"translate": ["4 mm", 0, 0]}]})"));
    EXPECT_FALSE(scene.media[static_cast<std::size_t>(scene.surfaces[0].medium_behind)].sealed)
        << "another medium of the milk's index is in the scene";
  }
}

// The whole-milk reference (#20): a 1.5 mm ball of the library's whole_milk (σ_s 71 000 to 20 000
// per m from 400 to 700 nm, g = 0.86, albedo 0.9995–0.9998; about 130 rays a path) under a grey sky
// brighter towards the zenith (tests/data/whole_milk_ball). The production walk (full: the camera
// path splits at the milk into 4 walks of one wavelength each, their bins drawn by a density that
// follows the colour-matching functions from a number stratified over the pixel's samples:
// integrators/dense_media.h, kSplitCount), 16 × 16 at 128 spp, against reference.exr there: a
// brute-force render that tracks every path at one wavelength alone at 16384 spp (make_reference.sh
// says how; README.md how long it took). A pixel is too noisy for its ΔE00 to say much (mean 3.4 at
// 32 spp), so the images are compared as 4 × 4 blocks of 4 × 4 pixels. The test's own spread,
// measured by rendering it at seeds 1–8: blocks' mean ΔE00 to the reference 0.48–0.88, mean 0.65,
// standard deviation 0.14 (2026-12-07; with the bins drawn by the eye's sensitivity, 0.60–0.92,
// 0.71 and 0.11); the tolerance is that mean plus 4 deviations. At 32 spp the spread was
// 1.10 ± 0.07 before the thinned next-event estimation and the split walks' roulette
// (integrators/dense_media.h, walk.h) and is 1.29 ± 0.27 after: they make a sample cheaper (the
// test 1.1 s instead of 2.3 s at 32 spp) with heavier tails, hence 128 spp. (Before the split, the
// spectral-MIS walk needed 128 spp for 1.96 ± 0.15.) What it catches is a walk that converges to
// another colour: bins drawn by the eye's sensitivity but weighted as if uniform give 11.8. Small
// errors of scale are the furnaces' to catch: the split walks' weight 3 % too high gave 1.32
// against 1.20 (seed 1, at 32 spp before the thinning).
TEST(Scattering, WholeMilkBallMatchesItsReference) {
  // The blocks' mean ΔE00 over seeds 1–8 at 128 spp, where the path splits into walks of one
  // wavelength each (integrators/dense_media.h: kSplitCount).
  constexpr double kNoiseMean = 0.65, kNoiseDeviation = 0.14;
  constexpr double kTolerance = kNoiseMean + 4.0 * kNoiseDeviation;
  SceneDesc desc = load_scene(test::test_data("whole_milk_ball/scene.json"));
  desc.render.spp = 128;
  const auto start = std::chrono::steady_clock::now();
  const Film f = test::render_desc(desc);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const Film reference = read_exr(test::test_data("whole_milk_ball/reference.exr"));
  const double blocks = compare_images(block_means(f, 4), block_means(reference, 4)).mean;
  std::printf("whole milk ball, %d spp against its reference: mean ΔE00 of 4x4 blocks %.3f (tolerance %.3f), of "
              "pixels %.3f; %.1f s\n",
              desc.render.spp, blocks, kTolerance, compare_images(f, reference).mean, seconds);
  EXPECT_LT(blocks, kTolerance);
}

// The light tracer splats medium vertices through the phase function: on a slab lit from below by
// an area lamp (whose back the camera sees: black) it reaches the same radiance as the path
// tracer's next-event estimation; index-matched faces let the connections through.
TEST(Scattering, LightTracerAgreesWithThePathTracerInAMedium) {
  const std::string json = R"({
    "camera": {"type": "orthographic", "position": [0, 0.5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
               "width": "30 mm", "resolution": [12, 12]},
    "render": {"spectral": "hero", "max_depth": 64},
    "world_medium": "vacuum",
    "media": {"haze": {"ior": 1.0, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                                                  "value": [40, 10], "phase": {"type": "isotropic"}}}},
    "objects": [
      {"name": "slab", "shape": {"type": "box", "size": ["40 mm", "10 mm", "40 mm"]}, "inside": "haze"},
      {"name": "lamp", "shape": {"type": "quad", "size": [0.04, 0.04]},
       "transform": [{"rotate_deg": [-90, [1, 0, 0]]}, {"translate": [0.0, -0.03, 0.0]}],
       "emission": {"spectrum": "D65", "scale": 5}}
    ]
  })";
  SceneDesc desc = parse_scene(json, "slab.json");
  desc.render.integrator = IntegratorType::path;
  const Film path = render(desc, SpectralMode::hero, 1024);
  desc.render.integrator = IntegratorType::light;
  const Film light = render(desc, SpectralMode::hero, 2048);
  for (int c = 0; c < 3; ++c) {
    const Estimate p = channel_estimate(path, c, 2, 2, 10, 10), l = channel_estimate(light, c, 2, 2, 10, 10);
    const double se = std::hypot(p.standard_error, l.standard_error);
    std::printf("medium, path %.5f ± %.5f vs light %.5f ± %.5f (ch %d)\n", p.mean, p.standard_error, l.mean,
                l.standard_error, c);
    EXPECT_NEAR(p.mean, l.mean, 0.02 * p.mean) << "ch " << c;
    EXPECT_LT(3.0 * se, 0.02 * p.mean) << "ch " << c << ": too few samples";
  }
}

// --- Tracking through a voxel grid density (media/majorant.h): the majorant of each cell ---

// The spectral tables as the tracking sees them: σ_s per wavelength, no absorbers.
struct TestTables {
  SampledSpectrum<4> sigma_s;
  SampledSpectrum<4> at(int, const SampledWavelengths<4>&) const { return sigma_s; }
  float at_index(int, const SampledWavelengths<4>&, std::size_t j) const { return sigma_s[j]; }
  SampledSpectrum<4> transmittance(std::span<const OpticalDepthTerm>, const SampledWavelengths<4>&) const {
    return SampledSpectrum<4>::constant(1.0f);
  }
  float kept_transmittance(std::span<const OpticalDepthTerm>, const SampledWavelengths<4>&) const { return 1.0f; }
};
struct TestRay {
  Vec3 origin, direction;
};

// A sparse grid: 34³ nodes of 0.5 mm (zero border), centred on the origin, empty but for three
// balls of 2 to 3 voxels' radius with densities 2, 3 and 4 (0.4 % of the cells hold density).
struct DensityBall {
  Vec3 centre;  // in index space
  double radius, density;
};
constexpr DensityBall kBalls[] = {{{10, 12, 15}, 2.5, 4.0}, {{22, 20, 17}, 3.0, 2.0}, {{16, 17, 24}, 2.0, 3.0}};
constexpr double kIndexPerM = 2000.0, kIndexAtOrigin = 16.5;

GridField sparse_grid() {
  constexpr int n = 34;
  auto values = std::make_shared<GridValues>();
  values->nodes = {n, n, n};
  values->value.assign(std::size_t{n} * n * n, 0.0f);
  for (int k = 1; k < n - 1; ++k)
    for (int j = 1; j < n - 1; ++j)
      for (int i = 1; i < n - 1; ++i)
        for (const DensityBall& b : kBalls)
          if (length(Vec3{double(i), double(j), double(k)} - b.centre) <= b.radius)
            values->value[values->index(i, j, k)] = static_cast<float>(b.density);
  values->max_value = 4.0f;
  GridField f;
  f.values = values;
  f.index_per_m = Mat3::diagonal({kIndexPerM, kIndexPerM, kIndexPerM});
  f.index_at_origin = {kIndexAtOrigin, kIndexAtOrigin, kIndexAtOrigin};
  return f;
}

ScatteringMedium grid_medium(const GridField& f) {
  ScatteringMedium m;
  m.sigma_s = 0;
  m.density = f;
  return m;
}

// Rays 20 mm long whose middles are uniform within 4 mm of the grid's centre (most miss the
// balls), or within 0.5 mm of a ball's centre (`at_balls`).
std::vector<TestRay> rays_across(int count, std::uint64_t seed, bool at_balls = false) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<TestRay> rays;
  for (int i = 0; i < count; ++i) {
    const Vec3 d = normalize(Vec3{n(rng), n(rng), n(rng)});
    const Vec3 ball = (kBalls[i % 3].centre - Vec3{kIndexAtOrigin, kIndexAtOrigin, kIndexAtOrigin}) / kIndexPerM;
    const Vec3 middle = at_balls ? ball + Vec3{u(rng), u(rng), u(rng)} * 0.0005 : Vec3{u(rng), u(rng), u(rng)} * 0.004;
    rays.push_back({middle - d * 0.01, d});
  }
  return rays;
}
constexpr double kRayLengthM = 0.02;

SampledWavelengths<4> four_wavelengths(int hero) {
  SampledWavelengths<4> w;
  w.mode = SpectralMode::hero;
  w.nm = {450, 500, 550, 600};
  w.hero = hero;
  return w;
}

// Ratio tracking through the sparse grid is an unbiased transmittance at every carried
// wavelength, as a connection uses it (divided by the mean of its r_l ratios: the one-sample
// balance combination over the wavelengths, the hero taking each in turn): the mean over 16384
// tracks is exp(−σ_s,k·∫ρ dt), ∫ρ the exact column density, within 0.02 on each of 48 rays through
// the balls (optical depths up to about 4; 3 standard errors, at most 0.018, must fit in the
// tolerance).
TEST(Scattering, RatioTrackingThroughAGridDensityMatchesItsColumnDensity) {
  const ScatteringMedium m = grid_medium(sparse_grid());
  const TestTables tables{{{300.0f, 200.0f, 120.0f, 80.0f}}};
  Rng rng(5, 0);
  int dense = 0;
  for (const TestRay& ray : rays_across(48, 3, true)) {
    constexpr int kTracks = 16384;
    SampledSpectrum<4> sum, sum2;
    for (int j = 0; j < kTracks; ++j) {
      SampledSpectrum<4> tr = SampledSpectrum<4>::constant(1.0f);
      SpectralMis<4> mis;
      ratio_track(m, tables, ray, kRayLengthM, four_wavelengths(j % 4), rng, tr, mis);
      const SampledSpectrum<4> estimate = tr / mis.r_l.average();
      sum += estimate;
      sum2 += estimate * estimate;
    }
    const double column = scattering_column_density(m, ray, 0.0, kRayLengthM);
    if (tables.sigma_s[0] * column > 1.0) ++dense;
    for (std::size_t k = 0; k < 4; ++k) {
      const double mean = sum[k] / kTracks, se = std::sqrt(std::max(0.0, sum2[k] / kTracks - mean * mean) / kTracks);
      const double exact = std::exp(-tables.sigma_s[k] * column);
      EXPECT_NEAR(mean, exact, 0.02) << "column " << column << " λ " << k;
      EXPECT_LT(3.0 * se, 0.02) << "column " << column << " λ " << k << ": too few tracks";
    }
  }
  EXPECT_GT(dense, 24);  // the test must cross the balls, not only the empty grid
}

// In a constant density the majorant is the medium itself, so ratio tracking's estimate is a coin
// toss (0 at the first tentative collision, which is real); ratio_track returns its expectation
// given the hero instead: exp(−σ_s,k·ρ·t) at every wavelength on every call, whatever the random
// numbers, with the ratios of a walk without collision, exp(−(σ_s,k − σ_s,hero)·ρ·t), so that the
// one-sample combination over the heroes, tr / mean(r_l), is the exact transmittance too. The toss
// fails each check (tr 0, or f times 1 where exp(−σ_hero·ρ·t) was due); a wrong rate fails them all.
TEST(Scattering, TrackingThroughAConstantDensityIsItsExpectation) {
  ScatteringMedium m;
  m.sigma_s = 0;
  m.density = ConstantField{2.0};
  const TestTables tables{{{300.0f, 200.0f, 120.0f, 80.0f}}};
  const TestRay ray{{0.0, 0.0, 0.0}, normalize(Vec3{1.0, 2.0, 2.0})};
  constexpr double kLengthM = 0.01;  // optical depths 6, 4, 2.4 and 1.6
  Rng rng(7, 3);
  std::array<double, 4> combined{};
  for (int hero = 0; hero < 4; ++hero) {
    for (int j = 0; j < 64; ++j) {
      SampledSpectrum<4> tr = SampledSpectrum<4>::constant(1.0f);
      SpectralMis<4> mis;
      ratio_track(m, tables, ray, kLengthM, four_wavelengths(hero), rng, tr, mis);
      for (std::size_t k = 0; k < 4; ++k) {
        const double exact = std::exp(-tables.sigma_s[k] * 2.0 * kLengthM);
        const double ratio = std::exp(-(tables.sigma_s[k] - tables.sigma_s[static_cast<std::size_t>(hero)]) * 2.0 * kLengthM);
        EXPECT_NEAR(tr[k], exact, 1e-5 * exact) << "hero " << hero << " λ " << k;
        EXPECT_NEAR(mis.r_l[k], ratio, 1e-5 * ratio) << "hero " << hero << " λ " << k;
        EXPECT_NEAR(mis.r_u[k], ratio, 1e-5 * ratio) << "hero " << hero << " λ " << k;
        if (j == 0) combined[k] += tr[k] / mis.r_l.average() / 4.0;
      }
    }
  }
  for (std::size_t k = 0; k < 4; ++k) {
    const double exact = std::exp(-tables.sigma_s[k] * 2.0 * kLengthM);
    EXPECT_NEAR(combined[k], exact, 1e-5 * exact) << "λ " << k;
  }
}

// walk_deep takes a collision deep in a constant density from first_collision_m (a copy of the
// stream) and take_first_collision, not by tracking: the same distance, throughput (with an
// absorber, whose transmittance here is exp(−40·length)) and stream as sample_scattering's, bit for
// bit, for one wavelength carried; walks on from each and on to the next collision.
TEST(Scattering, ACollisionTakenWhereItWasFoundIsSampleScatteringsOwn) {
  struct AbsorbingTables : TestTables {
    float kept_transmittance(std::span<const OpticalDepthTerm> terms, const SampledWavelengths<4>&) const {
      double length = 0.0;
      for (const OpticalDepthTerm& term : terms) length += term.length;
      return static_cast<float>(std::exp(-40.0 * length));
    }
  };
  const AbsorbingTables tables{{{{300.0f, 200.0f, 120.0f, 80.0f}}}};
  for (const bool absorbing : {false, true}) {
    ScatteringMedium m;
    m.sigma_s = 0;
    m.density = ConstantField{2.5};
    if (absorbing) m.absorbers.push_back(FieldAbsorber{1, ConstantField{0.5}});
    Rng seeds(5, 1);
    int taken = 0;
    for (int j = 0; j < 400; ++j) {
      SampledWavelengths<4> w = four_wavelengths(j % 4);
      w.terminate_secondary((j / 4) % 4, 500.0);
      const auto kept = static_cast<std::size_t>(w.single);
      const TestRay ray{{0.01 * j, 0.0, 0.0}, normalize(Vec3{1.0, 2.0 + j, 2.0})};
      const double t_max = 0.002 + 0.00002 * j;
      Rng walk(seeds.next_u32(), 9);
      Rng deep = walk;
      SampledSpectrum<4> beta = SampledSpectrum<4>::constant(0.0f), beta_deep;
      beta[kept] = 0.75f;
      beta_deep = beta;
      SpectralMis<4> mis;
      const MediumEvent e = sample_scattering(m, tables, ray, t_max, w, walk, beta, mis);
      const double t = first_collision_m(m, tables, w, kept, deep);
      ASSERT_EQ(e.scattered, t < t_max) << j;
      if (!e.scattered) continue;
      ++taken;
      take_first_collision(m, tables, ray, t, w, kept, deep, beta_deep);
      EXPECT_EQ(e.t, t) << j;
      EXPECT_EQ(beta[kept], beta_deep[kept]) << j;
      EXPECT_EQ(walk.next_u32(), deep.next_u32()) << j;
      EXPECT_EQ(mis.r_l[kept], 1.0f);
    }
    EXPECT_GT(taken, 100);
  }
}

// Delta tracking draws the first real collision with the analog density σ_s ρ(t) exp(−σ_s∫₀ᵗρ)
// at every wavelength (the hero's directly, the others through their weights): the weighted
// fraction of walks scattering before t, and passing through, against the exact column density,
// within 0.02 (40000 walks on each of 12 rays through the balls: 3 standard errors at most 0.015).
TEST(Scattering, DistancesThroughAGridDensityFollowTheAnalogDensity) {
  const ScatteringMedium m = grid_medium(sparse_grid());
  const TestTables tables{{{250.0f, 200.0f, 150.0f, 100.0f}}};
  const double quantiles[] = {0.25, 0.5, 0.75};
  Rng rng(9, 1);
  for (const TestRay& ray : rays_across(12, 4, true)) {
    constexpr int kWalks = 40000;
    // Per wavelength: the weighted indicator of a collision before each quantile, and of none.
    std::array<std::array<double, 4>, 4> sum{}, sum2{};
    for (int j = 0; j < kWalks; ++j) {
      SampledSpectrum<4> beta = SampledSpectrum<4>::constant(1.0f);
      SpectralMis<4> mis;
      const MediumEvent e = sample_scattering(m, tables, ray, kRayLengthM, four_wavelengths(j % 4), rng, beta, mis);
      for (std::size_t k = 0; k < 4; ++k)
        for (std::size_t q = 0; q < 4; ++q) {
          const bool hit = q < 3 ? e.scattered && e.t < quantiles[q] * kRayLengthM : !e.scattered;
          const double v = hit ? beta[k] : 0.0;
          sum[k][q] += v;
          sum2[k][q] += v * v;
        }
    }
    const double column = scattering_column_density(m, ray, 0.0, kRayLengthM);
    for (std::size_t k = 0; k < 4; ++k)
      for (std::size_t q = 0; q < 4; ++q) {
        const double sigma = tables.sigma_s[k];
        const double expected =
            q < 3 ? -std::expm1(-sigma * scattering_column_density(m, ray, 0.0, quantiles[q] * kRayLengthM))
                  : std::exp(-sigma * column);
        const double mean = sum[k][q] / kWalks;
        const double se = std::sqrt(std::max(0.0, sum2[k][q] / kWalks - mean * mean) / kWalks);
        EXPECT_NEAR(mean, expected, 0.02) << "λ " << k << (q < 3 ? " before quantile " : " through ") << q;
        EXPECT_LT(3.0 * se, 0.02) << "λ " << k << " quantile " << q << ": too few walks";
      }
  }
}

// The walk of before (for the comparison below only): the segment in 8 equal pieces, each with
// the largest density of the cells it crosses; how many tentative collisions a full traversal
// draws (a ratio tracking that never stops).
int eight_piece_collisions(const ScatteringMedium& m, double sigma, const TestRay& ray, double t_max, Rng& rng,
                           double& real_sum) {
  int collisions = 0;
  for (int p = 0; p < kMajorantPieces; ++p) {
    const double a = t_max * p / kMajorantPieces, b = t_max * (p + 1) / kMajorantPieces;
    const double rho_bar = max_concentration_on(m.density, ray.origin, ray.direction, a, b);
    if (!(rho_bar > 0.0)) continue;
    for (double t = a;;) {
      t += -std::log1p(-rng.next_double()) / (sigma * rho_bar);
      if (t >= b) break;
      ++collisions;
      real_sum += concentration_at(m.density, ray.origin + ray.direction * t) / rho_bar;
    }
  }
  return collisions;
}

// On the sparse grid a full traversal draws its tentative collisions from the cells' majorants:
// as many as σ·∫ρ̄ dt predicts (the walk uses the majorant it reports), and far fewer null
// collisions than with the 8 pieces of before. Both counts and times are printed.
TEST(Scattering, AGridMajorantTakesFewNullCollisionsInASparseGrid) {
  const ScatteringMedium m = grid_medium(sparse_grid());
  const double sigma = 200.0;
  const std::vector<TestRay> rays = rays_across(2000, 6);
  constexpr int kRepeats = 20;
  Rng rng(13, 2);
  double dda_tentative = 0.0, dda_real = 0.0, dda_expected = 0.0, dda_seconds = 0.0;
  double eight_tentative = 0.0, eight_real = 0.0, eight_seconds = 0.0;
  for (const TestRay& ray : rays) {
    auto start = std::chrono::steady_clock::now();
    for (int r = 0; r < kRepeats; ++r) {
      const detail::MajorantWalk walk =
          detail::walk_majorant(m, sigma, ray, kRayLengthM, rng, [&](double, double real) {
            dda_real += real;
            return true;
          });
      dda_tentative += walk.collisions;
      dda_expected += sigma * walk.rho_length_m;  // the walk's own ∫ρ̄: all of the segment here
    }
    auto end = std::chrono::steady_clock::now();
    dda_seconds += std::chrono::duration<double>(end - start).count();
    start = end;
    for (int r = 0; r < kRepeats; ++r)
      eight_tentative += eight_piece_collisions(m, sigma, ray, kRayLengthM, rng, eight_real);
    eight_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const double walks = double(rays.size()) * kRepeats;
  // A DDA majorant's pieces partition the segment: ∫ρ̄ over them is fixed per ray, the collision
  // count Poisson with that mean.
  // The real ones (the sum of ρ/ρ̄ over the tentative collisions) have the mean σ·∫ρ dt and a
  // variance below their count's, whichever majorant drew them.
  double majorant_integral = 0.0, column = 0.0;
  for (const TestRay& ray : rays) {
    DensityMajorant majorant(m.density, ray.origin, ray.direction, kRayLengthM);
    for (MajorantSegment s; majorant.next(s);) majorant_integral += s.density * (s.t1 - s.t0);
    column += scattering_column_density(m, ray, 0.0, kRayLengthM);
  }
  const double expected = sigma * majorant_integral * kRepeats, expected_real = sigma * column * kRepeats;
  std::printf(
      "sparse grid, per walk: DDA %.3f tentative (%.3f real, %.3f null), 8 pieces %.3f tentative "
      "(%.3f real, %.3f null), σ∫ρ %.3f; %.2f µs against %.2f µs a walk\n",
      dda_tentative / walks, dda_real / walks, (dda_tentative - dda_real) / walks, eight_tentative / walks,
      eight_real / walks, (eight_tentative - eight_real) / walks, expected_real / walks, 1e6 * dda_seconds / walks,
      1e6 * eight_seconds / walks);
  EXPECT_NEAR(dda_expected, expected, 1e-9 * expected);
  EXPECT_NEAR(dda_tentative, expected, 4.0 * std::sqrt(expected));
  EXPECT_NEAR(dda_real, expected_real, 4.0 * std::sqrt(expected_real));
  EXPECT_NEAR(eight_real, expected_real, 4.0 * std::sqrt(expected_real));
  EXPECT_LT(dda_tentative - dda_real, 0.5 * (eight_tentative - eight_real));  // measured: 0.27
}

}  // namespace
}  // namespace bouguer
