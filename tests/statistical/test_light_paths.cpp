// The light tracer's camera connections through smooth glass (integrators/splats.cpp) and the path
// tracer's light paths (render.light_paths, integrators/light.cpp). Each check compares image
// means whose standard errors come from the sample counts (the path tracer's pixels are
// independent; the light tracer's splats spread one path over pixels, so its error is taken from
// independent seeds), within 4 of them, and requires those to be small enough to see the bias it
// is there for.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bouguer/scene/loader.h"
#include "support/test_scenes.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

constexpr int kSeeds = 8;  // (4 standard errors from 7 degrees of freedom: a 0.5 % two-sided level)

// Each channel's image mean, from kSeeds seeds of `spp` samples each (the standard error from
// their spread: the image's own variation from pixel to pixel is not noise).
std::array<test::Estimate, 3> image_means(SceneDesc desc, IntegratorType integrator, int spp,
                                          bool light_paths = false) {
  desc.render.integrator = integrator;
  desc.render.spp = spp;
  desc.render.light_paths = light_paths;
  const std::vector<Film> films = test::render_seeds(desc, kSeeds, 1);
  std::array<test::Estimate, 3> out;
  for (int c = 0; c < 3; ++c) out[c] = test::seeds_estimate(films, c, 0, 0, films[0].width, films[0].height);
  return out;
}

// Estimate `b` (named b_name) against the reference `a` in each channel: their means within 4
// standard errors of the difference, and those under `cap` of the reference's mean.
void expect_agree(const char* what, const char* a_name, const std::array<test::Estimate, 3>& a, const char* b_name,
                  const std::array<test::Estimate, 3>& b, double cap) {
  for (int c = 0; c < 3; ++c) {
    const double se = std::hypot(a[c].standard_error, b[c].standard_error);
    std::printf("%s, ch %d: %s %.5f ± %.5f, %s %.5f ± %.5f (%.4f of it)\n", what, c, a_name, a[c].mean,
                a[c].standard_error, b_name, b[c].mean, b[c].standard_error, b[c].mean / a[c].mean);
    EXPECT_LT(std::abs(b[c].mean - a[c].mean), 4.0 * se) << what << " ch " << c;
    EXPECT_LT(4.0 * se, cap * a[c].mean) << what << " ch " << c << ": too noisy";
  }
}

// What the camera sees through glass, the light tracer (its camera connections solved through the
// glass, as next-event estimation solves them to a point lamp) against the path tracer, in each
// channel: the means within 4 standard errors of their difference, and those under `cap` of the
// path tracer's mean; the light tracer without them (`manifold: false`) black. The light tracer
// leaves out the camera's own reflections inside the glass (a few tenths of a per cent here).
void expect_light_tracer_sees_as_path(const std::string& json, const char* what, int path_spp, int light_spp,
                                      double cap) {
  SceneDesc desc = parse_scene(json, "light_through_glass.json");
  const auto path = image_means(desc, IntegratorType::path, path_spp);
  expect_agree(what, "path", path, "light tracer", image_means(desc, IntegratorType::light, light_spp), cap);
  desc.render.manifold = false;
  desc.render.integrator = IntegratorType::light;
  desc.render.spp = 16;
  const Film off = test::render_desc(desc);
  EXPECT_EQ(test::channel_estimate(off, 1, 0, 0, off.width, off.height).mean, 0.0) << what << ": seen without glass";
}

// A pinhole camera, 16 × 16 pixels, over `objects` under `lights`, in vacuum with a coloured glass
// and a water.
std::string scene(const char* camera, const char* objects, const char* lights, const char* extra_media = "") {
  return fmt::format(R"({{
      "camera": {},
      "render": {{"integrator": "path", "max_depth": 64}},
      "world_medium": "vacuum",
      "media": {{"glass": {{"ior": 1.5, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                                                    "value": [5, 40]}}}},
                "water": {{"ior": 1.33, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                                                     "value": [1, 8]}}}}{}}},
      "objects": [{}],
      "lights": [{}],
      "background": {{"spectrum": "E", "scale": 0}}
    }})",
                     camera, extra_media, objects, lights);
}

