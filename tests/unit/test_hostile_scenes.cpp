// Scenes and command lines made to break Bouguer (#11): JSON the parser must refuse with its
// place, numbers that would poison the image, renders that cannot fit in memory, and tools asked
// for numbers they cannot give. Each ends in one line naming the file and the place, exit 1
// (2 for a bad command line), and an earlier output at the same path byte for byte as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>

#include "bouguer/core/error.h"
#include "bouguer/render/film.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "support/test_support.h"
#include "support/vdb_files.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

testing::AssertionResult has(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return testing::AssertionSuccess();
  return testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

// What loading and compiling the scene text says (its file is named s.json in messages).
std::string scene_error(const std::string& json) {
  try {
    (void)compile(parse_scene(json, "s.json"));
  } catch (const Error& e) {
    return e.what();
  }
  return "accepted";
}

// A small scene with a glass sphere over a lamp; each placeholder is replaced by a test's value.
std::string scene(const std::string& radius = "\"20 mm\"", const std::string& lamp_scale = "1",
                  const std::string& concentration = "1", const std::string& extra_object = "") {
  return R"({"camera": {"position": [0, "150 mm", "1 mm"], "look_at": [0, 0, 0], "up": [0, 0, -1], "fov_deg": 20,
             "resolution": [16, 16]},
  "render": {"spp": 1},
  "media": {"glass": {"ior": 1.52, "absorption": {"library": "red-glass", "concentration": )" +
         concentration + R"(}}},
  "objects": [
    {"name": "ball", "shape": {"type": "sphere", "radius": )" +
         radius + R"(}, "inside": "glass"},)" + extra_object + R"(
    {"name": "lamp", "shape": {"type": "quad", "size": ["300 mm", "300 mm"]},
     "transform": [{"rotate_deg": [-90, [1, 0, 0]]}, {"translate": [0, "-40 mm", 0]}],
     "emission": {"spectrum": "D65", "scale": )" +
         lamp_scale + R"(}}
  ]})";
}

TEST(HostileScene, TheTestSceneItselfIsAccepted) { EXPECT_EQ(scene_error(scene()), "accepted"); }

TEST(HostileScene, JsonNumbersBeyondADoubleNameTheirLineAndColumn) {
  EXPECT_EQ(scene_error("{\n  \"objects\": [1e999]\n}"),
            "s.json:2:15: the number 1e999 is beyond the range of a double (about ±1.8e308)");
  EXPECT_TRUE(has(scene_error(scene("1e999")), "s.json:6:60: the number 1e999 is beyond the range of a double"));
  EXPECT_TRUE(has(scene_error("{\"objects\": [-1e400]}"), "s.json:1:14: the number -1e400 is beyond"));
}

TEST(HostileScene, DuplicateKeysAreErrors) {
  EXPECT_EQ(scene_error("{\"objects\": [],\n \"objects\": []}"),
            "s.json:2:2: (top level): duplicate key 'objects' (each key may appear once in an object)");
  EXPECT_EQ(scene_error(R"({"objects": [{"shape": {"type": "sphere", "type": "box"}}]})"),
            "s.json:1:43: objects[0].shape: duplicate key 'type' (each key may appear once in an object)");
}

TEST(HostileScene, MalformedJsonIsOneShortLine) {
  const std::string long_token = scene_error("{\"a\": \"" + std::string(100000, 'x') + "\" b}");
  EXPECT_TRUE(has(long_token, "s.json:1:100010: malformed JSON: syntax error while parsing object"));
  EXPECT_TRUE(has(long_token, "… (100004 bytes)"));
  EXPECT_LT(long_token.size(), 300u);
  const std::string deep = scene_error("{\"objects\": " + std::string(100000, '[') + std::string(100000, ']') + "}");
  EXPECT_TRUE(has(deep, "s.json:1:"));
  EXPECT_TRUE(has(deep, "nested deeper than 64 levels"));
  EXPECT_LT(deep.size(), 300u);
  EXPECT_TRUE(has(scene_error("{\"objects\": tru}"), "s.json:1:16: malformed JSON: syntax error while parsing value"));
  EXPECT_EQ(scene_error(""), "s.json:1:1: malformed JSON: syntax error while parsing value - unexpected end of input; expected '[', '{', or a literal");
}

// Values that each pass a plain "is it a number" check, and made most pixels NaN with exit 0.
TEST(HostileScene, NumbersThatWouldPoisonTheImageAreRefusedWithTheirPlace) {
  const std::string box = R"(
    {"name": "far", "shape": {"type": "box", "size": [1, 1, 1]}, "material": {"type": "diffuse"},
     "transform": [{"scale": 1e200}, {"scale": 1e200}]},)";
  const std::string far_box = R"(
    {"name": "far", "shape": {"type": "box", "size": [1, 1, 1]}, "material": {"type": "diffuse"},
     "transform": [{"scale": 1e10}]},)";
  const struct {
    std::string json, message;
  } cases[] = {
      {scene("1e308"), "s.json: objects[0].shape.radius: 1e+308 m is beyond the scene's extent of ±1e+07 m"},
      {scene("\"1e300 km\""), "objects[0].shape.radius: 1e+303 m is beyond the scene's extent"},
      {scene("1e-300"), "objects[0].shape.radius: 1e-300 m is below the smallest length of 1e-09 m"},
      {scene("\"20 mm\"", "1e308"), "s.json: objects[1].emission: the emitted radiance reaches 1.19134e+308, beyond the limit of 1e+12"},
      {scene("\"20 mm\"", "1", "1e308"),
       "s.json: media.glass.absorption: the absorption coefficient σ_a (per metre) is not finite (the product overflows)"},
      {scene("\"20 mm\"", "1", "1e10"), "media.glass.absorption: the absorption coefficient σ_a (per metre) reaches"},
      {scene("\"20 mm\"", "1", "1", box), "s.json: objects[1].transform: the transform is not finite"},
      {scene("\"20 mm\"", "1", "1", far_box), "s.json: object 'far': its transform puts a vertex at x = 5e+09 m, beyond the scene's extent of ±1e+07 m"},
      {R"({"camera": {"up": [1e300, 1e300, 0]}, "objects": []})", "s.json: camera.up: must be a direction of finite, non-zero length"},
      {R"({"objects": [], "lights": [{"type": "point", "position": [0, 1, 0], "spectrum": "D65", "scale": 1e308}]})",
       "s.json: lights[0]: the light's intensity reaches"},
      {R"({"objects": [], "background": {"spectrum": "E", "scale": 1e300}})", "s.json: background: the background's radiance reaches"},
      {R"({"objects": [], "render": {"spp": 18446744073709551615}})",
       "s.json: render.spp: 18446744073709551615 is beyond the largest whole number, 9223372036854775807"},
      {R"({"objects": [], "render": {"spp": 2000000}})", "s.json: render.spp: must be between 1 and 1048576 (got 2000000)"},
      {R"({"objects": [], "render": {"exit_guide": 0}})", "s.json: render.exit_guide: expected true or false, found"},
  };
  for (const auto& c : cases) {
    const std::string e = scene_error(c.json);
    EXPECT_TRUE(has(e, c.message)) << c.json;
  }
}

