// Denoising from the two half buffers (render/denoise.h, bouguer render --denoise): on images whose
// truth is known (a converged gradient, flat grey, a step, heavy-tailed noise), then run as a user
// runs it: the same image at any thread count, closer to a reference than the noisy render it came
// from, and its options refused where they cannot hold.
#include <gtest/gtest.h>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <vector>

#include "bouguer/core/rng.h"
#include "bouguer/io/image_io.h"
#include "bouguer/render/compare.h"
#include "bouguer/render/denoise.h"
#include "bouguer/scene/loader.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

// Half images of `truth` (one value per pixel, grey) with each half the mean of `samples` draws
// of noise about it: Gaussian of standard deviation sigma, or (sigma < 0) exponential with the
// truth as its mean, every channel drawn apart. The film holds (a + b)/2, as a render's does.
struct Noisy {
  HalfImages halves;
  Film film;
};
Noisy noisy(int width, int height, const std::vector<double>& truth, double sigma, int samples, std::uint64_t seed) {
  Noisy n;
  n.halves.width = width, n.halves.height = height;
  n.film = Film(width, height);
  Rng rng(seed, 7);
  const auto draw = [&](double mean) {
    if (sigma < 0.0) return -mean * std::log(1.0 - rng.next_double());
    const double u = 1.0 - rng.next_double(), v = rng.next_double();
    return mean + sigma * std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * 3.141592653589793 * v);
  };
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const double t = truth[static_cast<std::size_t>(y) * width + x];
      Vec3 half[2];
      for (Vec3& h : half)
        for (std::size_t c = 0; c < 3; ++c) {
          double s = 0.0;
          for (int i = 0; i < samples; ++i) s += draw(t);
          h[c] = s / samples;
        }
      n.halves.a.push_back(half[0]);
      n.halves.b.push_back(half[1]);
      n.halves.usable.push_back(1);
      n.halves.even_share.push_back(0.5);
      const Vec3 m = (half[0] + half[1]) * 0.5;
      n.film.set_rgb(x, y, {float(m.x), float(m.y), float(m.z)});
    }
  return n;
}

// The root-mean-square difference of the film's green channel from the truth, over pixels
// [x0, x1) of every row.
double rms(const Film& film, const std::vector<double>& truth, int x0, int x1) {
  double s = 0.0;
  int n = 0;
  for (int y = 0; y < film.height; ++y)
    for (int x = x0; x < x1; ++x, ++n) {
      const double d = film.rgb_at(x, y).y - truth[static_cast<std::size_t>(y) * film.width + x];
      s += d * d;
    }
  return std::sqrt(s / n);
}

// Halves that agree (a converged render, or one with no noise) are left exactly as they are: the
// variance read from them is zero, so every neighbour that differs weighs exp(−∞) and those equal
// to the pixel add nothing. A filter that smoothed regardless of the noise (a fixed kernel, or a
// variance floor) would move the gradient's pixels.
TEST(Denoise, HalvesThatAgreeAreLeftAsTheyAre) {
  const int w = 40, h = 30;
  std::vector<double> truth;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) truth.push_back(0.1 + 0.02 * x + 0.001 * y);
  Noisy n = noisy(w, h, truth, 0.0, 1, 1);
  const Film before = n.film;
  denoise(n.film, n.halves, {});
  for (std::size_t i = 0; i < before.rgb.size(); ++i) ASSERT_EQ(n.film.rgb[i], before.rgb[i]) << i;
}

