// The thin dielectric sheet (materials/surface_bsdf.h, ThinDielectric): its closed form, its sampling
// and adjoint, and rendered: a sheet seen face-on before a uniform backlight transmits (1−R)/(1+R),
// and a hollow sheet ball in a white furnace keeps every path's energy (R' + T' = 1), in each
// estimator that can see it.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cmath>
#include <random>

#include "bouguer/materials/fresnel.h"
#include "bouguer/materials/surface_bsdf.h"
#include "bouguer/scene/description.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

constexpr std::size_t N3 = 3;

// R at normal incidence, and the sheet's transmittance there: (1 − R)/(1 + R), 0.923 at n = 1.5.
double normal_reflectance(double n) { return ((n - 1.0) / (n + 1.0)) * ((n - 1.0) / (n + 1.0)); }
double normal_transmittance(double n) { return (1.0 - normal_reflectance(n)) / (1.0 + normal_reflectance(n)); }

Vec3 random_direction(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Vec3 v;
  do v = {u(rng), u(rng), u(rng)};
  while (length(v) > 1.0 || length(v) < 1e-3);
  return normalize(v);
}

TEST(ThinDielectricBsdf, ClosedForms) {
  for (const double n : {1.33, 1.5, 2.4}) {
    const double r = normal_reflectance(n);
    EXPECT_NEAR(thin_dielectric_reflectance(1.0, n), 2.0 * r / (1.0 + r), 1e-12) << n;
    EXPECT_NEAR(1.0 - thin_dielectric_reflectance(1.0, n), normal_transmittance(n), 1e-12) << n;
    // Oblique: the series R + T²R(1 + R² + R⁴ + ...) of the single-face Fresnel reflectance.
    const double c = 0.4, r1 = fresnel_dielectric(c, 1.0, n);
    EXPECT_NEAR(thin_dielectric_reflectance(c, n), 2.0 * r1 / (1.0 + r1), 1e-12) << n;
    EXPECT_NEAR(thin_dielectric_reflectance(0.0, n), 1.0, 1e-12) << n;  // grazing: a mirror
  }
  EXPECT_NEAR(normal_transmittance(1.5), 0.923, 5e-4);
  EXPECT_EQ(thin_dielectric_reflectance(1.0, 1.0), 0.0);  // an index-matched sheet: nothing reflected
  // A sheet of lower index than its medium reflects totally beyond the critical angle.
  EXPECT_EQ(thin_dielectric_reflectance(0.3, 1.0 / 1.5), 1.0);
}

// Reflection is drawn with probability R' and carries weight 1; transmission goes straight through
// carrying the tint; both are delta lobes (eval and pdf 0), and the sheet is specular.
TEST(ThinDielectricBsdf, SamplesItsTwoDeltaLobesByTheirShares) {
  const Bsdf<N3> sheet = ThinDielectric<N3>{1.5, SampledSpectrum<N3>{{0.2f, 0.5f, 0.9f}}};
  EXPECT_TRUE(is_specular(sheet));
  const Vec3 wo = normalize(Vec3{0.6, -0.2, 0.5});
  const double rp = thin_dielectric_reflectance(wo.z, 1.5);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  constexpr int n = 200000;
  int reflected = 0;
  for (int i = 0; i < n; ++i) {
    const auto s = sample(sheet, wo, u(rng), u(rng), u(rng), TransportMode::radiance);
    ASSERT_TRUE(s);
    EXPECT_EQ(s->pdf, 0.0);
    if (!s->transmitted) {
      ++reflected;
      ASSERT_NEAR(length(s->wi - Vec3{-wo.x, -wo.y, wo.z}), 0.0, 1e-15);
      ASSERT_EQ(s->weight[0], 1.0f);
    } else {
      ASSERT_NEAR(length(s->wi + wo), 0.0, 1e-15);
      ASSERT_EQ(s->weight[0], 0.2f);
      ASSERT_EQ(s->weight[2], 0.9f);
    }
  }
  // A binomial count: 5 standard deviations (σ = 0.0007 here).
  const double sigma = std::sqrt(rp * (1.0 - rp) / n);
  EXPECT_NEAR(double(reflected) / n, rp, 5.0 * sigma);
  EXPECT_EQ(eval(sheet, wo, Vec3{-wo.x, -wo.y, wo.z}, TransportMode::radiance)[0], 0.0f);
  EXPECT_EQ(pdf(sheet, wo, -wo), 0.0);
}

