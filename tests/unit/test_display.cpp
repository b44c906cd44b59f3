// Exposure, white balance and the display curve (io/display.h): each relation in closed form,
// the defaults that leave every image bit for bit as it was, the builder's one check for the scene
// file and the command line, and a Blender-like glTF (27 000 cd point light) rendered as issue #35
// asks: the lit floor neither clipped nor dark, +1 EV doubling the PNG's linear values and
// leaving the EXR alone.
#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "bouguer/io/display.h"
#include "bouguer/io/image_io.h"
#include "bouguer/scene/builder.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/display_white.h"
#include "bouguer/scene/loader.h"
#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/color_space.h"
#include "support/gltf_files.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;
using nlohmann::json;

// ---- closed forms ------------------------------------------------------------------------------

TEST(Display, Ev100AndTheCameraScaleFollowTheSaturationBasedRelation) {
  // ISO 100, 1 s, f/1: EV100 = 0, so luminance 1.2 cd/m² is display white.
  EXPECT_DOUBLE_EQ(ev100({100.0, 1.0, 1.0}), 0.0);
  EXPECT_DOUBLE_EQ(camera_exposure_scale({100.0, 1.0, 1.0}), 1.0 / 1.2);
  // "Sunny 16": f/16, 1/100 s, ISO 100: EV100 = log2(256·100) = 14.64.
  const CameraExposure sunny{100.0, 0.01, 16.0};
  EXPECT_NEAR(ev100(sunny), std::log2(25600.0), 1e-12);
  // 1/(1.2·2^EV100) = t·S/(120·N²): pbrt-v4's imagingRatio t·S/100 over 1.2·N².
  for (const CameraExposure c : {sunny, CameraExposure{400.0, 1.0 / 60, 2.8}, CameraExposure{3200.0, 2.0, 1.4}}) {
    const double pbrt_imaging_ratio = c.shutter_s * c.iso / 100.0;
    EXPECT_NEAR(camera_exposure_scale(c), pbrt_imaging_ratio / (1.2 * c.f_number * c.f_number),
                1e-14 * camera_exposure_scale(c));
  }
  // One stop more light (twice the time, twice the ISO, or N/√2) doubles the scale.
  EXPECT_NEAR(camera_exposure_scale({200.0, 0.01, 16.0}) / camera_exposure_scale(sunny), 2.0, 1e-12);
  EXPECT_NEAR(camera_exposure_scale({100.0, 0.01, 16.0 / std::numbers::sqrt2}) / camera_exposure_scale(sunny), 2.0,
              1e-12);
  EXPECT_EQ(compensation_scale(1.0), 2.0);
  EXPECT_EQ(compensation_scale(-2.0), 0.25);
  EXPECT_EQ(compensation_scale(0.0), 1.0);
}

// A grey film whose pixels have luminance `values` (grey rgb has Y = the value).
Film grey_film(const std::vector<float>& values) {
  Film f(static_cast<int>(values.size()), 1);
  for (std::size_t i = 0; i < values.size(); ++i) f.set_rgb(static_cast<int>(i), 0, {values[i], values[i], values[i]});
  return f;
}

TEST(Display, AutoExposurePutsThe97thPercentileOfLitPixelsAt0Point8) {
  std::vector<float> values(200, 0.0f);  // 100 black pixels (not counted), then luminance 1..100
  for (int i = 0; i < 100; ++i) values[static_cast<std::size_t>(100 + i)] = static_cast<float>(i + 1);
  const Film film = grey_film(values);
  EXPECT_NEAR(auto_exposure_scale(film.rgb), 0.8 / 97.0, 1e-12);
  // The order of the pixels does not matter; a black film is left as it is.
  std::reverse(values.begin(), values.end());
  EXPECT_NEAR(auto_exposure_scale(grey_film(values).rgb), 0.8 / 97.0, 1e-12);
  EXPECT_EQ(auto_exposure_scale(grey_film({0.0f, 0.0f}).rgb), 1.0);
  // Three pixels in a hundred (a lamp seen directly, fireflies) do not move it.
  for (int i = 0; i < 3; ++i) values[static_cast<std::size_t>(i)] = 1e6f;
  std::vector<float> lamp(values);
  lamp.erase(std::remove(lamp.begin(), lamp.end(), 100.0f), lamp.end());
  lamp.erase(std::remove(lamp.begin(), lamp.end(), 99.0f), lamp.end());
  lamp.erase(std::remove(lamp.begin(), lamp.end(), 98.0f), lamp.end());
  EXPECT_NEAR(auto_exposure_scale(grey_film(lamp).rgb), 0.8 / 97.0, 1e-12);
}