constexpr const char* kFloor = R"({"name": "floor", "shape": {"type": "quad", "size": [2, 2]},
    "transform": [{"rotate_deg": [-90, [1, 0, 0]]}], "material": {"type": "diffuse", "reflectance": 0.3}})";

// A floor and a mirror 0.5 m above it, facing it, seen from above and beside the mirror.
constexpr const char* kMirrorCamera =
    R"({"position": [0, 0.5, 0.3], "look_at": [0, 0, 0], "fov_deg": 20, "resolution": [16, 16]})";
constexpr const char* kFloorBesideMirror = R"({"name": "floor", "shape": {"type": "quad", "size": [2, 2]},
    "transform": [{"rotate_deg": [-90, [1, 0, 0]]}], "material": {"type": "diffuse", "reflectance": 0.5}},
   {"name": "mirror", "shape": {"type": "quad", "size": [0.3, 0.3]},
    "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0, 0.5, 0]}],
    "material": {"type": "conductor", "n": 0.15, "k": 3.5}})";

// A haze of index 1.2 in a smooth-shaded tumbler of glass of the same index, seen through its wall.
constexpr const char* kTumblerCamera =
    R"({"position": [0, "40 mm", "200 mm"], "look_at": [0, "40 mm", 0], "fov_deg": 6, "resolution": [16, 16]})";
constexpr const char* kHazeTumbler = R"({"name": "tumbler", "shape": {"type": "vessel", "wall": "2 mm", "fill": 0.9,
    "segments": 32, "profile": [[0, 0], ["30 mm", 0], ["32 mm", "90 mm"]]}, "inside": "clear", "contents": "haze"})";
constexpr const char* kHazeMedia = R"(, "clear": {"ior": 1.2},
    "haze": {"ior": 1.2, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700], "value": [8, 2],
             "phase": {"type": "henyey_greenstein", "g": 0.5}}})";

// A pool of water 0.1 m deep and its floor, seen from above and beside it.
constexpr const char* kPoolCamera =
    R"({"position": [0, 0.5, 0.1], "look_at": [0, 0, 0], "fov_deg": 10, "resolution": [16, 16]})";
constexpr const char* kPool = R"({"name": "pool", "shape": {"type": "box", "size": [0.6, 0.1, 0.6]},
    "transform": [{"translate": [0, 0.05, 0]}], "inside": "water"},
   {"name": "floor", "shape": {"type": "quad", "size": [0.6, 0.6]},
    "transform": [{"rotate_deg": [-90, [1, 0, 0]]}, {"translate": [0, 0.001, 0]}],
    "material": {"type": "diffuse", "reflectance": 0.5}})";

// A glass object of shape `shape` at `translate` (JSON), over the floor.
std::string glass_over_floor(const char* shape, const char* translate) {
  return fmt::format(R"({{"name": "glass", "shape": {}, "transform": [{{"translate": {}}}], "inside": "glass"}}, {})",
                     shape, translate, kFloor);
}