// Flat grey under Gaussian noise: the noise falls by far more than a factor 4 (the 15 × 15 window
// holds 225 neighbours, nearly all alike), and the mean stays (within four of its standard errors
// before filtering). Weights that did not take the noise off the patch distance (α = 0), or a
// strength far too small, would average a handful of neighbours and fail the first check.
TEST(Denoise, FlatGreyLosesItsNoise) {
  const int w = 64, h = 48;
  const std::vector<double> truth(static_cast<std::size_t>(w) * h, 0.5);
  Noisy n = noisy(w, h, truth, 0.2, 8, 2);  // each half's σ 0.071, the film's 0.05
  const double before = rms(n.film, truth, 0, w);
  const DenoiseStats stats = denoise(n.film, n.halves, {});
  const double after = rms(n.film, truth, 0, w);
  double mean = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) mean += n.film.rgb_at(x, y).y / (w * h);
  std::printf("flat grey: RMS error %.4f before, %.4f after (%.1f times less); mean %.5f\n", before, after,
              before / after, mean);
  EXPECT_EQ(stats.pixels_left, 0u);
  EXPECT_NEAR(before, 0.05, 0.003);  // the noise is what it was made to be
  EXPECT_LT(after, before / 4.0);
  EXPECT_NEAR(mean, 0.5, 4.0 * 0.05 / std::sqrt(double(w) * h));
}

// A step from 0.2 to 0.8 under noise (each half's σ 0.02, the film's 0.014): the columns on either
// side of it keep their own level, with less noise than before, not more. A filter blind to the
// difference (a box, or weights from a strength so large that the step looks like noise) would
// pull them a good part of the 0.6 towards the other side; away from the step the noise falls by
// more than a factor 4.
TEST(Denoise, AStepIsNotBlurred) {
  const int w = 48, h = 32;
  std::vector<double> truth;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) truth.push_back(x < w / 2 ? 0.2 : 0.8);
  Noisy n = noisy(w, h, truth, 0.08, 16, 3);  // the film's σ 0.02
  const double before = rms(n.film, truth, w / 2 - 1, w / 2 + 1);
  denoise(n.film, n.halves, {});
  const double at_step = rms(n.film, truth, w / 2 - 1, w / 2 + 1), away = rms(n.film, truth, 0, w / 2 - 8);
  std::printf("step: RMS error beside it %.4f (before %.4f), away from it %.4f\n", at_step, before, away);
  EXPECT_LT(at_step, before);
  EXPECT_LT(away, before / 4.0);
}

// Monte Carlo noise is heavy-tailed: here each half is the mean of 4 exponential draws (a
// standard deviation equal to the mean). The filter is linear in the values it averages, with
// weights that sum to one, so the image's mean stays the truth's within its standard error. A
// filter that clamped bright values (a firefly clamp), or averaged in a non-linear space (the
// logarithm, the display's sRGB) would read low by several standard errors. (Each half weighted
// by itself instead of by the other half also passes here: 1.0002 against 1.0072; the cross
// weighting is kept for the paper's reason, weights independent of the values they multiply.)
TEST(Denoise, TheMeanOfHeavyTailedNoiseStays) {
  const int w = 96, h = 96;
  const std::vector<double> truth(static_cast<std::size_t>(w) * h, 1.0);
  Noisy n = noisy(w, h, truth, -1.0, 4, 4);
  double raw = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) raw += n.film.rgb_at(x, y).y;
  raw /= w * h;
  denoise(n.film, n.halves, {});
  double mean = 0.0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) mean += n.film.rgb_at(x, y).y;
  mean /= w * h;
  const double standard_error = std::sqrt(1.0 / 8.0 / (w * h));  // a pixel's 8 draws of variance 1
  std::printf("heavy-tailed: the image's mean %.4f before, %.4f after (standard error %.4f)\n", raw, mean,
              standard_error);
  EXPECT_NEAR(raw, 1.0, 4.0 * standard_error);
  EXPECT_NEAR(mean, 1.0, 4.0 * standard_error);
}