TEST(Display, WhiteBalanceMapsTheSourceWhiteToD65AndKeepsNeutralsNeutral) {
  const Mat3 to_rgb = xyz_to_rgb_matrix(kRec709);
  for (const char* name : {"A", "D50", "F11", "blackbody:3200"}) {
    const Vec3 white = spectrum_to_xyz(named_illuminant(name, 1.0));
    const Mat3 m = white_balance_matrix(white);
    // The source white, at any luminance, becomes the display white (1, 1, 1) at that luminance.
    for (const double y : {1.0, 0.3, 250.0}) {
      const Vec3 out = m * (to_rgb * (white * y));
      EXPECT_NEAR(out.x, y, 1e-12 * y) << name;
      EXPECT_NEAR(out.y, y, 1e-12 * y) << name;
      EXPECT_NEAR(out.z, y, 1e-12 * y) << name;
    }
  }
  // Balancing to the display's own white changes nothing: a neutral stays neutral.
  const Mat3 same = white_balance_matrix(xy_to_xyz(kD65White.x, kD65White.y));
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(same.m[i][j], i == j ? 1.0 : 0.0, 1e-12);
  const Vec3 grey = same * Vec3{0.18, 0.18, 0.18};
  EXPECT_NEAR(grey.x, 0.18, 1e-13);
  EXPECT_NEAR(grey.z, 0.18, 1e-13);
  // Under A (warm), a colour that looked white in the scene is bluer than it was on the film.
  const Vec3 a = white_balance_matrix(spectrum_to_xyz(named_illuminant("A"))) * Vec3{1, 1, 1};
  EXPECT_GT(a.z, a.x);
}

TEST(Display, FilmicCurveIsMonotoneMapsZeroToZeroAndKeepsHue) {
  EXPECT_EQ(filmic_shoulder(0.0), 0.0);
  EXPECT_EQ(filmic_shoulder(0.3), 0.3);  // below the knee: the identity, exposure keeps its meaning
  double previous = -1.0;
  for (double x = 0.0; x < 200.0; x += 0.01) {
    const double f = filmic_shoulder(x);
    if (x < 10.0)
      EXPECT_GT(f, previous) << x;  // increasing (until 1 − f is below double precision, near x = 15)
    else
      EXPECT_GE(f, previous) << x;
    EXPECT_LE(f, 1.0) << x;  // never above white
    previous = f;
  }
  EXPECT_LT(filmic_shoulder(10.0), 1.0);
  // Continuous with slope 1 at the knee (no kink in a gradient).
  const double h = 1e-6;
  EXPECT_NEAR(filmic_shoulder(kFilmicKnee + h), kFilmicKnee + h, 1e-11);
  EXPECT_NEAR((filmic_shoulder(kFilmicKnee + h) - filmic_shoulder(kFilmicKnee)) / h, 1.0, 1e-5);
  // Hue: every channel scaled by the same factor, the largest below 1.
  for (const Vec3 c : {Vec3{4.0, 2.0, 0.5}, Vec3{0.9, 0.1, 0.7}, Vec3{30.0, 30.0, 29.0}, Vec3{0.2, 0.5, 0.1}}) {
    const Vec3 f = filmic(c);
    EXPECT_NEAR(f.x / f.y, c.x / c.y, 1e-12);
    EXPECT_NEAR(f.z / f.y, c.z / c.y, 1e-12);
    EXPECT_LE(std::max({f.x, f.y, f.z}), 1.0);
  }
  EXPECT_EQ(filmic(Vec3{0.2, 0.5, 0.1}).y, 0.5);
}

