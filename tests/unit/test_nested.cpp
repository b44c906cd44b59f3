// Nested media by priority (#18): the bookkeeping of the set of objects a path is inside
// (scene/nested.h), the scene format's `priority` and its refusals, and overlapping absorbers whose
// transmittance has a closed form, through camera rays and shadow rays alike.
#include <gtest/gtest.h>
#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "bouguer/core/error.h"
#include "bouguer/render/film.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "bouguer/scene/nested.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

// Glass (priority 1) and wine (priority 2) in air: media 0 air, 1 glass, 2 wine.
constexpr int kAir = 0, kGlass = 1, kWine = 2;
const std::vector<NestedObject> kGlassAndWine = {{1, kGlass, kAir}, {2, kWine, kAir}};
const InsideSet kInGlass = nested_bit(0), kInWine = nested_bit(1);

TEST(NestedMedia, TheMediumIsTheHighestPriorityObjectsOrTheOneAround) {
  EXPECT_EQ(nested_medium(kGlassAndWine, 0, kAir), kAir);
  EXPECT_EQ(nested_medium(kGlassAndWine, kInGlass, kAir), kGlass);
  EXPECT_EQ(nested_medium(kGlassAndWine, kInWine, kAir), kWine);
  EXPECT_EQ(nested_medium(kGlassAndWine, kInGlass | kInWine, kAir), kWine);
}

TEST(NestedMedia, SidesOfASurfaceFollowTheSetTheOwnBitIgnored) {
  auto expect_sides = [](int k, InsideSet inside, int front, int behind) {
    const NestedSides s = nested_sides(kGlassAndWine, k, inside);
    EXPECT_EQ(s.front, front) << "object " << k << " set " << inside;
    EXPECT_EQ(s.behind, behind) << "object " << k << " set " << inside;
  };
  expect_sides(0, 0, kAir, kGlass);              // the glass's outer wall
  expect_sides(0, kInGlass, kAir, kGlass);       // the same, met from inside
  expect_sides(1, 0, kAir, kWine);               // the wine's free surface in the cavity
  expect_sides(1, kInGlass, kGlass, kWine);      // the wine's side inside the glass wall: glass|wine
  expect_sides(0, kInWine, kWine, kWine);        // the cavity wall under the wine: a false intersection
  expect_sides(0, kInWine | kInGlass, kWine, kWine);
  expect_sides(1, kInGlass | kInWine, kGlass, kWine);
}

TEST(NestedMedia, LeavingASurfaceSetsTheBitByTheSideOfTheDirection) {
  EXPECT_EQ(inside_after(0, 1, -0.5), kInWine);             // into the object (against its outward normal)
  EXPECT_EQ(inside_after(kInWine, 1, -0.5), kInWine);       // already in: unchanged
  EXPECT_EQ(inside_after(kInWine | kInGlass, 1, 0.5), kInGlass);  // out of it
  EXPECT_EQ(inside_after(kInGlass, 1, 0.5), kInGlass);      // out of what it was not in: nothing to remove
  EXPECT_EQ(inside_after(0, 63, -1.0), nested_bit(63));
}

std::string boxes_scene(const std::string& a_extra, const std::string& b_extra, const std::string& b_medium = "b",
                        const char* floor_y = "0 mm", const char* integrator = "path") {
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, "100 mm", 0], "look_at": [0, 0, 0], "up": [0, 0, -1],
                "width": "40 mm", "resolution": [8, 8]}},
    "render": {{"integrator": "{}", "spectral": "rgb3", "spp": 4, "max_depth": 8, "merge_radius": "0.1 mm"}},
    "world_medium": "clear",
    "media": {{"clear": {{"ior": 1.0}},
              "a": {{"ior": 1.0, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [300, 900], "value": [10, 10]}}}},
              "b": {{"ior": 1.0, "absorption": {{"unit": "attenuation_per_m", "wavelength_nm": [300, 900], "value": [30, 30]}}}}}},
    "objects": [
      {{"name": "box a", "shape": {{"type": "box", "size": ["20 mm", "20 mm", "20 mm"]}},
        "transform": [{{"translate": [0, "20 mm", 0]}}], "inside": "a"{}}},
      {{"name": "box b", "shape": {{"type": "box", "size": ["20 mm", "16 mm", "16 mm"]}},
        "transform": [{{"translate": ["10 mm", "20 mm", 0]}}], "inside": "{}"{}}},
      {{"name": "floor", "shape": {{"type": "quad", "size": ["1 m", "1 m"]}},
        "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}, {{"translate": [0, "{}", 0]}}],
        "material": {{"type": "diffuse", "reflectance": 0.5}}}}
    ],
    "lights": [{{"type": "distant", "direction": [0, -1, 0], "spectrum": "E", "scale": 1}}],
    "background": {{"spectrum": "E", "scale": 0}}
  }})",
                     integrator, a_extra, b_medium, b_extra, floor_y);
}

