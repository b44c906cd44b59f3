// Scattering media (#12): the null-scattering path tracer with spectral MIS against closed forms.
// Tolerances follow from the sample count: each test measures its own standard error and also
// requires it to be small enough that the stated tolerance is at least 3 standard errors.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "bouguer/io/image_io.h"
#include "bouguer/render/compare.h"
#include "bouguer/render/render.h"
#include "bouguer/render/spectral_sampling.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;
using test::channel_estimate;
using test::Estimate;
using test::kChromaticSigmaS;


Film render(SceneDesc desc, SpectralMode mode, int spp, std::uint64_t seed = 1) {
  desc.render.spectral = mode;
  desc.render.spp = spp;
  desc.render.seed = seed;
  return test::render_desc(desc);
}



void expect_white_furnace(const std::string& json, const std::string& what) {
  const SceneDesc desc = parse_scene(json, "furnace.json");
  for (const SpectralMode mode : {SpectralMode::full, SpectralMode::hero}) {
    const Film f = render(desc, mode, 8192);
    for (int c = 0; c < 3; ++c) {
      const Estimate e = channel_estimate(f, c, 0, 0, f.width, f.height);
      std::printf("white furnace (%s, %s) ch %d: %.5f ± %.5f\n", what.c_str(),
                  mode == SpectralMode::full ? "full" : "hero", c, e.mean, e.standard_error);
      EXPECT_NEAR(e.mean, 1.0, 0.005) << what << " ch " << c;
      EXPECT_LT(3.0 * e.standard_error, 0.005) << what << " ch " << c << ": too few samples for the tolerance";
    }
  }
}

TEST(Scattering, WhiteFurnaceHomogeneous) { expect_white_furnace(test::furnace_scene("", "path"), "homogeneous"); }

TEST(Scattering, WhiteFurnaceWithADensityField) {
  expect_white_furnace(
      test::furnace_scene(R"(, "density": {"field": "exponential", "axis": [0, 1, 0], "value": 1, "scale_length": "10 mm"})",
                          "path"),
      "exponential density");
}

// The same furnace lit by a uniform environment map instead of the background, around a ball of
// the medium whose index is that of the vacuum outside (n = 1): next-event estimation from the
// medium vertices reaches the map through the index-matched boundary and is weighted against
// phase sampling, so this checks that the two strategies share the light without loss or excess.
TEST(Scattering, WhiteFurnaceUnderAnEnvironmentMapWithNextEventEstimation) {
  const fs::path dir = test::scratch_dir("scattering_env_furnace");
  Film white(16, 8);
  std::fill(white.rgb.begin(), white.rgb.end(), 1.0f);
  write_pfm(dir / "white.pfm", white);
  std::string json = test::furnace_scene("", "path");
  auto replace = [&](const std::string& from, const std::string& to) {
    ASSERT_NE(json.find(from), std::string::npos) << from;
    json.replace(json.find(from), from.size(), to);
  };
  replace("\"ior\": 1.33", "\"ior\": 1.0");
  replace("\"background\": {\"spectrum\": \"D65\", \"scale\": 1}",
          fmt::format("\"background\": {{\"environment\": \"{}\"}}", (dir / "white.pfm").string()));
  const SceneDesc desc = parse_scene(json, "furnace.json");
  ASSERT_TRUE(desc.environment.has_value());
  for (const SpectralMode mode : {SpectralMode::full, SpectralMode::hero}) {
    const Film f = render(desc, mode, 16384);  // blue's standard error: 0.0013
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

// Full and hero carry different wavelengths but estimate the same image: a ball of a chromatic
// scattering and absorbing medium (index 1) under a grey sky, lit by an area lamp above. The
// noise floor (two full renders with different seeds) is a mean ΔE00 of 0.25 at 16384 spp on
// these 8 × 8 pixels; full against hero measured 0.34.
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
  const Film full = render(desc, SpectralMode::full, 16384, 1), hero = render(desc, SpectralMode::hero, 16384, 2);
  const ImageDifference d = compare_images(full, hero);
  std::printf("chromatic scattering ball, full vs hero at 16384 spp: mean ΔE00 %.3f, p95 %.3f\n", d.mean, d.p95);
  EXPECT_LT(d.mean, 0.5);
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

}  // namespace
}  // namespace bouguer