TEST(Display, ResolveMultipliesCameraAndCompensationAndDefaultsToNothing) {
  const Film film = grey_film({0.0f, 2.0f, 4.0f});
  const DisplayTransform none = resolve_display(DisplayDesc{}, film);
  EXPECT_TRUE(none.leaves_png());
  EXPECT_TRUE(none.leaves_floats());
  DisplayDesc d;
  d.exposure_ev = 1.0;
  d.camera = CameraExposure{100.0, 1.0, 1.0};
  d.auto_exposure = true;  // the camera's exposure wins
  EXPECT_DOUBLE_EQ(resolve_display(d, film).scale, 2.0 / 1.2);
  d.camera.reset();
  EXPECT_DOUBLE_EQ(resolve_display(d, film).scale, 2.0 * 0.8 / 4.0);
  // Exposure reaches the float formats only when asked, and then their spectra too.
  Film spectral(1, 1, {500.0, 600.0});
  spectral.set_rgb(0, 0, {1.0f, 1.0f, 1.0f});
  spectral.spectral = {1.0f, 3.0f};
  DisplayTransform t;
  t.scale = 4.0;
  EXPECT_EQ(exposed(spectral, t).rgb, spectral.rgb);
  t.float_outputs = true;
  EXPECT_EQ(exposed(spectral, t).spectral, (std::vector<float>{4.0f, 12.0f}));
  EXPECT_EQ(exposed(spectral, t).rgb_at(0, 0).y, 4.0f);
}

TEST(Display, TheDefaultTransformWritesEveryFormatBitForBitAsBefore) {
  const fs::path dir = test::scratch_dir("display_identity");
  Film film(5, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 5; ++x) {
      const float fx = static_cast<float>(x), fy = static_cast<float>(y);
      film.set_rgb(x, y, {0.37f * fx, 1.5f * fy - 0.2f, 0.01f * fx * fy});
    }
  const DisplayTransform t = resolve_display(DisplayDesc{}, film);
  for (const char* ext : {".png", ".exr", ".pfm"}) {
    write_image(dir / (std::string("a") + ext), film);
    write_image(dir / (std::string("b") + ext), film, t);
    EXPECT_EQ(test::read_file(dir / (std::string("a") + ext)), test::read_file(dir / (std::string("b") + ext))) << ext;
  }
  EXPECT_EQ(encode_png(displayed(film, t)), encode_png(film));
}

// ---- the scene file and the command line --------------------------------------------------------

TEST(Display, SceneKeysAndTheCommandLinePassOneCheck) {
  const fs::path dir = test::scratch_dir("display_keys");
  const auto scene = [&](const std::string& display) {
    test::write_file(dir / "s.json", R"({"camera": {"resolution": [4, 3]}, "display": )" + display +
                                         R"(, "objects": [{"shape": {"type": "sphere", "radius": 0.1},
                                         "material": {"type": "diffuse", "reflectance": 0.5}}]})");
    return dir / "s.json";
  };
  const SceneDesc d = load_scene(scene(R"({"exposure_ev": -1.5, "white_balance": "A", "curve": "filmic",
                                          "expose_float_outputs": true,
                                          "camera_exposure": {"iso": 400, "shutter_s": 0.02, "f_number": 4}})"));
  EXPECT_EQ(d.display.exposure_ev, -1.5);
  EXPECT_EQ(d.display.curve, DisplayCurve::filmic);
  EXPECT_TRUE(d.display.float_outputs);
  ASSERT_TRUE(d.display.camera);
  EXPECT_EQ(d.display.camera->f_number, 4.0);
  ASSERT_TRUE(std::holds_alternative<IlluminantWhite>(d.display.white_balance));
  // A JSON scene has no automatic exposure unless it asks.
  EXPECT_FALSE(load_scene(scene("{}")).display.auto_exposure);
  // The same bad value from the file and from the command line: one check, one message.
  const auto from_file = test::run_bouguer(
      {"render", scene(R"({"exposure_ev": 40})").string(), "-o", (dir / "x.png").string(), "--quiet"});
  EXPECT_EQ(from_file.exit_code, 1);
  EXPECT_NE(from_file.err.find("s.json: display.exposure_ev: must be between -32 and 32 EV (got 40)"),
            std::string::npos)
      << from_file.err;
  const auto from_cli = test::run_bouguer(
      {"render", scene("{}").string(), "-o", (dir / "x.png").string(), "--exposure", "40", "--quiet"});
  EXPECT_EQ(from_cli.exit_code, 2);
  EXPECT_NE(from_cli.err.find("--exposure: must be between -32 and 32 EV (got 40)"), std::string::npos) << from_cli.err;
  const auto white = test::run_bouguer(
      {"render", scene(R"({"white_balance": "D56"})").string(), "-o", (dir / "x.png").string(), "--quiet"});
  EXPECT_NE(white.err.find("display.white_balance: unknown white 'D56' (did you mean"), std::string::npos) << white.err;
  const auto curve = test::run_bouguer(
      {"render", scene("{}").string(), "-o", (dir / "x.png").string(), "--display", "filmc", "--quiet"});
  EXPECT_NE(curve.err.find("--display: unknown display curve 'filmc' (did you mean 'filmic'?)"), std::string::npos)
      << curve.err;
  const auto partial =
      test::run_bouguer({"render", scene("{}").string(), "-o", (dir / "x.png").string(), "--iso", "100", "--quiet"});
  EXPECT_EQ(partial.exit_code, 2);
  EXPECT_NE(partial.err.find("give all three"), std::string::npos) << partial.err;
  const auto both = test::run_bouguer({"render",
                                       scene(R"({"auto_exposure": true,
      "camera_exposure": {"iso": 100, "shutter_s": 1, "f_number": 1}})")
                                           .string(),
                                       "-o", (dir / "x.png").string(), "--quiet"});
  EXPECT_NE(both.err.find("display.camera_exposure: excludes 'auto_exposure'"), std::string::npos) << both.err;
  const auto shutter = test::run_bouguer(
      {"render", scene(R"({"camera_exposure": {"iso": 100, "shutter_s": 0, "f_number": 1}})").string(), "-o",
       (dir / "x.png").string(), "--quiet"});
  EXPECT_NE(shutter.err.find("display.camera_exposure: the shutter time (s) must be a positive number"),
            std::string::npos)
      << shutter.err;
}