// Four ways the camera sees through glass, each lit where the path tracer's image is complete (the
// lamp's light refracts at most, through faces next-event estimation solves) and each a bias the
// connection could have (the first two here, the last two, whose light tracers need more samples,
// in LightTracerLong below):
// - a floor through a 4 mm slab of coloured glass (a chain of two faces): Fresnel left out at its
//   two crossings would be 8 % bright, the glass's absorption left out 2-15 %;
// - a floor at the bottom of a pool of water (one flat face between the camera in vacuum and the
//   floor in water): the squared ratio of the indices, (1/1.33)², left out would be 77 % bright;
// - a floor through an exact glass ball (a caster, crossed twice: through_casters' solve);
// - a haze inside a smooth-shaded tumbler of glass of index 1.2 (a chain of faces whose normals are
//   interpolated; the ray tube traced from the pinhole; a medium vertex, whose phase function
//   (g = 0.5, the camera across the beam) read the wrong way round would be 40 % dark). The
//   index 1.2 keeps the glass's reflections, which the two estimators treat differently, under
//   1 % of the light.
// Measured (green, 8 seeds each): 1.0015, 1.0023, 0.9990 and 1.0125 of the path tracer.
TEST(LightTracer, SeesThroughGlassAsThePathTracer) {
  const char* above = R"({"position": [0, 1.5, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_deg": 8,
                          "resolution": [16, 16]})";
  expect_light_tracer_sees_as_path(
      scene(above, glass_over_floor(R"({"type": "box", "size": [0.2, 0.004, 0.2]})", "[0, 1, 0]").c_str(),
            R"({"type": "spot", "position": [0.3, 0.5, 0.02], "look_at": [0, 0, 0], "cone_deg": 10,
                "falloff_deg": 1, "spectrum": "D65", "scale": 1})"),
      "floor through a glass slab", 32, 128, 0.03);
  expect_light_tracer_sees_as_path(
      scene(kPoolCamera, kPool,
            R"({"type": "spot", "position": [-0.2, 0.4, 0], "look_at": [0, 0, 0], "cone_deg": 12, "falloff_deg": 1,
                "spectrum": "D65", "scale": 1})"),
      "floor under water", 32, 256, 0.03);
}

// The floor at the bottom of the pool above under a sun 35° from the vertical instead of the spot
// (the floor in view far from the walls): the path tracer reaches the sun through the water's flat
// top (manifold.h: distant_light_through_chains, one crossing), the light tracer's light subpaths refract in from it
// (its camera connections through the same face); bdpt, whose camera subpath sees the floor
// through the water, takes the path tracer's connection (Bdpt::through_glass) and agrees too.
// What it catches: the beam's compression left out (cos θ_l/cos θ_x: 10 % bright) or a
// radiance's n² (77 %), Fresnel left out (2 %, under the cap), and a sun the path tracer or bdpt
// does not reach through water (before: black).
TEST(LightTracer, SeesASunThroughWaterAsThePathTracer) {
  const std::string json = scene(kPoolCamera, kPool,
                                 R"({"type": "distant", "direction": [0.5736, -0.8192, 0], "spectrum": "D65", "scale": 1})");
  expect_light_tracer_sees_as_path(json, "floor under water, a sun", 16, 1024, 0.03);
  const SceneDesc desc = parse_scene(json, "sun_over_pool.json");
  expect_agree("floor under water, a sun", "path", image_means(desc, IntegratorType::path, 16), "bdpt",
               image_means(desc, IntegratorType::bdpt, 4), 0.03);
}

// The last two of the four: through an exact ball and a smooth-shaded tumbler. About 11 s on an
// idle core (the ball's light tracer is 512 spp): `long`.
TEST(LightTracerLong, SeesThroughGlassAsThePathTracer) {
  expect_light_tracer_sees_as_path(
      scene(R"({"position": [0, 0.3, 0], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_deg": 4,
                "resolution": [16, 16]})",
            glass_over_floor(R"({"type": "sphere", "radius": 0.02})", "[0, 0.05, 0]").c_str(),
            R"({"type": "spot", "position": [0.2, 0.1, 0.01], "look_at": [0, 0, 0], "cone_deg": 6,
                "falloff_deg": 1, "spectrum": "D65", "scale": 1})"),
      "floor through a glass ball", 32, 512, 0.05);
  expect_light_tracer_sees_as_path(
      scene(kTumblerCamera, kHazeTumbler,
            R"({"type": "spot", "position": [0, "300 mm", 0], "look_at": [0, 0, 0], "cone_deg": 5, "falloff_deg": 1,
                "spectrum": "D65", "scale": 1})",
            kHazeMedia),
      "haze in a smooth-shaded tumbler", 256, 384, 0.04);
}

