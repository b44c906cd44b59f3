// Path guiding (integrators/guiding.h, render/path_guide.h) in the path tracer: the guided render
// estimates the same image as the unguided one (the caustic under a red glass ball, where the
// guide learns the directions towards the ball), a white furnace of diffuse surfaces stays white,
// and the image is the same bit for bit on 1 and 2 threads and over any split into passes.
#include <gtest/gtest.h>

#include <cstring>

#include "bouguer/integrators/guiding.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

SceneDesc red_ball(int spp, bool guiding) {
  SceneDesc desc = load_scene(test::test_data("red_ball_lamp/scene.json").string());
  desc.camera.width_px = 32, desc.camera.height_px = 24;
  desc.render.spp = spp;
  desc.render.max_depth = 8;
  desc.render.guiding = guiding;
  return desc;
}

// Would catch a guided direction weighted by the BSDF's density instead of the mixture's (planted,
// the image came out 0.35 % bright, 11 standard errors), a guide density that does not match its
// samples, and records that changed the image rather than only the directions drawn. Both renders
// draw from the same streams until the guide first chooses, so their difference is small and its
// standard error a few hundredths of a per cent.
TEST(Guiding, TheCausticUnderARedBallIsTheUnguidedOne) {
  const Film plain = test::render_desc(red_ball(64, false));
  const Film guided = test::render_desc(red_ball(64, true));
  for (int c = 0; c < 3; ++c) {
    const test::Estimate d = test::difference_estimate(plain, guided, c);
    const test::Estimate m = test::channel_estimate(plain, c, 0, 0, plain.width, plain.height);
    std::printf("guided − unguided, channel %d: %.5f ± %.5f (mean %.4f)\n", c, d.mean, d.standard_error, m.mean);
    EXPECT_LT(std::abs(d.mean), 4.0 * d.standard_error + 1e-6) << "channel " << c;
    EXPECT_LT(d.standard_error, 0.02 * m.mean) << "too few samples to see a bias of a few per cent";
  }
  EXPECT_NE(std::memcmp(plain.rgb.data(), guided.rgb.data(), plain.rgb.size() * sizeof(float)), 0)
      << "the guide drew nothing";
}

// Diffuse surfaces of albedo 1 that see each other (a ball on a floor under a dome) under a
// uniform sky: every path brings back the sky, guided or not. A closed form that guided draws which
// lose or add energy would fail (paths ended by a draw, weights that do not average to the BSDF's
// albedo); the wrong density planted above is not seen here, where the learned light is nearly
// uniform over each hemisphere: the caustic test sees it.
TEST(Guiding, AWhiteFurnaceOfDiffuseSurfacesStaysWhite) {
  const char* json = R"({
    "camera": {"position": [0, 0.15, 0.3], "look_at": [0, 0.03, 0], "fov_deg": 40, "resolution": [16, 12]},
    "render": {"integrator": "path", "spectral": "hero", "spp": 512, "max_depth": 1000, "guiding": true},
    "objects": [
      {"name": "floor", "shape": {"type": "quad", "size": [0.4, 0.4]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
       "material": {"type": "diffuse", "reflectance": 1}},
      {"name": "ball", "shape": {"type": "sphere", "radius": "30 mm"}, "transform": [{"translate": [0, 0.03, 0]}],
       "material": {"type": "diffuse", "reflectance": 1}},
      {"name": "wall", "shape": {"type": "quad", "size": [0.4, 0.2]}, "transform": [{"translate": [0, 0.1, -0.1]}],
       "material": {"type": "diffuse", "reflectance": 1}}],
    "background": {"spectrum": "D65", "scale": 1}
  })";
  const SceneDesc desc = parse_scene(json, "furnace.json");
  const Film f = test::render_desc(desc);
  for (int c = 0; c < 3; ++c) {
    const test::Estimate e = test::channel_estimate(f, c, 0, 0, f.width, f.height);
    std::printf("guided white furnace, channel %d: %.5f ± %.5f\n", c, e.mean, e.standard_error);
    EXPECT_NEAR(e.mean, 1.0, 0.01) << "channel " << c;
    EXPECT_LT(3.0 * e.standard_error, 0.01) << "too few samples for the tolerance";
  }
}

// The guide is trained by the same iterations whatever the thread count, and the render that reads
// it splits like any other: 1 and 2 threads, one pass or three, the same film bit for bit.
TEST(Guiding, TheSameImageOnAnyThreadCountAndPassSplit) {
  const SceneDesc desc = red_ball(8, true);
  const RenderScene scene = compile(desc);
  auto guided_film = [&](int threads, std::vector<SampleRange> passes) {
    RenderControl control;
    control.threads = threads;
    RenderStats stats;
    GuideTraining training;
    const auto guide = prepare_guide(scene, desc.render, control, stats, training);
    EXPECT_TRUE(guide);
    EXPECT_GT(training.records, 0u);
    control.guide = guide.get();
    FilmBuffer film = make_film(scene, false);
    for (const SampleRange r : passes) render_into(scene, desc.render, film, PixelRegion::whole(scene.camera), r, control, stats);
    return resolve(film, desc.render.spp);
  };
  const Film one = guided_film(1, {{0, 8}});
  const Film two = guided_film(2, {{0, 1}, {1, 3}, {3, 8}});
  ASSERT_EQ(one.rgb.size(), two.rgb.size());
  EXPECT_EQ(std::memcmp(one.rgb.data(), two.rgb.data(), one.rgb.size() * sizeof(float)), 0);
}

}  // namespace
}  // namespace bouguer