// The adjoint of a delta lobe that leaves into the same medium: importance mode gives the same
// direction and weight as radiance mode, and the sample drawn back from wi with the same number
// returns wo with the same weight (the lobe's share depends on |cos θ| only, the same at both ends).
TEST(ThinDielectricBsdf, IsItsOwnAdjointAndReversible) {
  const Bsdf<N3> sheet = ThinDielectric<N3>{1.7, SampledSpectrum<N3>{{0.3f, 0.6f, 1.0f}}};
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 2000; ++i) {
    const Vec3 wo = random_direction(rng);
    const double uc = u(rng);
    const auto rad = sample(sheet, wo, uc, 0.5, 0.5, TransportMode::radiance);
    const auto imp = sample(sheet, wo, uc, 0.5, 0.5, TransportMode::importance);
    ASSERT_TRUE(rad && imp);
    EXPECT_EQ(rad->wi, imp->wi);
    for (std::size_t k = 0; k < N3; ++k) EXPECT_EQ(rad->weight[k], imp->weight[k]);
    const auto back = sample(sheet, rad->wi, uc, 0.5, 0.5, TransportMode::importance);
    ASSERT_TRUE(back);
    EXPECT_NEAR(length(back->wi - wo), 0.0, 1e-12);
    EXPECT_EQ(back->transmitted, rad->transmitted);
    for (std::size_t k = 0; k < N3; ++k) EXPECT_EQ(back->weight[k], rad->weight[k]);
  }
}

// A 20 cm sheet of n = 1.5 in vacuum, face-on to a pinhole camera, before a D65 panel of Y = 1
// (linear sRGB (1, 1, 1)); nothing in front of the sheet to reflect.
std::string backlit_sheet(const char* integrator, int spp, const char* material) {
  return fmt::format(R"({{
    "camera": {{"position": [0, 0, 1], "look_at": [0, 0, 0], "fov_deg": 4, "resolution": [4, 4]}},
    "render": {{"integrator": "{}", "spectral": "rgb3", "spp": {}, "seed": 3}},
    "world_medium": "vacuum",
    "objects": [
      {{"name": "sheet", "shape": {{"type": "quad", "size": [0.2, 0.2]}}, "material": {}}},
      {{"name": "panel", "shape": {{"type": "quad", "size": [2, 2]}}, "transform": [{{"translate": [0, 0, -0.5]}}],
        "emission": {{"spectrum": "D65", "scale": 1.0}}}}
    ]
  }})",
                     integrator, spp, material);
}

// Whitted follows both branches (exact); the path tracer and bdpt draw one per sample: a Bernoulli
// of T' with σ = 0.27 a sample, so 16 pixels × 1024 samples give σ = 0.0021, the 1 % tolerance
// (0.0092) over 4 σ.
TEST(ThinDielectricBsdf, ASheetFaceOnTransmitsOneMinusROverOnePlusR) {
  const double expected = normal_transmittance(1.5);
  const char* sheet = R"({"type": "thin_dielectric", "ior": 1.5})";
  const Film whitted = test::render_text(backlit_sheet("whitted", 1, sheet));
  EXPECT_NEAR(whitted.rgb_at(1, 1).y, expected, 1e-4);
  for (const char* integrator : {"path", "bdpt"}) {
    const Film f = test::render_text(backlit_sheet(integrator, 1024, sheet));
    for (int c = 0; c < 3; ++c) {
      const test::Estimate e = test::channel_estimate(f, c, 0, 0, 4, 4);
      if (c == 1) std::printf("%s: %.4f ± %.4f (closed form %.4f)\n", integrator, e.mean, e.standard_error, expected);
      EXPECT_NEAR(e.mean, expected, 0.01 * expected) << integrator << " channel " << c;
      EXPECT_LT(4.0 * e.standard_error, 0.01 * expected) << integrator;  // the test can fail
    }
  }
  // A tint multiplies what goes through (here by 0.5 in every channel).
  const Film tinted = test::render_text(backlit_sheet("whitted", 1, R"({"type": "thin_dielectric", "tint": 0.5})"));
  EXPECT_NEAR(tinted.rgb_at(1, 1).y, 0.5 * expected, 1e-4);
}