// The floor seen from above through two overlapping boxes of absorbing media that match the
// world's index, lit from straight above: each pixel is the bare floor's times T² (the camera ray
// and the shadow ray cross the same media). Box a is 20 mm high (y 10–30 mm), box b 16 mm
// (y 12–28 mm: no faces coincide). Columns of the 8×8 image, 5 mm each from x = −20 mm: 1 (bare),
// 2 (box a alone), 4 and 5 (the overlap), 6 (box b alone); rows 3 and 4 lie in both boxes.
struct BoxTransmittances {
  double a_alone, overlap, b_alone;
};

BoxTransmittances measure(const std::string& json) {
  const Film f = test::render_text(json, 1);
  auto mean = [&](int x) {
    double sum = 0.0;
    for (int y = 3; y <= 4; ++y) sum += f.rgb_at(x, y).y;
    return sum / 2.0;
  };
  const double bare = mean(1);
  EXPECT_GT(bare, 0.0);
  return {mean(2) / bare, 0.5 * (mean(4) + mean(5)) / bare, mean(6) / bare};
}

TEST(NestedMedia, OverlapTakesTheHigherPrioritysMediumAlongCameraAndShadowRays) {
  // T² along 20 mm of a (σ_a 10/m), 16 mm of b (30/m), and through the overlap with b on top:
  // 4 mm of a and 16 mm of b.
  const double t_a = std::exp(-2.0 * 10.0 * 0.020), t_b = std::exp(-2.0 * 30.0 * 0.016);
  const double t_b_in_a = std::exp(-2.0 * (10.0 * 0.004 + 30.0 * 0.016));
  const BoxTransmittances b_wins = measure(boxes_scene(R"(, "priority": 1)", R"(, "priority": 2)"));
  EXPECT_NEAR(b_wins.a_alone, t_a, 1e-4);
  EXPECT_NEAR(b_wins.overlap, t_b_in_a, 1e-4);
  EXPECT_NEAR(b_wins.b_alone, t_b, 1e-4);
  const BoxTransmittances a_wins = measure(boxes_scene(R"(, "priority": 7)", R"(, "priority": 2)"));
  EXPECT_NEAR(a_wins.a_alone, t_a, 1e-4);
  EXPECT_NEAR(a_wins.overlap, t_a, 1e-4);
  EXPECT_NEAR(a_wins.b_alone, t_b, 1e-4);
  std::printf("overlapping absorbers, T²: a %.5f (exact %.5f), b %.5f (%.5f), overlap b on top %.5f (%.5f), "
              "a on top %.5f (%.5f)\n",
              b_wins.a_alone, t_a, b_wins.b_alone, t_b, b_wins.overlap, t_b_in_a, a_wins.overlap, t_a);
}

// The floor raised to y = 20 mm, through the middle of both boxes: its shadow rays and
// connections start inside them, from the set the camera path arrived with, in every estimator
// that connects from a surface (vcm with a merging radius of 0.1 mm: against a delta light its
// merges add nothing measurable at the tolerance).
TEST(NestedMedia, ConnectionsFromInsideNestedObjectsStartFromTheirSet) {
  const double t_a = std::exp(-2.0 * 10.0 * 0.010), t_b = std::exp(-2.0 * 30.0 * 0.008);
  const double t_b_in_a = std::exp(-2.0 * (10.0 * 0.002 + 30.0 * 0.008));
  for (const char* integrator : {"whitted", "path", "bdpt", "vcm"}) {
    const BoxTransmittances b_wins =
        measure(boxes_scene(R"(, "priority": 1)", R"(, "priority": 2)", "b", "20 mm", integrator));
    EXPECT_NEAR(b_wins.a_alone, t_a, 1e-4) << integrator;
    EXPECT_NEAR(b_wins.overlap, t_b_in_a, 1e-4) << integrator;
    EXPECT_NEAR(b_wins.b_alone, t_b, 1e-4) << integrator;
    const BoxTransmittances a_wins =
        measure(boxes_scene(R"(, "priority": 7)", R"(, "priority": 2)", "b", "20 mm", integrator));
    EXPECT_NEAR(a_wins.overlap, t_a, 1e-4) << integrator;
    std::printf("floor inside the boxes, %s, T²: overlap b on top %.5f (exact %.5f), a on top %.5f (%.5f)\n",
                integrator, b_wins.overlap, t_b_in_a, a_wins.overlap, t_a);
  }
}

