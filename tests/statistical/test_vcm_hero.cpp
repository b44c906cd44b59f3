// vcm in hero mode on the strongly chromatic white furnace of #20 (#36's "hero-vcm question"):
// its image mean per channel is the sky's, within a tolerance that its seeds' spread must leave
// room for. The suite's name ends in "Long" (label `long`, run by `make test-long`): the check
// needs 32 renders of 2048 iterations (about 4 CPU minutes).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <future>
#include <thread>
#include <vector>

#include "bouguer/integrators/integrators.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

// The furnace (σ_s 900 → 30 per m over 400–700 nm, albedo 1, HG g = 0.7, a 20 mm ball of index
// 1.33 under a uniform D65 sky, 8 × 8 pixels through its middle), merging within the 1.16 mm that
// two footprints of #36's 24 × 24 image give. Every path of a vcm iteration shares the
// iteration's wavelengths and hero (vcm.cpp), so a render's pixels are not independent: its noise
// is the iterations', and the standard error comes from the image means of independent seeds (at 24 ×
// 24 one from the pixels was 8–15 times too small). Measured with the CLI on this scene, 55 seeds of
// 2048 iterations: a render's mean spreads 2.6 % in red, 1.0 % in green, 2.1 % in blue (a few
// renders 4–6 % high: rare medium connections), so over 32 seeds the standard errors are about
// 0.46 %, 0.17 % and 0.36 %, and the tolerances (red 2.5 %, green and blue 1.4 %) hold 3 of them.
// The bias it catches: #36 first read blue +1.9 % and red −0.8 % from 8 renders, whose standard
// error (±0.5 % quoted) is about ±0.8 % in blue and ±1 % in red at this spread. Many seeds put
// vcm's hero mode at the sky within noise (#36's note: blue +0.2 % ± 0.28 %, green 0.0 % ± 0.13 %,
// red −0.4 % ± 0.35 %); a bias of #36's size (1.9 %) in blue or green exceeds the tolerance.
// Its own 32 seeds read red −0.46 % ± 0.54 %, green +0.17 % ± 0.19 %, blue +0.05 % ± 0.26 %.
// Planted, 2 % more on vcm's hero-mode samples below 490 nm (blue +2.2 %) fails it in blue.
TEST(VertexMergingLong, HeroModeOnAStronglyChromaticFurnace) {
  SceneDesc desc = parse_scene(test::ball_furnace(0.16, "[900, 30]", 0.7, "20 mm"), "chromatic.json");
  desc.render.integrator = IntegratorType::vcm;
  desc.render.spectral = SpectralMode::hero;
  desc.render.spp = 2048;
  desc.render.merge_radius_m = 0.0011643;
  // The expected value: the sky alone, by the path tracer (a bias of vcm's own would cancel).
  SceneDesc sky_desc = desc;
  sky_desc.objects.clear();
  sky_desc.render.integrator = IntegratorType::path;
  const Film sky = test::render_desc(sky_desc);
  // The seeds two at a time (or as many as there are cores), each render on one thread: an 8 × 8
  // image is one tile. Each seed's image is the same whatever the threads.
  const RenderScene scene = compile(desc);
  constexpr int kSeeds = 32;
  std::array<std::array<double, kSeeds>, 3> means{};
  const int batch = static_cast<int>(std::max(2u, std::thread::hardware_concurrency()));
  for (int first = 0; first < kSeeds; first += batch) {
    std::vector<std::future<Film>> films;
    for (int i = first; i < std::min(kSeeds, first + batch); ++i)
      films.push_back(std::async(std::launch::async, [&, i] {
        RenderSettings settings = desc.render;
        settings.seed = static_cast<std::uint64_t>(i + 1);
        RenderControl control;
        control.threads = 1;
        RenderStats stats;
        return render(scene, settings, control, stats);
      }));
    for (int i = first; i < std::min(kSeeds, first + batch); ++i) {
      const Film f = films[static_cast<std::size_t>(i - first)].get();
      for (int c = 0; c < 3; ++c) means[c][i] = test::channel_estimate(f, c, 0, 0, f.width, f.height).mean;
    }
  }
  constexpr std::array<double, 3> kTolerance = {0.025, 0.014, 0.014};
  for (int c = 0; c < 3; ++c) {
    const double expected = test::channel_estimate(sky, c, 0, 0, sky.width, sky.height).mean;
    const auto [mean, se] = test::mean_estimate(means[c]);
    std::printf("vcm hero, strongly chromatic furnace, %d seeds ch %d: %.5f ± %.5f (sky %.5f)\n", kSeeds, c, mean, se,
                expected);
    EXPECT_NEAR(mean / expected, 1.0, kTolerance[c]) << "ch " << c;
    EXPECT_LT(3.0 * se / expected, kTolerance[c]) << "ch " << c << ": too few samples for the tolerance";
  }
}

}  // namespace
}  // namespace bouguer