// A pixel with an empty half (one sample) has no variance to read: it is left as rendered, and
// it enters none of its neighbours' means, patch distances or variances: whatever its halves hold,
// every other pixel comes out the same bit for bit. (A pixel whose halves entered its neighbours'
// patches would move them when they hold 100 and −50.)
TEST(Denoise, APixelWithAnEmptyHalfIsLeftAsRenderedAndTouchesNoOther) {
  const int w = 24, h = 20;
  const std::vector<double> truth(static_cast<std::size_t>(w) * h, 0.5);
  const std::size_t lone = 5 * w + 7;
  Noisy n = noisy(w, h, truth, 0.2, 4, 5);
  n.halves.usable[lone] = 0;
  n.film.set_rgb(7, 5, {9.0f, 9.0f, 9.0f});
  Noisy wild = n;
  wild.halves.a[lone] = Vec3{100.0, 100.0, 100.0};
  wild.halves.b[lone] = Vec3{-50.0, -50.0, -50.0};
  const DenoiseStats stats = denoise(n.film, n.halves, {});
  denoise(wild.film, wild.halves, {});
  EXPECT_EQ(stats.pixels_left, 1u);
  EXPECT_EQ(n.film.rgb_at(7, 5).y, 9.0f);
  EXPECT_EQ(n.film.rgb, wild.film.rgb);
}

// A pixel with an odd number of samples (2 even, 1 odd here) whose neighbours are all unlike it
// (or equal to it) is left exactly as the film has it. Through half_images from a FilmBuffer: each
// pixel's level differs from its neighbours' by at least 1 (or equals it), its samples by 0.02.
// An output made of the halves' plain mean (a + b)/2, not of the film's own value and the halves'
// filtered differences weighted by their samples, would move every pixel by 0.0033.
TEST(Denoise, APixelUnlikeItsNeighboursIsLeftAsItWas) {
  const int w = 20, h = 16;
  FilmBuffer buffer(w, h);
  buffer.keep_halves();
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double v = 1.0 + ((x * 7 + y * 13) % 17);
      for (int i = 0; i < 3; ++i) {
        const double s = v + (i % 2 ? -0.01 : 0.01);
        buffer.add_sample(x, y, Vec3{s, s, s}, 1.0, {}, i % 2 == 1);
      }
    }
  Film film = buffer.resolve(0.0);
  const Film before = film;
  denoise(film, half_images(buffer, film), {});
  EXPECT_EQ(film.rgb, before.rgb);
}

// The filter does to an image what it does to the same image a million times dimmer (no constant
// in it has the image's units): dim renders and dark regions are filtered as bright ones are.
TEST(Denoise, ADimmerImageIsFilteredTheSame) {
  const int w = 32, h = 24;
  std::vector<double> truth;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) truth.push_back(x < w / 2 ? 0.2 : 0.5 + 0.01 * y);
  Noisy bright = noisy(w, h, truth, 0.1, 4, 6);
  Noisy dim = bright;
  constexpr double kScale = 1e-6;
  for (std::size_t p = 0; p < dim.halves.a.size(); ++p) {
    dim.halves.a[p] = dim.halves.a[p] * kScale, dim.halves.b[p] = dim.halves.b[p] * kScale;
    const Vec3 m = (dim.halves.a[p] + dim.halves.b[p]) * 0.5;
    dim.film.rgb[3 * p] = float(m.x), dim.film.rgb[3 * p + 1] = float(m.y), dim.film.rgb[3 * p + 2] = float(m.z);
  }
  denoise(bright.film, bright.halves, {});
  denoise(dim.film, dim.halves, {});
  for (std::size_t i = 0; i < bright.film.rgb.size(); ++i)
    ASSERT_NEAR(dim.film.rgb[i] / kScale, bright.film.rgb[i], 1e-4 * std::abs(bright.film.rgb[i])) << i;
}