// Concentration fields (#12): each mistake names the key.
TEST(HostileScene, BadConcentrationFieldsNameTheirKey) {
  auto with = [](const std::string& field) {
    return R"({"media": {"g": {"ior": 1.5, "absorption": {"library": "red-glass", "concentration": )" + field +
           R"(}}}, "objects": []})";
  };
  const struct {
    std::string field, message;
  } cases[] = {
      {R"({"field": "linear", "value": -1, "slope_per_m": 2})",
       "s.json: media.g.absorption.concentration.value: a concentration must not be negative (got -1)"},
      {R"({"field": "linear", "axis": [0, 0, 0], "value": 1, "slope_per_m": 2})",
       "media.g.absorption.concentration.axis: must be a direction of finite, non-zero length"},
      {R"({"field": "diffusoin", "value": 1})", "media.g.absorption.concentration.field: unknown concentration field 'diffusoin' (did you mean 'diffusion'?)"},
      {R"({"field": "diffusion", "value": 1})", "needs either 'width' (w in erfc(s/w)) or 'diffusivity_m2_per_s' and 'time_s'"},
      {R"({"field": "diffusion", "value": 1, "diffusivity_m2_per_s": -1e-9, "time_s": 10})",
       "concentration.diffusivity_m2_per_s: must be positive (got -1e-09)"},
      {R"({"field": "exponential", "value": 1, "scale_length": "-2 mm"})", "concentration.scale_length: must be a positive length"},
      {R"({"field": "layers", "layers": [["10 mm", 1], ["5 mm", 2]]})",
       "concentration.layers[1][0]: layer bounds must increase (0.005 m follows 0.01 m)"},
      {R"({"field": "layers", "layers": [["10 mm", -1]]})", "concentration.layers[0][1]: a concentration must not be negative"},
      {R"({"field": "layers", "layers": []})", "concentration.layers: needs 1 to 256 layers (got 0)"},
      {R"({"field": "linear", "value": 1, "slope_per_m": 2, "colour": 3})", "concentration.colour: unknown key"},
      {R"({"field": "diffusion", "value": 1e13, "width": "1 mm"})",
       "media.g.absorption.concentration: σ_a at the field's largest concentration (1e+13) exceeds 1e+12 per metre"},
  };
  for (const auto& c : cases) EXPECT_TRUE(has(scene_error(with(c.field)), c.message)) << c.field;
  EXPECT_TRUE(has(scene_error(R"({"media": {"g": {"ior": 1.5, "absorption": []}}, "objects": []})"),
                  "media.g.absorption: needs 1 to 8 absorbers (got 0)"));
}

