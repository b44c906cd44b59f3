#include <gtest/gtest.h>

#include "bouguer/core/error.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

const fs::path kBad = fs::path(BOUGUER_SOURCE_DIR) / "tests" / "bad_scenes";

TEST(SceneLoader, LengthsWithUnits) {
  EXPECT_DOUBLE_EQ(parse_length_m("5 mm"), 0.005);
  EXPECT_DOUBLE_EQ(parse_length_m("0.5 cm"), 0.005);
  EXPECT_DOUBLE_EQ(parse_length_m("1.2 um"), 1.2e-6);
  EXPECT_DOUBLE_EQ(parse_length_m("1.2µm"), 1.2e-6);
  EXPECT_DOUBLE_EQ(parse_length_m("2 m"), 2.0);
  EXPECT_DOUBLE_EQ(parse_length_m("-40 mm"), -0.04);
  EXPECT_THROW(parse_length_m("5 inches"), Error);
  EXPECT_THROW(parse_length_m("mm"), Error);
  // A string without a unit, and NaN or infinity with one, are refused with what is wrong.
  const auto message = [](const char* text) {
    try {
      parse_length_m(text);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("5").find("'5' has no unit"), std::string::npos) << message("5");
  EXPECT_NE(message("nan").find("not a finite length"), std::string::npos) << message("nan");
  EXPECT_NE(message("inf mm").find("not a finite length"), std::string::npos) << message("inf mm");
}

// The example scene of issue #3, exactly as written there.
TEST(SceneLoader, TheIssueExampleLoadsAndCompiles) {
  const SceneDesc s = load_scene(fs::path(BOUGUER_SOURCE_DIR) / "scenes" / "examples" / "issue3.json");
  EXPECT_DOUBLE_EQ(s.camera.position_m.y, 0.15);
  EXPECT_EQ(s.camera.width_px, 400);
  EXPECT_EQ(s.render.seed, 7u);
  ASSERT_EQ(s.objects.size(), 3u);
  EXPECT_EQ(*s.objects[0].inside, "red_glass");
  EXPECT_TRUE(s.media.at("probe").absorbing);
  // 0.9 absorbance per cm at 380 nm.
  EXPECT_NEAR(eval(s.media.at("probe").sigma_a_per_m, 380.0), 0.9 * 230.25850929940458, 1e-9);
  const RenderScene r = compile(s);
  EXPECT_EQ(r.surfaces.size(), 3u);
  // Two emissive triangles (the quad), each an area light.
  EXPECT_EQ(std::count_if(r.lights.begin(), r.lights.end(), [](const Light& l) { return std::holds_alternative<AreaLight>(l); }), 2);
}

struct BadScene {
  const char* file;
  const char* expected;  // in the message
};

// Every bad scene fails with one line naming the file and what is wrong.
TEST(SceneLoader, BadScenesFailWithOneClearLine) {
  const BadScene cases[] = {
      {"malformed_json.json", "malformed_json.json:5:"},
      {"unknown_key.json", "did you mean 'absorption'?"},
      {"unknown_medium.json", "unknown medium 'glas' (did you mean 'glass'?)"},
      {"open_mesh.json", "object 'open_tetra': cannot bound medium 'glass': the surface is open"},
      {"missing_mesh.json", "no_such_bunny.obj' not found"},
      {"negative_size.json", "objects[0].shape.size[1]: must be a positive length"},
      {"bad_unit.json", "unknown length unit 'inches'"},
      {"unknown_library.json", "did you mean 'red-wine'?"},
      {"flat_interface.json", "a flat shape cannot bound medium 'glass'"},
      {"impossible_ior.json", "media.glass.ior: a refractive index must be between 1 and 5"},
      {"not_an_object.json", "expected an object"},
      {"missing_environment.json", "background.environment: no such file"},
      {"negative_rgb.json", "reflectance.rgb[1]: must not be negative"},
      {"rgb_above_one.json", "reflectance.rgb[1]: a reflectance must lie between 0 and 1"},
      {"infrared_table.json", "media.glass.absorption: the table covers 1000-1100 nm, none of the range 360-830 nm"},
      {"corrupt_environment.json", "not_an_image.exr"},
  };
  for (const auto& c : cases) {
    try {
      compile(load_scene(kBad / c.file));
      ADD_FAILURE() << c.file << " loaded";
    } catch (const Error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(c.expected), std::string::npos) << c.file << ": " << m;
      EXPECT_NE(m.find(c.file), std::string::npos) << c.file << ": " << m;
      EXPECT_EQ(m.find('\n'), std::string::npos) << c.file;
    }
  }
}

