// Reference-plus-variance image regressions for the unbiased estimators (path, bdpt, vcm), after
// Mitsuba 3's practice: a stored reference per estimator (tests/regression/references/
// estimators-<name>.pfm, 32 × 24, rendered at kReferenceSpp), a fresh render at kSpp with another
// seed, and a z-test of their difference. Renders are not compared bit for bit: an estimator may
// change its sampling (a new MIS formulation, another random sequence) and stay right; what must
// not change is its expectation.
//
// The variance is estimated per pixel from the difference itself: under the hypothesis that both
// renders estimate the same image, each pixel's difference d_i has mean 0, the pixels are
// independent, and Σ d_i² / n² is an unbiased estimate of the variance of the mean difference over
// n pixels, whatever each pixel's own variance (a firefly inflates its block's standard error
// instead of failing it). It holds the reference's noise too. It does not rely on the variance the
// reference's build had, which a new MIS formulation changes.
//
// Checks, per channel: the mean difference over each 8 × 8 block (12 blocks) within kBlockZ of its
// standard errors, and over the whole image within kImageZ. Caps, so that noise cannot hide a bias:
// the image mean's standard error must stay below kImageRelativeSe of the image mean, so a 2 %
// scale of the estimator's result (a lost or doubled factor, a wrong pdf, a MIS weight that sums
// to 1.02) is at least (2 % − 4.5 × 0.3 %) / 0.3 % ≈ 2 standard errors beyond the tolerance; each
// block's below kBlockRelativeSe, so a strategy that goes missing or counts twice where it carries
// a fifth of a block's light (the caustic under the ball lit by light tracing, the haze by medium
// connections) is far outside. The thresholds (4.5 and 5 standard errors over 132
// tests) leave a false alarm rarer than 1 in 1000 runs, and the renders are deterministic: a pass
// stays a pass until the estimator changes. Measured at 192 spp: the image's standard error
// 0.16–0.22 %, the blocks' at most 1.7 % (caps 0.3 % and 3 %). Merges carry almost nothing on
// this floor (connections see it well), so vcm has a second regression where they carry most: the
// liquid behind glass below.
//
// For vcm the pixels are not independent: every pixel of an iteration merges the same photons
// (the radius spans about two pixel footprints) and, in hero mode, shares its wavelengths, so a
// per-pixel estimate understates the standard errors (8–15 times on the chromatic furnace of
// test_vcm_hero.cpp). vcm's fresh render is therefore kVcmSeeds renders of independent seeds at
// kSpp / kVcmSeeds iterations each, and each mean's standard error comes from their spread: with
// d_k the seed's mean difference and R the reference, Var(mean d) = Var(F_k)/K + Var(R), and the
// reference, the same estimator at ref_spp iterations, has Var(R) = Var(F_k)·(spp/K)/ref_spp, so
// SE = s/√K·√(1 + spp/ref_spp) (s the seeds' standard deviation; K − 1 = 31 degrees of freedom,
// which move a threshold of 5 to a false alarm of 2e-5 per mean). Measured on the floor: the
// seeds' image standard errors 0.15–0.20 %, as the pixels had said; in full mode the shared
// photons correlate neighbouring pixels little.
//
// Regenerating (after a change that is meant to change an estimator's expectation, e.g. a bias fix):
// BOUGUER_UPDATE_REFERENCES=1 build/tests/bouguer_tests --gtest_filter='EstimatorRegression.*'
// rewrites the four references (about 6 minutes on 2 loaded cores), then look at them before committing.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bouguer/integrators/integrators.h"
#include "bouguer/io/image_io.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

constexpr int kSpp = 192, kReferenceSpp = 4096;
constexpr int kBlock = 8;
constexpr double kBlockZ = 5.0, kImageZ = 4.5;
constexpr double kImageRelativeSe = 0.003, kBlockRelativeSe = 0.03;
constexpr int kVcmSeeds = 32;