TEST(NestedMedia, CompileOrdersTheObjectsByPriorityAndMarksTheirSurfaces) {
  const RenderScene s = compile(parse_scene(boxes_scene(R"(, "priority": 5)", R"(, "priority": 2)"), "boxes.json"));
  ASSERT_EQ(s.nested.size(), 2u);
  EXPECT_EQ(s.nested[0].priority, 2);
  EXPECT_EQ(s.media[static_cast<std::size_t>(s.nested[0].inside)].name, "b");
  EXPECT_EQ(s.nested[1].priority, 5);
  for (const Surface& surface : s.surfaces)
    EXPECT_EQ(surface.nested, surface.object == "box a" ? 1 : surface.object == "box b" ? 0 : -1) << surface.object;
  const RenderScene plain = compile(parse_scene(boxes_scene("", ""), "boxes.json"));
  EXPECT_TRUE(plain.nested.empty());
  for (const Surface& surface : plain.surfaces) EXPECT_EQ(surface.nested, -1);
}

std::string error_of(const std::string& json) {
  try {
    compile(parse_scene(json, "boxes.json"));
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(NestedMedia, OverlapsOfOnePriorityWithDifferentMediaAreRefusedNamingBoth) {
  EXPECT_EQ(error_of(boxes_scene(R"(, "priority": 3)", R"(, "priority": 3)")),
            "boxes.json: objects 'box a' and 'box b' overlap with the same priority 3 and different media ('a', "
            "'b'): give one a higher priority");
  EXPECT_EQ(error_of(boxes_scene(R"(, "priority": 3)", R"(, "priority": 3)", "a")), "");  // the same medium
  // Side by side, not overlapping: accepted.
  std::string apart = boxes_scene(R"(, "priority": 3)", R"(, "priority": 3)");
  const std::string at = R"(["10 mm", "20 mm", 0])";
  apart.replace(apart.find(at), at.size(), R"(["30 mm", "20 mm", 0])");
  EXPECT_EQ(error_of(apart), "");
}

TEST(NestedMedia, PriorityIsRefusedWhereItCannotApply) {
  auto bad = [](const std::string& object) {
    return error_of(fmt::format(R"({{"media": {{"glass": {{"ior": 1.5}}, "wine": {{"ior": 1.34}}}},
      "objects": [{}]}})",
                                object));
  };
  EXPECT_EQ(bad(R"({"shape": {"type": "box", "size": [1, 1, 1]}, "material": {"type": "diffuse"}, "priority": 1})"),
            "boxes.json: objects[0].priority: belongs to interfaces ('inside')");
  EXPECT_EQ(bad(R"({"shape": {"type": "box", "size": [1, 1, 1]}, "inside": "glass", "roughness": 0.1, "priority": 1})"),
            "boxes.json: objects[0].priority: only smooth interfaces take a priority (roughness 0)");
  EXPECT_EQ(bad(R"({"shape": {"type": "vessel", "profile": [[0, 0], [0.03, 0], [0.03, 0.09]], "fill": 0.5},
                    "inside": "glass", "contents": "wine", "priority": 1})"),
            "boxes.json: objects[0].priority: a vessel with contents cannot take a priority: model the liquid as an "
            "object of its own");
  EXPECT_NE(bad(R"({"shape": {"type": "box", "size": [1, 1, 1]}, "inside": "glass", "priority": -1})").find(
                "objects[0].priority"),
            std::string::npos);
  EXPECT_NE(bad(R"({"shape": {"type": "box", "size": [1, 1, 1]}, "inside": "glass", "priority": 1.5})").find(
                "objects[0].priority"),
            std::string::npos);
}

// Analytic spheres have no vertices to probe: the centre of each stands for them, so a sphere wholly
// inside a box or inside another sphere of the same priority is still found.
TEST(NestedMedia, OverlapsOfAnalyticShapesAreFoundByTheirCentres) {
  auto scene = [](const std::string& outer_shape, const std::string& inner_medium) {
    return fmt::format(R"({{"media": {{"a": {{"ior": 1.5}}, "b": {{"ior": 1.33}}}},
      "objects": [{{"name": "outer", "shape": {}, "inside": "a", "priority": 2}},
                  {{"name": "inner", "shape": {{"type": "sphere", "radius": "5 mm"}},
                    "transform": [{{"translate": ["2 mm", 0, 0]}}], "inside": "{}", "priority": 2}}]}})",
                       outer_shape, inner_medium);
  };
  const std::string box = R"({"type": "box", "size": ["40 mm", "40 mm", "40 mm"]})";
  const std::string sphere = R"({"type": "sphere", "radius": "20 mm"})";
  for (const std::string& outer : {box, sphere}) {
    EXPECT_EQ(error_of(scene(outer, "b")),
              "boxes.json: objects 'outer' and 'inner' overlap with the same priority 2 and different media ('a', "
              "'b'): give one a higher priority")
        << outer;
    EXPECT_EQ(error_of(scene(outer, "a")), "") << outer;
  }
}

}  // namespace
}  // namespace bouguer