// Scattering media (#12): bad σ_s, phase functions and densities name their key.
TEST(HostileScene, BadScatteringNamesItsKey) {
  auto with = [](const std::string& scattering) {
    return R"({"media": {"m": {"ior": 1.33, "scattering": )" + scattering + R"(}}, "objects": []})";
  };
  const struct {
    std::string scattering, message;
  } cases[] = {
      {R"({"unit": "attenuation_per_m", "wavelength_nm": [400, 700], "value": [1, -2]})",
       "s.json: media.m.scattering.value: values must not be negative (got -2)"},
      {R"({"unit": "attenuation_per_m", "rgb": [1, -1, 0]})", "media.m.scattering.rgb[1]: σ_s must not be negative"},
      {R"({"unit": "absorbance_per_cm", "wavelength_nm": [400, 700], "value": [1, 2]})",
       "media.m.scattering.unit: unknown unit 'absorbance_per_cm'"},
      {R"({"rayleigh": {"at_nm": 550, "value_per_m": -1}})", "media.m.scattering.rayleigh.value_per_m: σ_s must not be negative (got -1)"},
      {R"({"rayleigh": {"at_nm": 5, "value_per_m": 1}})", "media.m.scattering.rayleigh.at_nm: must lie between 200 and 2000 nm (got 5)"},
      {R"({"rayleigh": {"value_per_m": 1}, "phase": {"type": "henyey_greenstein", "g": 1.0}})",
       "media.m.scattering.rayleigh: needs 'at_nm' and 'value_per_m'"},
      {R"({"rayleigh": {"at_nm": 550, "value_per_m": 1}, "phase": {"type": "henyey_greenstein", "g": 1.0}})",
       "media.m.scattering.phase.g: must lie strictly between −1 and 1 (got 1)"},
      {R"({"rayleigh": {"at_nm": 550, "value_per_m": 1}, "phase": {"type": "henyey_greenstein", "g": -1.5}})",
       "media.m.scattering.phase.g: must lie strictly between −1 and 1 (got -1.5)"},
      {R"({"rayleigh": {"at_nm": 550, "value_per_m": 1}, "phase": {"type": "rayleigh"}})",
       "media.m.scattering.phase.type: unknown phase function 'rayleigh'"},
      {R"({"rayleigh": {"at_nm": 550, "value_per_m": 1}, "density": -2})", "media.m.scattering.density: must not be negative (got -2)"},
      {R"({"rayleigh": {"at_nm": 550, "value_per_m": 1}, "density": {"field": "linear", "axis": [0, 0, 0], "value": 1, "slope_per_m": 1}})",
       "media.m.scattering.density.axis: must be a direction of finite, non-zero length"},
      {R"({"rayleigh": {"at_nm": 550, "value_per_m": 1e9}, "density": {"field": "diffusion", "value": 1e4, "width": "1 mm"}})",
       "media.m.scattering.density: σ at the density's largest value (10000) exceeds 1e+12 per metre"},
      {R"({"library": "whole_milc"})", "media.m.scattering.library: unknown scattering medium 'whole_milc' (did you mean 'whole_milk'?)"},
      {R"({"library": "whole_milk", "concentration": 0.1, "density": 2})", "give either 'concentration' (of the library medium) or 'density', not both"},
      {R"({"rayleigh": {"at_nm": 550, "value_per_m": 1}, "albedo": 0.5})", "media.m.scattering.albedo: unknown key"},
  };
  for (const auto& c : cases) EXPECT_TRUE(has(scene_error(with(c.scattering)), c.message)) << scene_error(with(c.scattering));
  // Absorption in RGB only: negative components refused; a valid one is lifted and accepted.
  EXPECT_TRUE(has(scene_error(R"({"media": {"m": {"ior": 1.33, "absorption": {"unit": "attenuation_per_m", "rgb": [1, -2, 0]}}},
      "objects": []})"),
                  "media.m.absorption.rgb[1]: must not be negative"));
  EXPECT_EQ(scene_error(R"({"media": {"m": {"ior": 1.33, "absorption": {"unit": "absorbance_per_cm", "rgb": [0.1, 0.3, 0.9]}}},
      "objects": []})"),
            "accepted");
  // A density scales the absorption, which must then have numbers for concentrations.
  EXPECT_TRUE(has(scene_error(R"({"media": {"m": {"ior": 1.33, "absorption": {"library": "red-glass", "concentration":
      {"field": "linear", "value": 1, "slope_per_m": 1}}, "scattering": {"rayleigh": {"at_nm": 550, "value_per_m": 1},
      "density": 2}}}, "objects": []})"),
                  "media.m.absorption: with a scattering 'density', the absorption's concentration must be a number"));
  // The world medium cannot scatter; Whitted cannot render a scattering medium.
  EXPECT_TRUE(has(scene_error(R"({"world_medium": "m", "media": {"m": {"ior": 1.0, "scattering": {"rayleigh": {"at_nm": 550,
      "value_per_m": 1}}}}, "objects": []})"),
                  "s.json: world_medium: 'm' scatters; the world medium cannot"));
  const std::string whitted = R"({"render": {"integrator": "whitted"},
    "media": {"m": {"ior": 1.33, "scattering": {"rayleigh": {"at_nm": 550, "value_per_m": 1}}}},
    "objects": [{"name": "ball", "shape": {"type": "sphere", "radius": "10 mm"}, "inside": "m"}]})";
  std::string message;
  try {
    RenderStats stats;
    (void)render(compile(parse_scene(whitted, "s.json")), parse_scene(whitted, "s.json").render, {}, stats, false);
  } catch (const Error& e) {
    message = e.what();
  }
  EXPECT_TRUE(has(message, "s.json: object 'ball': medium 'm' scatters; the whitted integrator renders absorption only"))
      << message;
}