// A red glass ball (a caustic from the lamp and from the point light, which only light subpaths
// find through the glass), a box of index-matched haze (medium vertices: connections and merges in
// a medium), a diffuse floor and a coloured back wall (interreflection), an area lamp and a point
// light (a delta light in every strategy's weights).
const char* const kScene = R"({
  "camera": {"position": [0, 0.35, 0.45], "look_at": [0, 0.05, 0], "fov_deg": 40, "resolution": [32, 24]},
  "render": {"integrator": "path", "spectral": "full", "spp": 64, "max_depth": 16, "seed": 1, "merge_radius": "4 mm"},
  "world_medium": "vacuum",
  "media": {"red": {"ior": 1.5, "absorption": {"library": "red-glass", "concentration": 0.3}},
            "haze": {"ior": 1.0, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                                                "value": [60, 20], "phase": {"type": "henyey_greenstein", "g": 0.3}}}},
  "objects": [
    {"name": "floor", "shape": {"type": "quad", "size": [1, 1]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
     "material": {"type": "diffuse", "reflectance": 0.8}},
    {"name": "back", "shape": {"type": "quad", "size": [1, 0.6]}, "transform": [{"translate": [0, 0.3, -0.2]}],
     "material": {"type": "diffuse", "reflectance": {"rgb": [0.2, 0.5, 0.7]}}},
    {"name": "ball", "shape": {"type": "sphere", "radius": "40 mm", "segments": 48},
     "transform": [{"translate": [-0.05, 0.04, 0]}], "inside": "red"},
    {"name": "haze", "shape": {"type": "box", "size": [0.08, 0.08, 0.08]}, "transform": [{"translate": [0.08, 0.04, -0.05]}],
     "inside": "haze"},
    {"name": "lamp", "shape": {"type": "disk", "radius": "50 mm", "segments": 32},
     "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0.0, 0.35, -0.05]}],
     "emission": {"spectrum": "D65", "scale": 20}}
  ],
  "lights": [{"type": "point", "position": [0.2, 0.25, 0.1], "spectrum": "A", "scale": 0.02}]
})";

const fs::path kReferences = fs::path(BOUGUER_SOURCE_DIR) / "tests" / "regression" / "references";

// `seeds` renders at spp each, with the seeds first_seed, first_seed + 1, ...
std::vector<Film> render(const std::string& scene, IntegratorType integrator, int spp, std::uint64_t first_seed,
                         int seeds = 1) {
  SceneDesc desc = parse_scene(scene, "estimators.json");
  desc.render.integrator = integrator;
  desc.render.spp = spp;
  return test::render_seeds(desc, seeds, first_seed);
}

struct Difference {
  double mean = 0.0, standard_error = 0.0, reference_mean = 0.0;
};

// The mean of fresh − reference over pixels [x0, x1) × [y0, y1) in one channel, its standard error
// and the reference's mean there. One fresh render: the error from the pixels' squared
// differences; several (independent seeds, `spp` iterations in all): from the spread of their
// means, with the reference's share (see the head comment).
Difference difference(const std::vector<Film>& fresh, const Film& reference, int channel, int x0, int y0, int x1,
                      int y1, int spp, int reference_spp) {
  const double n = double(x1 - x0) * double(y1 - y0);
  double ref = 0.0;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) ref += reference.rgb_at(x, y)[channel];
  if (fresh.size() == 1) {
    double sum = 0.0, sum2 = 0.0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const double d = double(fresh[0].rgb_at(x, y)[channel]) - reference.rgb_at(x, y)[channel];
        sum += d, sum2 += d * d;
      }
    return {sum / n, std::sqrt(sum2) / n, ref / n};
  }
  const test::Estimate e = test::seeds_estimate(fresh, channel, x0, y0, x1, y1);
  return {e.mean - ref / n, e.standard_error * std::sqrt(1.0 + double(spp) / reference_spp), ref / n};
}

// A regression: its scene, estimator, reference name, sample counts and caps (relative standard
// errors of the image's and of each block's mean difference).
struct Regression {
  std::string scene, reference;
  IntegratorType integrator;
  int spp, reference_spp;
  double image_cap, block_cap;
  int seeds = 1;  // independent renders, spp / seeds each (vcm: kVcmSeeds)
};