// The path tracer with its light paths against the light tracer, where the camera sees everything
// directly (so the light tracer's image is complete) and some light reaches what it sees by paths
// that next-event estimation does not make: with them, the path tracer's image is the light
// tracer's, in each channel within 4 standard errors of the difference (those under 4 % of it
// where the light next-event estimation leaves out is a fifth, under 8 % where the bias to catch is
// a double count).
// A floor beside a mirror over a point lamp: the mirror's light, 22 % of the floor's, is missing
// without them (asserted: more than 6 standard errors dark), and the light paths counted again
// where next-event estimation makes them (the lamp's direct light) would be 80 % bright. A floor
// under a slab of glass lit through it from above: next-event estimation solves the paths through
// the slab's two faces, which counted again would double the floor; the light through the slab's
// edges, which it does not solve, is 2 % of the floor's, in lines where the edges focus it. Under
// a 4 cm glass block, the light through its sides, where the straight segment crosses its top and
// bottom, is 6 % of the floor's: a path next-event estimation solves through the top and bottom
// taken for the light path's own would drop it (the match; asserted: more than 6 standard errors
// dark without the light paths). A floor
// lit through an exact glass ball (next-event estimation's casters: the caustic and the shadow,
// seen from low beside the ball) and a haze lit from the side through a smooth-shaded tumbler (a
// scattering vertex, a chain of interpolated normals, a spot's profile): the paths next-event
// estimation solves there, counted again, would double the light they carry; what it does not
// (the ball's and the glass's reflections inside) is a few per cent. (The tumbler's glass and
// haze have index 1.2, so the camera's own reflections in its wall, which the light tracer leaves
// out, are under 1 %.) The mirror and the slab here; the block (its light tracer 2048 spp), the
// ball and the tumbler in PathTracerLightPathsLong.
// (`bare_spp`: the samples of the render without the light paths.)
void expect_light_paths_complete(const std::string& json, const char* what, int path_spp, int light_spp, double cap,
                                 bool dark_without, int bare_spp = 8) {
  const SceneDesc desc = parse_scene(json, "light_paths.json");
  const auto light = image_means(desc, IntegratorType::light, light_spp);
  const auto with = image_means(desc, IntegratorType::path, path_spp, true);
  const auto bare = image_means(desc, IntegratorType::path, bare_spp);
  for (int c = 0; c < 3; ++c) {
    const test::Estimate &l = light[c], &p = with[c], &b = bare[c];
    const double se = std::hypot(p.standard_error, l.standard_error);
    std::printf("%s, ch %d: light tracer %.5f ± %.5f, path with light paths %.5f ± %.5f, without %.5f ± %.5f\n", what,
                c, l.mean, l.standard_error, p.mean, p.standard_error, b.mean, b.standard_error);
    EXPECT_LT(std::abs(p.mean - l.mean), 4.0 * se) << what << " ch " << c;
    EXPECT_LT(4.0 * se, cap * l.mean) << what << " ch " << c << ": too noisy";
    if (dark_without) {
      EXPECT_GT(l.mean - b.mean, 6.0 * std::hypot(l.standard_error, b.standard_error)) << what << " ch " << c;
    }
  }
}

TEST(PathTracerLightPaths, CompleteWhatNextEventEstimationMakes) {
  expect_light_paths_complete(
      scene(kMirrorCamera, kFloorBesideMirror,
            R"({"type": "point", "position": [0.1, 0.3, 0.05], "spectrum": "D65", "scale": 0.1})"),
      "floor lit by a lamp and its mirror", 128, 512, 0.04, true);
  expect_light_paths_complete(
      scene(R"({"position": [0, 0.6, 0.6], "look_at": [0, 0, 0], "fov_deg": 10, "resolution": [16, 16]})",
            glass_over_floor(R"({"type": "box", "size": [0.3, 0.004, 0.3]})", "[0, 0.3, -0.1]").c_str(),
            R"({"type": "point", "position": [0, 0.8, -0.1], "spectrum": "D65", "scale": 1})"),
      "floor lit through a glass slab", 64, 512, 0.08, false);
}