// render.manifold (next-event estimation through glass): on unless a scene says false, and a
// value that is not a boolean is one line naming the key.
TEST(SceneLoader, ManifoldKeyIsABoolean) {
  const std::string base = R"({"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "fov_deg": 30},
                               "render": {"integrator": "path"%s},
                               "objects": [], "background": {"spectrum": "E", "scale": 1}})";
  auto with = [&](const std::string& extra) {
    std::string text = base;
    text.replace(text.find("%s"), 2, extra);
    return text;
  };
  EXPECT_TRUE(parse_scene(with(""), "a.json").render.manifold);
  EXPECT_FALSE(parse_scene(with(R"(, "manifold": false)"), "a.json").render.manifold);
  EXPECT_FALSE(parse_scene(with(""), "a.json").render.area_lamp_chains.has_value());
  EXPECT_EQ(parse_scene(with(R"(, "area_lamp_chains": true)"), "a.json").render.area_lamp_chains, true);
  EXPECT_EQ(parse_scene(with(R"(, "area_lamp_chains": false)"), "a.json").render.area_lamp_chains, false);
  try {
    parse_scene(with(R"(, "area_lamp_chains": "yes")"), "a.json");
    ADD_FAILURE() << "a string loaded as area_lamp_chains";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("render.area_lamp_chains"), std::string::npos) << e.what();
  }
  try {
    parse_scene(with(R"(, "manifold": 3)"), "a.json");
    ADD_FAILURE() << "a number loaded as manifold";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("render.manifold"), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

// render.integrator: a scene that names none, or names "auto", has it chosen by trials
// (integrators/choose.h); a named one is rendered by that one; an unknown name lists "auto" too.
TEST(SceneLoader, IntegratorAutoUnlessNamed) {
  auto scene = [](const std::string& render) {
    return R"({"camera": {"position": [0, 0, 1], "look_at": [0, 0, 0], "fov_deg": 30}, )" + render +
           R"("objects": [], "background": {"spectrum": "E", "scale": 1}})";
  };
  constexpr IntegratorType kAuto = IntegratorType::automatic;
  EXPECT_EQ(parse_scene(scene(""), "a.json").render.integrator, kAuto);
  EXPECT_EQ(parse_scene(scene(R"("render": {"spp": 4}, )"), "a.json").render.integrator, kAuto);
  EXPECT_EQ(parse_scene(scene(R"("render": {"integrator": "auto"}, )"), "a.json").render.integrator, kAuto);
  EXPECT_EQ(parse_scene(scene(R"("render": {"integrator": "bdpt"}, )"), "a.json").render.integrator,
            IntegratorType::bdpt);
  try {
    parse_scene(scene(R"("render": {"integrator": "mlt"}, )"), "a.json");
    ADD_FAILURE() << "an unknown integrator loaded";
  } catch (const Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("render.integrator"), std::string::npos) << m;
    EXPECT_NE(m.find("auto"), std::string::npos) << m;
  }
}

// Through the command line: non-zero exit, one line, and an earlier image survives.
TEST(SceneLoader, FailedRenderLeavesTheEarlierImageIntact) {
  const auto dir = test::scratch_dir("failed_render");
  test::write_file(dir / "earlier.png", "an earlier render");
  for (const char* bad : {"malformed_json.json", "open_mesh.json", "negative_size.json", "missing_mesh.json"}) {
    const auto r = test::run_bouguer({"render", (kBad / bad).string(), "-o", (dir / "earlier.png").string()});
    EXPECT_EQ(r.exit_code, 1) << bad;
    EXPECT_EQ(test::line_count(r.err), 1) << bad << ": " << r.err;
    EXPECT_EQ(test::read_file(dir / "earlier.png"), "an earlier render") << bad;
  }
  const auto missing = test::run_bouguer({"render", (dir / "nothing.json").string()});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("file not found"), std::string::npos);
  const auto bad_flag = test::run_bouguer({"render", (kBad / "open_mesh.json").string(), "--spp", "0"});
  EXPECT_EQ(bad_flag.exit_code, 2);
  EXPECT_EQ(test::line_count(bad_flag.err), 1);
}

}  // namespace
}  // namespace bouguer