void expect_matches_reference(const Regression& r) {
  const std::string name(integrator_info(r.integrator).name);
  const fs::path path = kReferences / (r.reference + ".pfm");
  if (std::getenv("BOUGUER_UPDATE_REFERENCES")) write_pfm(path, render(r.scene, r.integrator, r.reference_spp, 1)[0]);
  ASSERT_TRUE(fs::exists(path)) << path << " missing: run with BOUGUER_UPDATE_REFERENCES=1";
  const Film reference = read_pfm(path);
  const std::vector<Film> fresh = render(r.scene, r.integrator, r.spp / r.seeds, 2, r.seeds);
  const int width = fresh[0].width, height = fresh[0].height;
  ASSERT_EQ(width, reference.width);
  ASSERT_EQ(height, reference.height);
  auto diff = [&](int c, int x0, int y0, int x1, int y1) {
    return difference(fresh, reference, c, x0, y0, x1, y1, r.spp, r.reference_spp);
  };
  for (int c = 0; c < 3; ++c) {
    const Difference image = diff(c, 0, 0, width, height);
    std::printf("%s ch %d: image %+.5f ± %.5f (%.2f %% of %.5f)", name.c_str(), c, image.mean, image.standard_error,
                100.0 * image.standard_error / image.reference_mean, image.reference_mean);
    EXPECT_LT(std::abs(image.mean), kImageZ * image.standard_error) << name << " ch " << c << ": the image mean moved";
    EXPECT_LT(image.standard_error, r.image_cap * image.reference_mean)
        << name << " ch " << c << ": too noisy for the cap";
    double worst_z = 0.0, worst_se = 0.0;
    for (int y0 = 0; y0 < height; y0 += kBlock)
      for (int x0 = 0; x0 < width; x0 += kBlock) {
        const Difference b = diff(c, x0, y0, x0 + kBlock, y0 + kBlock);
        worst_z = std::max(worst_z, std::abs(b.mean) / b.standard_error);
        worst_se = std::max(worst_se, b.standard_error / b.reference_mean);
        EXPECT_LT(std::abs(b.mean), kBlockZ * b.standard_error)
            << name << " ch " << c << " block at (" << x0 << ", " << y0 << "): " << b.mean << " ± " << b.standard_error
            << " against " << b.reference_mean;
        EXPECT_LT(b.standard_error, r.block_cap * b.reference_mean)
            << name << " ch " << c << " block at (" << x0 << ", " << y0 << "): too noisy";
      }
    std::printf(", largest block |z| %.2f, largest block standard error %.1f %%\n", worst_z, 100.0 * worst_se);
  }
}

Regression on_the_floor(IntegratorType integrator) {
  return {kScene, "estimators-" + std::string(integrator_info(integrator).name), integrator, kSpp, kReferenceSpp,
          kImageRelativeSe, kBlockRelativeSe, integrator == IntegratorType::vcm ? kVcmSeeds : 1};
}

TEST(EstimatorRegression, PathMatchesItsReference) { expect_matches_reference(on_the_floor(IntegratorType::path)); }
TEST(EstimatorRegression, BdptMatchesItsReference) { expect_matches_reference(on_the_floor(IntegratorType::bdpt)); }
TEST(EstimatorRegression, VcmMatchesItsReference) { expect_matches_reference(on_the_floor(IntegratorType::vcm)); }

// Merges that matter: the liquid in a glass tumbler lit by a point light and a spot
// (support/test_scenes.h: lit_tumbler, 16 × 16), where single scattering is merging's alone (both
// neighbours of the medium vertex are glass) and merges carry most of the light that connections
// reach only with an infinite variance. A merge counted twice, a kernel normalised over the wrong
// area or a merge weight that does not sum to 1 with the connections' moves the liquid's blocks by
// far more than the caps (measured at 1024 spp from 32 seeds: the image mean's standard error
// 2.8–4.1 %, blocks' up to 9.5 %; from one render's pixels it had read 3.1–3.9 % and 9.6 %; caps
// 5 % and 15 %). Doubling every merge's contribution moved the image by +63 % (z ≈ 11). The
// reference was rendered again on 2026-12-05, when merges right after a specular vertex came to be
// weighed (they had weighed 0, and the once-scattered light was missing): the image rose 88 %
// (z ≈ 21); the image mean's standard error is now 2.1–3.1 %, the blocks' up to 7.1 %.
TEST(EstimatorRegression, VcmMatchesItsReferenceInALiquidBehindGlass) {
  expect_matches_reference({test::lit_tumbler("vcm"), "estimators-vcm-tumbler", IntegratorType::vcm, 1024, 16384, 0.05,
                            0.15, kVcmSeeds});
}

}  // namespace
}  // namespace bouguer