// A hollow ball of the sheet (white tint) under a uniform D65 background of Y = 1 and nothing else:
// it only redistributes light, so every pixel, the ball's included, is (1, 1, 1). Each path of the
// path tracer carries exactly 1 (weights 1, no roulette loss at weight 1), as do bdpt's (its only
// strategy through delta vertices) and vcm's, so the tolerance is rounding and the paths cut at
// max_depth (R'^64, nothing).
TEST(ThinDielectricBsdf, WhiteFurnaceKeepsEveryPathsEnergy) {
  for (const char* integrator : {"whitted", "path", "bdpt", "vcm"}) {
    const Film f = test::render_text(fmt::format(R"({{
      "camera": {{"position": [0, 0, 3], "look_at": [0, 0, 0], "fov_deg": 20, "resolution": [8, 8]}},
      "render": {{"integrator": "{}", "spectral": "full", "spp": 8, "max_depth": 64}},
      "world_medium": "vacuum",
      "objects": [{{"name": "bubble", "shape": {{"type": "sphere", "radius": 0.5}},
                    "material": {{"type": "thin_dielectric", "ior": 1.5}}}}],
      "background": {{"spectrum": "D65", "scale": 1.0}}
    }})",
                                                 integrator));
    for (int y = 0; y < 8; ++y)
      for (int x = 0; x < 8; ++x)
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(f.rgb_at(x, y)[c], 1.0, 2e-3) << integrator << " " << x << "," << y;
  }
}

// A floor lit by a lamp partly through a tinted sheet and seen partly through it: the light under
// the sheet arrives only along delta chains, which each estimator reaches its own way (the path
// tracer by BSDF sampling, bdpt by its one strategy that crosses them, vcm also by merging at the
// floor). Their images agree: the mean pixel difference from the path tracer's is within 4
// standard errors, and those are below 1.5 % of the image's mean, so a sheet that one estimator
// handled wrongly (a lost tint, a wrong share, a weight for a strategy that cannot cross it) fails.
TEST(ThinDielectricBsdf, PathBdptAndVcmAgreeOnAFloorLitThroughASheet) {
  const std::string json = R"({
    "camera": {"position": [0, 0.6, 0.8], "look_at": [0, 0, 0], "fov_deg": 50, "resolution": [12, 12]},
    "render": {"integrator": "path", "spectral": "rgb3", "spp": 1, "max_depth": 8, "merge_radius": 0.01},
    "world_medium": "vacuum",
    "objects": [
      {"name": "floor", "shape": {"type": "quad", "size": [1, 1]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
       "material": {"type": "diffuse", "reflectance": 0.8}},
      {"name": "sheet", "shape": {"type": "quad", "size": [0.5, 1]},
       "transform": [{"rotate_deg": [-90, [1, 0, 0]]}, {"translate": [-0.25, 0.25, 0]}],
       "material": {"type": "thin_dielectric", "ior": 1.5, "tint": {"rgb": [0.9, 0.6, 0.3]}}},
      {"name": "lamp", "shape": {"type": "quad", "size": [0.3, 0.3]},
       "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0, 0.5, 0]}], "emission": {"spectrum": "D65", "scale": 5}}
    ]
  })";
  SceneDesc desc = parse_scene(json, "sheet.json");
  auto render = [&](IntegratorType integrator, int spp, std::uint64_t seed) {
    desc.render.integrator = integrator;
    desc.render.spp = spp;
    desc.render.seed = seed;
    return test::render_desc(desc);
  };
  const Film path = render(IntegratorType::path, 2048, 1);
  for (const auto& [integrator, name] : {std::pair{IntegratorType::bdpt, "bdpt"}, std::pair{IntegratorType::vcm, "vcm"}}) {
    const Film other = render(integrator, 1024, 2);
    for (int c = 0; c < 3; ++c) {
      const test::Estimate image = test::channel_estimate(path, c, 0, 0, 12, 12);
      const test::Estimate d = test::difference_estimate(path, other, c);
      std::printf("%s − path, channel %d: %+.5f ± %.5f (image mean %.4f)\n", name, c, d.mean, d.standard_error, image.mean);
      EXPECT_NEAR(d.mean, 0.0, 4.0 * d.standard_error) << name << " channel " << c;
      EXPECT_LT(d.standard_error, 0.015 * image.mean) << name;
    }
  }
}

// The JSON front end refuses what the builder refuses: a hand-written scene's mistake is pointed at.
TEST(ThinDielectricBsdf, JsonValuesOutsideTheModelAreRefused) {
  const std::vector<std::pair<const char*, const char*>> cases = {
      {R"({"type": "thin_dielectric", "ior": 0.5})", "objects[0].material.ior: a refractive index must be between 1 and 5"},
      {R"({"type": "thin_dielectric", "tint": {"rgb": [1.2, 0.5, 0.5]}})", "objects[0].material.tint.rgb[0]"},
      {R"({"type": "thin_dielectric", "thickness": 1})", "objects[0].material.thickness: unknown key"},
  };
  for (const auto& [material, expected] : cases) {
    try {
      parse_scene(backlit_sheet("path", 1, material), "s.json");
      ADD_FAILURE() << material << " was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace bouguer