// Grid fields (#12): every bad .vdb ends in one line naming the scene key and the file.
TEST(HostileScene, BadGridFilesNameTheKeyAndTheFile) {
  const fs::path dir = test::scratch_dir("hostile_grid_files");
  auto with = [](const fs::path& file, const std::string& extra = "") {
    return R"({"media": {"g": {"ior": 1.5, "absorption": {"library": "red-glass", "concentration":
        {"field": "grid", "file": ")" + file.string() + "\"" + extra + R"(}}}}, "objects": []})";
  };
  const std::string key = "s.json: media.g.absorption.concentration.";
  test::VdbTestGrid good;
  test::write_vdb_file(dir / "good.vdb", {good});
  ASSERT_EQ(scene_error(with(dir / "good.vdb")), "accepted");
  const std::string bytes = test::read_file(dir / "good.vdb");
  test::write_file(dir / "truncated.vdb", bytes.substr(0, bytes.size() / 2));
  std::string flipped = bytes;
  for (std::size_t i = 16; i < flipped.size(); i += 7) flipped[i] = static_cast<char>(flipped[i] ^ 0x5a);
  test::write_file(dir / "corrupt.vdb", flipped);
  test::write_file(dir / "text.vdb", "not a voxel grid\n");
  { std::ofstream(dir / "huge.vdb").close(); fs::resize_file(dir / "huge.vdb", std::uintmax_t{3} << 30); }  // sparse
  test::VdbTestGrid named = good, vec3 = good, negative = good, nan = good, background = good, empty = good;
  named.name = "temperature";
  vec3.vec3 = true;
  negative.value = [](const Vec3& x) { return x.x > 0.0015 ? -0.5 : 1.0; };
  nan.value = [](const Vec3& x) { return x.z > 0.0025 ? std::nan("") : 1.0; };
  background.background = 0.25f;
  empty.count = {0, 0, 0};
  test::write_vdb_file(dir / "names.vdb", {named});
  test::write_vdb_file(dir / "vec3.vdb", {vec3});
  test::write_vdb_file(dir / "negative.vdb", {negative});
  test::write_vdb_file(dir / "nan.vdb", {nan});
  test::write_vdb_file(dir / "background.vdb", {background});
  test::write_vdb_file(dir / "empty.vdb", {empty});
  const struct {
    std::string file, extra, message;
  } cases[] = {
      {"missing.vdb", "", "file: " + (dir / "missing.vdb").string() + ": file not found"},
      {"text.vdb", "", "file: " + (dir / "text.vdb").string() + ": not an OpenVDB file"},
      {"huge.vdb", "", "file: " + (dir / "huge.vdb").string() + ": the file has 3072.0 MiB, more than"},
      {"truncated.vdb", "", "file: " + (dir / "truncated.vdb").string() + ": OpenVDB cannot read it"},
      {"names.vdb", "", "grid: " + (dir / "names.vdb").string() + ": no grid named 'density' (the file has: temperature)"},
      {"vec3.vdb", "", "grid: " + (dir / "vec3.vdb").string() + ": grid 'density': holds vec3s values; a concentration grid holds floats"},
      {"negative.vdb", "", "grid: " + (dir / "negative.vdb").string() + ": grid 'density': voxel (2, 0, 0) is negative (-0.5)"},
      {"nan.vdb", "", "grid: " + (dir / "nan.vdb").string() + ": grid 'density': voxel (0, 0, 3) is nan"},
      {"background.vdb", "", "grid 'density': its background is 0.25; the field is zero outside"},
      {"empty.vdb", "", "grid: " + (dir / "empty.vdb").string() + ": grid 'density': the grid has no active voxels"},
      {"good.vdb", R"(, "scale": -1)", key + "scale: must not be negative (got -1)"},
      {"good.vdb", R"(, "grid": 3)", key + "grid: expected a string, found number"},
      {"good.vdb", R"(, "origin": [0, 0, 0])", key + "origin: unknown key"},
      {"good.vdb", R"(, "transform": [{"scale": 1e10}])", "grid: " + (dir / "good.vdb").string() + ": the grid reaches ("},
      {"good.vdb", R"(, "scale": 1e13)", key.substr(0, key.size() - 1) + ": σ_a at the field's largest concentration (1e+13)"},
  };
  for (const auto& c : cases) {
    const std::string e = scene_error(with(dir / c.file, c.extra));
    EXPECT_TRUE(has(e, c.message)) << c.file << c.extra;
    EXPECT_TRUE(has(e, "s.json: media.g.absorption.concentration")) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
  // Damaged bytes: refused with an Error on the file key (what OpenVDB makes of them varies).
  EXPECT_TRUE(has(scene_error(with(dir / "corrupt.vdb")), key)) << scene_error(with(dir / "corrupt.vdb"));
}

TEST(HostileScene, AGridTooLargeForItsLimitsOrMemoryIsRefusedBeforeItIsCopied) {
  const fs::path dir = test::scratch_dir("hostile_grid_memory");
  auto with = [](const fs::path& file) {
    return R"({"media": {"g": {"ior": 1.5, "absorption": {"library": "red-glass", "concentration":
        {"field": "grid", "file": ")" + file.string() + R"("}}}}, "objects": []})";
  };
  // Two voxels 2000 apart: 8·10⁹ nodes in the dense copy of their bounding box.
  test::VdbTestGrid far;
  far.count = {1, 1, 1};
  far.more = {{1999, 1999, 1999}};
  test::write_vdb_file(dir / "far.vdb", {far});
  EXPECT_TRUE(has(scene_error(with(dir / "far.vdb")), "concentration.grid: " + (dir / "far.vdb").string() +
                  ": grid 'density': its active voxels span 2002×2002×2002 voxels with the border, more than 268435456"));
  // 600 apart: 218 million nodes, within the limit, but 832 MiB as floats.
  far.more = {{599, 599, 599}};
  test::write_vdb_file(dir / "wide.vdb", {far});
  const std::string outcome =
      test::run_with_memory_budget([&] { (void)parse_scene(with(dir / "wide.vdb"), "s.json"); }, std::size_t{256} << 20);
  EXPECT_TRUE(has(outcome, "error: s.json: media.g.absorption.concentration.grid: ")) << outcome;
  EXPECT_TRUE(has(outcome, "grid 'density' needs about 832 MiB of memory; ")) << outcome;
}