// bouguer render --denoise on the whole-milk ball of the scattering tests (16 × 16, 32 spp, under
// a grey sky) against its stored reference: the denoised image is nearer than the noisy one by
// more than a third in mean ΔE00 (measured over seeds 1 to 4: 3.38–3.53 noisy, 1.84–2.01
// denoised), the noisy image written beside it is the render without --denoise bit for bit (the
// half buffers change no sample), and 1 and 2 threads give the same denoised image. A denoiser
// that filtered nothing, or blurred the ball's edge into the sky, fails the first check.
TEST(DenoiseCli, NearerItsReferenceTheSameAtAnyThreadCount) {
  const auto dir = test::scratch_dir("denoise_cli");
  const fs::path scene = test::test_data("whole_milk_ball/scene.json");
  const auto render = [&](const char* threads, bool denoised) {
    std::vector<std::string> args = {"render", scene.string(), "--threads", threads, "--quiet", "--seed", "3"};
    if (denoised)
      for (const std::string& a :
           {std::string("--denoise"), std::string("-o"), (dir / fmt::format("denoised_{}.pfm", threads)).string(),
            std::string("--noisy-output"), (dir / fmt::format("noisy_{}.pfm", threads)).string(),
            std::string("--stats-json"), (dir / "stats.json").string()})
        args.push_back(a);
    else
      for (const std::string& a : {std::string("-o"), (dir / "plain.pfm").string()}) args.push_back(a);
    const auto r = test::run_bouguer(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  };
  render("1", true);
  render("2", true);
  render("2", false);
  const Film reference = read_exr(test::test_data("whole_milk_ball/reference.exr"));
  const Film denoised = read_pfm(dir / "denoised_2.pfm"), noisy = read_pfm(dir / "noisy_2.pfm");
  const double before = compare_images(noisy, reference).mean, after = compare_images(denoised, reference).mean;
  std::printf("whole-milk ball, 32 spp: mean ΔE00 to the reference %.3f noisy, %.3f denoised\n", before, after);
  EXPECT_LT(after, 0.67 * before);
  EXPECT_EQ(read_pfm(dir / "denoised_1.pfm").rgb, denoised.rgb);
  EXPECT_EQ(read_pfm(dir / "plain.pfm").rgb, noisy.rgb);
  const auto stats = nlohmann::json::parse(test::read_file(dir / "stats.json"));
  EXPECT_EQ(stats["denoise"]["pixels_left_as_rendered"].get<int>(), 0);
}

// With an automatic exposure (measured on the film), the noisy PNG is still the plain render's PNG
// byte for byte: the display is set on the noisy image, not on the denoised one, whose brightest
// pixels are dimmer.
TEST(DenoiseCli, TheNoisyImageIsThePlainRenderUnderAnAutomaticExposure) {
  const auto dir = test::scratch_dir("denoise_exposure");
  const std::string scene = test::test_data("whole_milk_ball/scene.json").string();
  const std::vector<std::string> common = {"render", scene, "--quiet", "--seed", "4", "--auto-exposure", "on"};
  auto with = common, plain = common;
  for (const std::string& a : {std::string("--denoise"), std::string("-o"), (dir / "denoised.png").string(),
                               std::string("--noisy-output"), (dir / "noisy.png").string()})
    with.push_back(a);
  for (const std::string& a : {std::string("-o"), (dir / "plain.png").string()}) plain.push_back(a);
  ASSERT_EQ(test::run_bouguer(with).exit_code, 0);
  ASSERT_EQ(test::run_bouguer(plain).exit_code, 0);
  EXPECT_EQ(test::read_file(dir / "noisy.png"), test::read_file(dir / "plain.png"));
  EXPECT_NE(test::read_file(dir / "denoised.png"), test::read_file(dir / "plain.png"));
}

// What --denoise cannot do is refused before anything is rendered, in one line.
TEST(DenoiseCli, WhatCannotHoldIsRefused) {
  const auto dir = test::scratch_dir("denoise_refused");
  const std::string scene = test::test_data("whole_milk_ball/scene.json").string();
  const auto refused = [&](std::vector<std::string> args, const std::string& says) {
    const auto r = test::run_bouguer(args);
    EXPECT_NE(r.exit_code, 0);
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
  };
  refused({"render", scene, "--quiet", "-o", (dir / "a.pfm").string(), "--noisy-output", (dir / "b.pfm").string()},
          "--noisy-output: only with --denoise");
  refused({"render", scene, "--quiet", "--denoise", "--integrator", "light", "-o", (dir / "a.pfm").string()},
          "--denoise: the light tracer's image is all light-path splats");
  EXPECT_FALSE(fs::exists(dir / "a.pfm"));
}

}  // namespace
}  // namespace bouguer