// The 8-bit sRGB pixels of a PNG file.
std::vector<unsigned char> png_pixels(const fs::path& path, int& width) {
  png_image image{};
  image.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&image, path.c_str())) return {};
  image.format = PNG_FORMAT_RGB;
  std::vector<unsigned char> px(PNG_IMAGE_SIZE(image));
  if (!png_image_finish_read(&image, nullptr, px.data(), 0, nullptr)) return {};
  width = static_cast<int>(image.width);
  return px;
}

TEST(Display, JsonScenesWriteTheLinearFilmClippedAsBefore) {
  // The PNG `bouguer render` writes by default is the EXR of the same run, clipped and encoded.
  const fs::path dir = test::scratch_dir("display_json_default");
  const std::string scene = (fs::path(BOUGUER_SOURCE_DIR) / "scenes" / "examples" / "issue3.json").string();
  const auto r = test::run_bouguer({"render", scene, "--resolution", "24x18", "--spp", "1", "-o",
                                    (dir / "a.png").string(), "-o", (dir / "a.exr").string(), "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(test::read_file(dir / "a.png"), encode_png(read_exr(dir / "a.exr")));
}

// ---- the Blender-like asset of issue #35 ---------------------------------------------------------

constexpr double kCandela = 27176.0;  // Blender's 500 W point light through its exporter's 683 lm/W / 4π
constexpr double kLightHeightM = 4.0, kFloorAlbedo = 0.8;

// A UV sphere of radius r centred at c: `rings` bands of `segments` quads, faces outward.
void uv_sphere(double r, const Vec3& c, int rings, int segments, std::vector<Vec3>& p,
               std::vector<std::uint32_t>& idx) {
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j <= segments; ++j) {
      const double theta = std::numbers::pi * i / rings, phi = 2 * std::numbers::pi * j / segments;
      p.push_back(c + Vec3{std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi)} * r);
    }
  const auto at = [&](int i, int j) { return static_cast<std::uint32_t>(i * (segments + 1) + j); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j)
      idx.insert(idx.end(), {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j), at(i + 1, j + 1), at(i, j + 1)});
}