TEST(HostileScene, ARenderTooLargeForMemoryIsRefusedBeforeItAllocates) {
  // 16384 x 16384 is within the resolution limit; its film takes about 20 GiB.
  const std::string outcome = test::run_with_memory_budget(
      [] {
        SceneDesc desc = parse_scene(scene(), "s.json");
        desc.camera.width_px = desc.camera.height_px = 16384;
        const RenderScene s = compile(desc);
        (void)make_film(s, false);
      },
      std::size_t{1} << 30);
  EXPECT_TRUE(has(outcome, "error: s.json: a 16384x16384 image needs about 20.0 GiB of memory; ")) << outcome;
  EXPECT_TRUE(has(outcome, " is available")) << outcome;

  // 20 000 tessellated spheres in a 2 MB scene: 184 million triangles, refused before most are
  // made (analytic spheres, the default, keep no triangles).
  std::string many = R"({"media": {"g": {"ior": 1.5}}, "objects": [)";
  for (int i = 0; i < 20000; ++i)
    many += fmt::format(R"({}{{"shape": {{"type": "sphere", "radius": "1 mm", "tessellate": true}}, "inside": "g", "transform": [{{"translate": [{}, 0, 0]}}]}})",
                        i ? "," : "", 0.003 * i);
  many += "]}";
  const std::string spheres = test::run_with_memory_budget([&] { (void)compile(parse_scene(many, "s.json")); },
                                                           std::size_t{512} << 20);
  EXPECT_TRUE(has(spheres, "error: s.json: object 'object ")) << spheres;
  EXPECT_TRUE(has(spheres, " triangles) needs about ")) << spheres;
  EXPECT_TRUE(has(spheres, " of memory; ")) << spheres;
}