// The last three of the five (the glass block, the ball and the tumbler): about 14 s on an idle
// core, the block's light tracer 2048 spp: `long`.
TEST(PathTracerLightPathsLong, CompleteWhatNextEventEstimationMakes) {
  expect_light_paths_complete(
      scene(R"({"position": [0, 0.5, 0.5], "look_at": [0.06, 0, 0], "fov_deg": 10, "resolution": [16, 16]})",
            glass_over_floor(R"({"type": "box", "size": [0.1, 0.04, 0.1]})", "[0, 0.08, -0.1]").c_str(),
            R"({"type": "point", "position": [0, 0.3, -0.1], "spectrum": "D65", "scale": 1})"),
      "floor lit through a glass block", 128, 2048, 0.04, true);
  expect_light_paths_complete(
      scene(R"({"position": [0, 0.04, 0.25], "look_at": [0, 0, -0.03], "fov_deg": 6, "resolution": [16, 16]})",
            glass_over_floor(R"({"type": "sphere", "radius": 0.02})", "[0, 0.05, 0]").c_str(),
            R"({"type": "spot", "position": [0.05, 0.4, 0.02], "look_at": [0, 0.05, 0], "cone_deg": 8,
                "falloff_deg": 1, "spectrum": "D65", "scale": 1})"),
      "floor lit through a glass ball", 64, 512, 0.08, false);
  expect_light_paths_complete(scene(kTumblerCamera, kHazeTumbler,
                                    R"({"type": "spot", "position": ["300 mm", "50 mm", 0], "look_at": [0, "40 mm", 0],
                            "cone_deg": 6, "falloff_deg": 1, "spectrum": "D65", "scale": 1})",
                                    kHazeMedia),
                              "haze lit through a smooth-shaded tumbler", 128, 512, 0.08, false);
}

// A sun's light paths (render.light_paths from a distant lamp, light_prefix.h): the same haze in
// the smooth-shaded tumbler of index 1.2 lit only by a sun from the side, 30° up. Next-event
// estimation reaches it through the wall and through the liquid's surface and the glass above it
// (manifold.h: distant_light_through_chains); the light the wall and the base reflect inside
// (total internal reflection beyond 56°: the sun's light through the wall meets the base at about
// 25°) only the light paths bring, 11 % of the image. Asserted as above (4 standard errors under
// 8 %), and darker without the light paths by more than 6 standard errors (measured 0.988, 0.987
// and 0.989 of the light tracer with them, 0.87 to 0.89 without). 8 s on two idle cores: `long`.
TEST(PathTracerLightPathsLong, CompleteASunsLightThroughAGlass) {
  expect_light_paths_complete(
      scene(kTumblerCamera, kHazeTumbler,
            R"({"type": "distant", "direction": [0.8, -0.5, -0.3], "spectrum": "D65", "scale": 1})", kHazeMedia),
      "haze lit by a sun through a smooth-shaded tumbler", 256, 2048, 0.08, true, 64);
}

// A tumbler under a sun with glass of index 1.0001 and haze of 1.0002: next-event estimation
// solves the chains through the wall's two faces (paths all but straight), and almost nothing
// reflects, so the light
// paths, which count only what it does not make, add almost nothing: the image with them within
// 0.3 % of the image without, at the same seed (the camera samples draw the same numbers). Before
// the match of a light path with a solved path allowed for the light path's ray offsets
// (made_within_m: they put its crossings up to 1.5e-6 m off the exact path's, where 1e-5 of its
// length is 3e-7 to 9e-7 m), a fifth of the paths through the wall were counted again: 10 to 11 %
// more (measured, 1.0008 now: the glass's reflections).
TEST(PathTracerLightPaths, ASunsLightPathsAddNothingThatNextEventEstimationMakes) {
  // (The tumbler alone: the disk the sun's rays start on lies a few centimetres from it, so the
  // paths are short and 1e-5 of them was below the offsets.)
  SceneDesc desc = parse_scene(R"({
    "camera": {"position": [0, "60 mm", "260 mm"], "look_at": [0, "45 mm", 0], "fov_deg": 22, "resolution": [16, 16]},
    "render": {"integrator": "path", "spectral": "full", "max_depth": 64, "spp": 64, "seed": 3},
    "world_medium": "air",
    "media": {"glass": {"ior": 1.0001},
              "haze": {"ior": 1.0002, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                                                     "value": [30, 15], "phase": {"type": "henyey_greenstein", "g": 0.3}}}},
    "objects": [{"name": "tumbler", "shape": {"type": "vessel", "wall": "2 mm", "fill": 0.8, "segments": 64,
                                              "profile": [[0, 0], ["30 mm", 0], ["32 mm", "90 mm"]]},
                 "inside": "glass", "contents": "haze"}],
    "lights": [{"type": "distant", "direction": [0.64, -0.77, 0], "spectrum": "D65", "scale": 1}]
  })", "sun_tumbler_matched.json");
  const Film without = test::render_desc(desc);
  desc.render.light_paths = true;
  const Film with = test::render_desc(desc);
  for (int c = 0; c < 3; ++c) {
    const double a = test::channel_estimate(without, c, 0, 0, without.width, without.height).mean;
    const double b = test::channel_estimate(with, c, 0, 0, with.width, with.height).mean;
    std::printf("sun through a tumbler of index 1.0001 and 1.0002, ch %d: with light paths %.6f, without %.6f (%.5f of it)\n", c,
                b, a, b / a);
    EXPECT_GT(a, 0.0);
    EXPECT_NEAR(b / a, 1.0, 0.003) << "ch " << c;
  }
}