// An 8 m grey floor, a glass ball on it (Principled BSDF with Transmission 1 as Blender's exporter
// writes it: KHR_materials_transmission without a volume, a thin-walled sheet) and a point light
// 4 m above, seen by the asset's camera from 5 m away and 2 m up.
fs::path blender_like_asset(const fs::path& dir) {
  test::GltfDoc g;
  const int floor = g.material({{"pbrMetallicRoughness",
                                 {{"baseColorFactor", {kFloorAlbedo, kFloorAlbedo, kFloorAlbedo, 1.0}},
                                  {"metallicFactor", 0.0},
                                  {"roughnessFactor", 1.0}}}});
  const int glass = g.material({{"name", "Glass"},
                                {"pbrMetallicRoughness", {{"metallicFactor", 0.0}, {"roughnessFactor", 0.0}}},
                                {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}}}});
  g.node({{"name", "floor"},
          {"mesh", g.mesh({{-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}}, {0, 1, 2, 0, 2, 3}, floor)}});
  std::vector<Vec3> ball;
  std::vector<std::uint32_t> ball_indices;
  uv_sphere(0.4, {0.6, 0.4, 0.6}, 12, 24, ball, ball_indices);
  g.node({{"name", "ball"}, {"mesh", g.mesh(ball, ball_indices, glass)}});
  const double pitch = -std::atan2(2.0, 5.0);  // looking at the origin
  g.doc["cameras"] = {
      {{"type", "perspective"}, {"perspective", {{"yfov", 0.7}, {"aspectRatio", 1.5}, {"znear", 0.1}}}}};
  g.node({{"camera", 0}, {"translation", {0, 2, 5}}, {"rotation", {std::sin(pitch / 2), 0, 0, std::cos(pitch / 2)}}});
  g.doc["extensionsUsed"] = {"KHR_lights_punctual", "KHR_materials_transmission"};
  g.doc["extensions"] = {{"KHR_lights_punctual", {{"lights", {{{"type", "point"}, {"intensity", kCandela}}}}}}};
  g.node({{"translation", {0, kLightHeightM, 0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  g.write(dir / "blender.glb");
  return dir / "blender.glb";
}

TEST(Display, ABlenderLikeAssetIsExposedAutomaticallyAndPlusOneEvDoublesThePng) {
  const fs::path dir = test::scratch_dir("display_blender");
  const fs::path asset = blender_like_asset(dir);
  EXPECT_TRUE(load_scene(asset).display.auto_exposure);  // on for assets
  const auto render = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"render",       asset.string(),
                                     "--resolution", "48x32",
                                     "--spp",        "4",
                                     "--spectral",   "rgb3",
                                     "-o",           (dir / (name + ".png")).string(),
                                     "-o",           (dir / (name + ".exr")).string(),
                                     "--stats-json", (dir / (name + ".json")).string(),
                                     "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = test::run_bouguer(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
  };
  render("auto", {});
  render("one_thread", {"--threads", "1"});
  render("plus1", {"--exposure", "1"});
  render("off", {"--auto-exposure", "off"});
  const Film exr = read_exr(dir / "auto.exr");
  // The exposure is measured on the finished film: the same at any thread count, byte for byte.
  EXPECT_EQ(test::read_file(dir / "auto.png"), test::read_file(dir / "one_thread.png"));
  // The EXR is the linear film, whatever the exposure: the same bytes with +1 EV or without any.
  EXPECT_EQ(test::read_file(dir / "auto.exr"), test::read_file(dir / "plus1.exr"));
  EXPECT_EQ(test::read_file(dir / "auto.exr"), test::read_file(dir / "off.exr"));
  const double auto_scale = json::parse(test::read_file(dir / "auto.json"))["exposure_scale"].get<double>();
  EXPECT_EQ(json::parse(test::read_file(dir / "plus1.json"))["exposure_scale"].get<double>(), 2.0 * auto_scale);
  EXPECT_EQ(json::parse(test::read_file(dir / "off.json"))["exposure_scale"].get<double>(), 1.0);
  // Asked, the EXR gets the exposure too (the same scale, in float).
  render("floats", {"--expose-float-outputs"});
  const Film exposed_exr = read_exr(dir / "floats.exr");
  ASSERT_EQ(exposed_exr.rgb.size(), exr.rgb.size());
  for (std::size_t i = 0; i < exr.rgb.size(); i += 97)
    EXPECT_EQ(exposed_exr.rgb[i], static_cast<float>(static_cast<double>(exr.rgb[i]) * auto_scale)) << i;

  // The lit floor: the pixels whose radiance is at least a quarter of the floor's peak under the
  // light, ρ·I/(π·h²) ≈ 430 cd/m². Without exposure they are white (clipped); with it, neither
  // clipped nor below 10 % grey.
  const double peak = kFloorAlbedo * kCandela / (std::numbers::pi * kLightHeightM * kLightHeightM);
  int width = 0;
  const std::vector<unsigned char> shown = png_pixels(dir / "auto.png", width),
                                   raw = png_pixels(dir / "off.png", width),
                                   doubled = png_pixels(dir / "plus1.png", width);
  ASSERT_EQ(shown.size(), exr.rgb.size());
  int lit = 0, compared = 0;
  for (int y = 0; y < exr.height; ++y)
    for (int x = 0; x < exr.width; ++x) {
      const Vec3f c = exr.rgb_at(x, y);
      const double luminance = 0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z;
      const std::size_t i = 3 * exr.pixel_index(x, y);
      if (luminance >= 0.25 * peak) {
        ++lit;
        EXPECT_EQ(raw[i + 1], 255) << "without exposure the lit floor is white at " << x << "," << y;
        for (int k = 0; k < 3; ++k) {
          EXPECT_LT(shown[i + k], 255) << "clipped at " << x << "," << y;
          EXPECT_GE(srgb_decode(shown[i + k] / 255.0), 0.1) << "darker than 10 % grey at " << x << "," << y;
        }
      }
      // +1 EV: each 8-bit value decodes to an interval of linear values; twice the first interval
      // must meet the second, wherever neither clips nor sits in the first codes.
      for (int k = 0; k < 3; ++k) {
        const int a = shown[i + k], b = doubled[i + k];
        if (a < 8 || b == 255) continue;
        ++compared;
        const double lo = 2 * srgb_decode((a - 0.5) / 255.0), hi = 2 * srgb_decode((a + 0.5) / 255.0);
        EXPECT_TRUE(srgb_decode((b + 0.5) / 255.0) >= lo && srgb_decode((b - 0.5) / 255.0) <= hi)
            << a << " -> " << b << " at " << x << "," << y;
      }
    }
  EXPECT_GT(lit, 40);  // the pool of light under the lamp is there to look at
  EXPECT_GT(compared, 300);
}

TEST(Display, WhiteBalanceToTheBrightestEmitterNeutralisesItsColour) {
  // A warm (illuminant A) point light on a white floor: balanced to the brightest emitter, the floor is neutral.
  const fs::path dir = test::scratch_dir("display_emitter_white");
  test::write_file(dir / "a.json", R"({
    "camera": {"position": [0, 1, 0.001], "look_at": [0, 0, 0], "fov_deg": 30, "resolution": [6, 4]},
    "render": {"integrator": "path", "spectral": "full", "spp": 2},
    "display": {"white_balance": "brightest_emitter"},
    "objects": [{"shape": {"type": "quad", "size": [4, 4]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
                 "material": {"type": "diffuse", "reflectance": 0.7}}],
    "lights": [{"type": "point", "position": [0, 2, 0], "spectrum": "A", "scale": 1.0},
               {"type": "point", "position": [3, 2, 0], "spectrum": "F11", "scale": 0.01}]
  })");
  const SceneDesc desc = load_scene(dir / "a.json");
  const RenderScene scene = compile(desc);
  const std::optional<Vec3> white = brightest_emitter_white_xyz(scene);
  ASSERT_TRUE(white);
  const Vec3 a = spectrum_to_xyz(named_illuminant("A"));
  EXPECT_NEAR(white->x, a.x, 1e-12);
  EXPECT_NEAR(white->z, a.z, 1e-12);
  Film film(1, 1);
  const Vec3 under_a = xyz_to_rgb_matrix(kRec709) * (a * 0.3);  // a white surface under A on the film
  film.set_rgb(0, 0, {static_cast<float>(under_a.x), static_cast<float>(under_a.y), static_cast<float>(under_a.z)});
  const Vec3f shown = displayed(film, display_transform(scene, desc.display, film)).rgb_at(0, 0);
  EXPECT_NEAR(shown.x, 0.3, 1e-6);
  EXPECT_NEAR(shown.y, 0.3, 1e-6);
  EXPECT_NEAR(shown.z, 0.3, 1e-6);

  // An emitting quad of luminance 6 has power π·6 per m²: each of its two triangles (3π) is below the
  // point light's 4π, the quad (6π) above it, and the quad is the brightest emitter.
  test::write_file(dir / "b.json", R"({
    "objects": [{"shape": {"type": "quad", "size": [4, 4]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
                 "material": {"type": "diffuse", "reflectance": 0.7}},
                {"shape": {"type": "quad", "size": [1, 1]}, "transform": [{"translate": [0, 0.5, -3]}],
                 "emission": {"spectrum": "F11", "scale": 6}}],
    "lights": [{"type": "point", "position": [0, 2, 0], "spectrum": "A", "scale": 1.0}]
  })");
  const std::optional<Vec3> quad = brightest_emitter_white_xyz(compile(load_scene(dir / "b.json")));
  ASSERT_TRUE(quad);
  const Vec3 f11 = spectrum_to_xyz(named_illuminant("F11"));
  EXPECT_NEAR(quad->x, f11.x, 1e-9);
  EXPECT_NEAR(quad->z, f11.z, 1e-9);

  // An environment map of one colour: its white is that colour.
  Film sky(8, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) sky.set_rgb(x, y, {1.0f, 0.5f, 0.25f});
  write_exr(dir / "sky.exr", sky);
  test::write_file(dir / "c.json", R"({"background": {"environment": "sky.exr"},
    "objects": [{"shape": {"type": "quad", "size": [4, 4]}, "material": {"type": "diffuse", "reflectance": 0.7}}]})");
  const std::optional<Vec3> env = brightest_emitter_white_xyz(compile(load_scene(dir / "c.json")));
  ASSERT_TRUE(env);
  const Vec3 orange = rgb_to_xyz_matrix(kRec709) * Vec3{1.0, 0.5, 0.25};
  EXPECT_NEAR(env->x, orange.x / orange.y, 1e-6);
  EXPECT_NEAR(env->z, orange.z / orange.y, 1e-6);
}

}  // namespace
}  // namespace bouguer