TEST(HostileScene, VcmLightSubpathsBeyondTheMemoryAreRefusedBeforeTheyGrow) {
  // vcm keeps every pixel's light subpath for its iteration, 2 kB a vertex in full spectrum: at
  // 1024 x 1024 about 3 GB where the lamp's light subpaths mostly end on the floor, in a budget of
  // 384 MiB (the film's 80 MiB fits). One thread, so that no other thread allocates between the
  // check and the array's growth. A missing check ends in std::bad_alloc instead.
  const std::string outcome = test::run_with_memory_budget(
      [] {
        SceneDesc desc = parse_scene(scene(), "s.json");
        desc.camera.width_px = desc.camera.height_px = 1024;
        desc.render.integrator = IntegratorType::vcm;
        desc.render.spectral = SpectralMode::full;
        const RenderScene s = compile(desc);
        FilmBuffer film = make_film(s, false);
        RenderControl control;
        control.threads = 1;
        RenderStats stats;
        render_into(s, desc.render, film, PixelRegion::whole(s.camera), {0, 1}, control, stats);
      },
      std::size_t{384} << 20);
  EXPECT_TRUE(has(outcome, "error: s.json: the store of light subpaths of iteration 1 (past ")) << outcome;
  EXPECT_TRUE(has(outcome, " of them) needs about ")) << outcome;
  EXPECT_TRUE(has(outcome, " is available")) << outcome;
}

TEST(HostileScene, NonFinitePixelsAreCountedWithTheFirst) {
  Film film(4, 3, {500.0});
  EXPECT_EQ(find_non_finite(film).count, 0u);
  film.set_rgb(2, 1, {0.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f});
  film.spectrum_at(3, 2)[0] = std::numeric_limits<float>::infinity();
  const NonFinitePixels bad = find_non_finite(film);
  EXPECT_EQ(bad.count, 2u);
  EXPECT_EQ(bad.first_x, 2);
  EXPECT_EQ(bad.first_y, 1);
}