// bdpt's light through glass to the camera (Bdpt::through_glass_to_camera) against the light
// tracer, where the light tracer's image is complete (the camera sees directly or through a
// slab, whose own reflections of the dark scene are a few tenths of a per cent) and every lamp's
// light reaches part of what the camera sees by a mirror, which bdpt's next-event estimation
// through glass does not solve: bdpt's image the light tracer's in each channel, within 4 standard
// errors of their difference (those under `cap` of it).
// - A floor beside a mirror under a point lamp, its left half seen through a slab of glass below the
//   lamp: the mirror's light on the floor behind the slab, 16 % of it there, is this strategy's
//   alone (without it the image reads 0.92 of the light tracer's); where the floor is seen
//   directly, light tracing's straight connection (t = 1) has it, and the strategy's straight
//   splats counted there too read 1.13; the lamp's own light reaches the floor behind the slab
//   through it along paths bdpt's camera-side next-event estimation through glass makes, which
//   counted again read 1.42.
// - A floor and a white card standing on it, seen through a slab and lit only by a spot's beam
//   off a mirror: the light the card sends to the floor bdpt makes by connecting the two, and the
//   strategy's splats from the floor, the second non-specular vertex of those light paths, would
//   count it again (1.085 of the image); without the strategy, 0.10.
// - A thin chromatic haze (index 1, optical depth 0.4 to 0.2 across) seen through a pane and lit
//   only by a spot's beam off a mirror, in hero mode: a medium vertex's splats and their
//   spectral-MIS ratios (without the strategy, 0.12 of the image).
// Measured (green, 8 seeds): 0.999, 0.997 and 0.994 of the light tracer. The first and the third
// here, the card in BidirectionalLong.
void expect_bdpt_complete(const std::string& json, const char* what, int bdpt_spp, int light_spp, double cap,
                          SpectralMode mode = SpectralMode::full) {
  SceneDesc desc = parse_scene(json, "bdpt_through_glass.json");
  desc.render.spectral = mode;
  expect_agree(what, "light tracer", image_means(desc, IntegratorType::light, light_spp), "bdpt",
               image_means(desc, IntegratorType::bdpt, bdpt_spp), cap);
}