namespace bouguer {
namespace {

// The data: URI of the image with alt text `alt` in a report page.
std::string report_image(const std::string& html, const std::string& alt) {
  const std::size_t at = html.find("alt=\"" + alt + "\"");
  if (at == std::string::npos) return {};
  const std::size_t begin = html.find("src=\"", at), end = html.find('"', begin + 5);
  return html.substr(begin + 5, end - begin - 5);
}

TEST(Display, TheReportShowsItsRendersThroughTheDisplayTransform) {
  const fs::path dir = test::scratch_dir("display_report");
  fs::create_directories(dir / "scenes");
  test::write_file(dir / "scenes" / "lit.json", R"({
    "camera": {"position": [0, 1, 0.001], "look_at": [0, 0, 0], "fov_deg": 30, "resolution": [6, 4]},
    "render": {"integrator": "whitted", "spp": 1},
    "objects": [{"shape": {"type": "quad", "size": [4, 4]}, "transform": [{"rotate_deg": [-90, [1, 0, 0]]}],
                 "material": {"type": "diffuse", "reflectance": 0.7}}],
    "lights": [{"type": "point", "position": [0, 2, 0], "spectrum": "D65", "scale": 0.5}]
  })");
  const auto page = [&](const std::string& name, std::vector<std::string> extra) {
    std::vector<std::string> args = {"report", "--out", (dir / name).string(), "--scenes", (dir / "scenes").string(),
                                     "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    const auto r = test::run_bouguer(args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return test::read_file(dir / name / "index.html");
  };
  const std::string plain = page("plain", {}), same = page("same", {"--exposure", "0"}),
                    brighter = page("brighter", {"--exposure", "1"});
  for (const char* alt : {"lit full", "lit rgb3", "lit heat map"}) {
    ASSERT_FALSE(report_image(plain, alt).empty()) << alt;
    EXPECT_EQ(report_image(plain, alt), report_image(same, alt)) << alt;
  }
  EXPECT_NE(report_image(plain, "lit full"), report_image(brighter, "lit full"));
  EXPECT_NE(report_image(plain, "lit rgb3"), report_image(brighter, "lit rgb3"));
  EXPECT_EQ(report_image(plain, "lit heat map"), report_image(brighter, "lit heat map"));  // ΔE00 of the linear films
}

}  // namespace
}  // namespace bouguer