// The command line: exit 1 with one line naming the file, and keep.png as the good render left it.
TEST(HostileCli, RefusedScenesLeaveTheEarlierOutputByteIdentical) {
  const fs::path dir = test::scratch_dir("hostile_cli_scenes");
  test::write_file(dir / "good.json", scene());
  const std::string keep = (dir / "keep.png").string();
  ASSERT_EQ(test::run_bouguer({"render", (dir / "good.json").string(), "-o", keep, "--quiet"}).exit_code, 0);
  const std::string before = test::read_file(keep);
  const struct {
    std::string name, json, message;
  } cases[] = {
      {"radius.json", scene("1e308"), "radius.json: objects[0].shape.radius: 1e+308 m is beyond the scene's extent"},
      {"overflow.json", scene("1e999"), "overflow.json:6:60: the number 1e999 is beyond the range of a double"},
      {"scale.json", scene("\"20 mm\"", "1e308"), "scale.json: objects[1].emission: the emitted radiance reaches"},
      {"duplicate.json", "{\"objects\": [], \"objects\": []}", "duplicate.json:1:17: (top level): duplicate key 'objects'"},
  };
  for (const auto& c : cases) {
    test::write_file(dir / c.name, c.json);
    const auto r = test::run_bouguer({"render", (dir / c.name).string(), "-o", keep});
    EXPECT_EQ(r.exit_code, 1) << c.name;
    EXPECT_TRUE(has(r.err, "bouguer: error: ")) << r.err;
    EXPECT_TRUE(has(r.err, c.message)) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(has(r.err, "internal error"));
    EXPECT_EQ(test::read_file(keep), before) << c.name;
  }
}

TEST(HostileCli, ToolsExitNonZeroRatherThanPrintNan) {
  const auto color = test::run_bouguer({"color", "D65", "--scale", "1e308"});
  EXPECT_EQ(color.exit_code, 2);
  EXPECT_TRUE(has(color.err, "--scale: must be a finite number from 0 to 1e+12, got 1e308")) << color.err;
  EXPECT_EQ(color.out, "");

  const auto water = test::run_bouguer({"material", "water", "--concentration", "1e308"});
  EXPECT_EQ(water.exit_code, 2);
  EXPECT_TRUE(has(water.err, "--concentration: must be a finite number from 0 to 1e+12, got 1e308")) << water.err;
  const auto glass = test::run_bouguer({"material", "red-glass", "--concentration", "1e11"});
  EXPECT_EQ(glass.exit_code, 1);
  EXPECT_TRUE(has(glass.err, "red-glass: σ_a (per metre) at this concentration reaches")) << glass.err;
  EXPECT_EQ(glass.out.find("nan"), std::string::npos);

  const fs::path dir = test::scratch_dir("hostile_cli_compare");
  const auto pfm = [](float a, float b) {
    std::string bytes = "PF\n2 1\n-1.0\n";
    const float values[6] = {0.5f, 0.5f, 0.5f, a, b, 0.0f};
    bytes.append(reinterpret_cast<const char*>(values), sizeof values);
    return bytes;
  };
  test::write_file(dir / "ok.pfm", pfm(0.5f, 0.5f));
  test::write_file(dir / "nan.pfm", pfm(std::numeric_limits<float>::quiet_NaN(), 0.0f));
  test::write_file(dir / "inf.pfm", pfm(0.0f, std::numeric_limits<float>::infinity()));
  for (const char* bad : {"nan.pfm", "inf.pfm"}) {
    const auto r = test::run_bouguer({"compare", (dir / bad).string(), (dir / "ok.pfm").string(), "--json"});
    EXPECT_EQ(r.exit_code, 1) << bad;
    EXPECT_TRUE(has(r.err, std::string(bad) + ": pixel (1, 0) holds ")) << r.err;
    EXPECT_TRUE(has(r.err, ", not a finite number")) << r.err;
    EXPECT_EQ(r.out, "");
  }
}

}  // namespace
}  // namespace bouguer