TEST(Bidirectional, CompletesThroughGlassWhatItsNextEventEstimationLeaves) {
  const std::string slab = fmt::format(R"({}, {{"name": "slab", "shape": {{"type": "box", "size": [0.2, 0.004, 0.4]}},
                                         "transform": [{{"translate": [-0.1, 0.2, 0.12]}}], "inside": "glass"}})",
                                       kFloorBesideMirror);
  expect_bdpt_complete(scene(kMirrorCamera, slab.c_str(),
                             R"({"type": "point", "position": [-0.1, 0.3, 0.05], "spectrum": "D65", "scale": 0.1})"),
                       "floor behind a slab lit by a lamp and its mirror", 128, 128, 0.06);
  expect_bdpt_complete(
      scene(R"({"position": [0, 0.1, 0.5], "look_at": [0, 0.1, 0], "fov_deg": 12, "resolution": [16, 16]})",
            R"({"name": "haze", "shape": {"type": "box", "size": [0.1, 0.1, 0.1]},
                "transform": [{"translate": [0, 0.1, 0]}], "inside": "haze"},
               {"name": "mirror", "shape": {"type": "quad", "size": [0.3, 0.3]},
                "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0, 0.4, 0]}],
                "material": {"type": "conductor", "n": 0.15, "k": 3.5}},
               {"name": "pane", "shape": {"type": "box", "size": [0.3, 0.3, 0.004]},
                "transform": [{"translate": [0, 0.1, 0.2]}], "inside": "glass"})",
            R"({"type": "spot", "position": [0.1, 0.2, 0], "look_at": [0.06, 0.4, 0], "cone_deg": 12,
                "falloff_deg": 1, "spectrum": "D65", "scale": 1})",
            R"(, "haze": {"ior": 1.0, "scattering": {"unit": "attenuation_per_m", "wavelength_nm": [400, 700],
                         "value": [4, 2], "phase": {"type": "henyey_greenstein", "g": 0.0}}})"),
      "thin haze behind a pane lit by a mirror (hero)", 64, 64, 0.1, SpectralMode::hero);
}

// The second of the three, the floor and the card (about 7 s on an idle core): `long`.
TEST(BidirectionalLong, CompletesThroughGlassWhatItsNextEventEstimationLeaves) {
  expect_bdpt_complete(
      scene(R"({"position": [0, 0.5, 0.3], "look_at": [0, 0, 0], "fov_deg": 24, "resolution": [16, 16]})",
            R"({"name": "floor", "shape": {"type": "quad", "size": [2, 2]},
                            "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
                            "material": {"type": "diffuse", "reflectance": 0.5}},
                           {"name": "card", "shape": {"type": "quad", "size": [0.3, 0.15]},
                            "transform": [{"rotate_deg": [90, [0, 1, 0]]}, {"translate": [-0.08, 0.1, 0]}],
                            "material": {"type": "diffuse", "reflectance": 0.9}},
                           {"name": "mirror", "shape": {"type": "quad", "size": [0.4, 0.4]},
                            "transform": [{"rotate_deg": [90, [1, 0, 0]]}, {"translate": [0, 0.5, 0]}],
                            "material": {"type": "conductor", "n": 0.15, "k": 3.5}},
                           {"name": "slab", "shape": {"type": "box", "size": [0.6, 0.004, 0.6]},
                            "transform": [{"translate": [0, 0.2, 0.12]}], "inside": "glass"})",
            R"({"type": "spot", "position": [0.1, 0.3, 0.05], "look_at": [0.05, 0.5, 0], "cone_deg": 30,
                            "falloff_deg": 2, "spectrum": "D65", "scale": 1})"),
      "floor and card behind a slab lit by a mirror", 96, 96, 0.06);
}

// The same seed gives the same image at 1 and 2 threads with the light paths (their splats are
// fixed-point sums in any order; each light path's numbers are its pixel's and sample's), and the
// light tracer and bdpt through glass too: the lit tumbler, whose light paths splat through its
// wall.
TEST(PathTracerLightPaths, TheSameImageAtAnyThreadCount) {
  for (const char* integrator : {"path", "light", "bdpt"}) {
    SceneDesc desc = parse_scene(test::lit_tumbler(integrator), "tumbler.json");
    desc.render.spp = 8;
    desc.render.light_paths = true;
    const Film one = test::render_desc(desc, 1);
    EXPECT_EQ(one.rgb, test::render_desc(desc, 2).rgb) << integrator;
    // (a test of nothing would pass too: the light paths splat there, the light tracer sees the
    // liquid, bdpt reaches it through the glass by both its strategies)
    if (desc.render.integrator == IntegratorType::path)
      desc.render.light_paths = false;
    else
      desc.render.manifold = false;
    EXPECT_NE(one.rgb, test::render_desc(desc, 1).rgb) << integrator;
  }
}

}  // namespace
}  // namespace bouguer
