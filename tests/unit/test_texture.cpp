// Textures: the reader's refusals, the MIP pyramid and its lookup in closed form, and renders that
// show a textured quad reproduces its texels, a grazing checkerboard does not alias, and the image
// does not depend on the thread count.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <numbers>
#include <random>

#include "bouguer/core/error.h"
#include "bouguer/io/image_io.h"
#include "bouguer/io/texture_image.h"
#include "bouguer/scene/texture.h"
#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"
#include "support/gltf_files.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

namespace fs = std::filesystem;

// Writes `rgb` (linear, rows from the top) as an 8-bit sRGB PNG with the project's own writer.
fs::path write_png_texture(const fs::path& dir, const std::string& name, int w, int h,
                           const std::function<Vec3(int, int)>& rgb) {
  Film film(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Vec3 c = rgb(x, y);
      film.set_rgb(x, y, {static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)});
    }
  const fs::path path = dir / name;
  write_image(path, film);
  return path;
}

// The linear value of texel (x, y) of a file as the renderer decodes it.
Vec3 decoded(const TextureImage& image, int x, int y) {
  const float* p = &image.rgb[(static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) +
                               static_cast<std::size_t>(x)) * 3];
  return {srgb_to_linear(p[0]), srgb_to_linear(p[1]), srgb_to_linear(p[2])};
}

double delta_e(const Vec3& a, const Vec3& b) {
  return ciede2000(xyz_to_lab(linear_rgb_to_xyz(kRec709, a)), xyz_to_lab(linear_rgb_to_xyz(kRec709, b)));
}

TEST(TextureImage, ReadsAnSrgbPngAndDecodesIt) {
  const fs::path dir = test::scratch_dir("TextureImageReadsPng");
  const fs::path file = write_png_texture(dir, "t.png", 3, 2, [](int x, int y) { return Vec3{x / 2.0, y * 1.0, 0.5}; });
  const TextureImage image = read_texture_image(file);
  EXPECT_EQ(image.width, 3);
  EXPECT_EQ(image.height, 2);
  EXPECT_TRUE(image.srgb);
  EXPECT_NEAR(decoded(image, 2, 1).x, 1.0, 1e-6);
  EXPECT_NEAR(decoded(image, 1, 0).x, 0.5, 0.004);  // 8-bit sRGB steps near 0.5 are ~0.004
  EXPECT_NEAR(decoded(image, 0, 1).z, 0.5, 0.004);
}

// Missing, not an image, and a header that declares a huge image: one line naming the file, within
// a small memory budget (nothing is allocated for the declared pixels).
TEST(TextureImage, RefusesBadFilesInOneLine) {
  const fs::path dir = test::scratch_dir("TextureImageRefuses");
  test::write_file(dir / "notes.png", "these are not the pixels you are looking for\n");
  // A Radiance HDR header declaring 60000 × 60000 pixels, and no pixels.
  test::write_file(dir / "huge.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 60000 +X 60000\n");
  // The OpenImageIO module (io/texture_module.h) and its libraries are mapped on the first read,
  // before the budget: it bounds what a file makes the reader allocate, not the program's code.
  (void)read_texture_image(write_png_texture(dir, "fine.png", 1, 1, [](int, int) { return Vec3{0.5, 0.5, 0.5}; }));
  for (const char* name : {"missing.png", "notes.png", "huge.hdr"}) {
    const fs::path file = dir / name;
    const std::string outcome =
        test::run_with_memory_budget([&] { read_texture_image(file); }, std::size_t{256} << 20);
    SCOPED_TRACE(outcome);
    EXPECT_EQ(outcome.rfind("error: ", 0), 0u);
    EXPECT_NE(outcome.find(file.string()), std::string::npos);
    EXPECT_EQ(test::line_count(outcome), 1);
  }
  const std::string huge = test::run_with_memory_budget([&] { read_texture_image(dir / "huge.hdr"); }, 256 << 20);
  EXPECT_NE(huge.find("larger than the limit"), std::string::npos) << huge;
}

// The pyramid: levels down to 1 × 1, each level's mean the image's mean (power-of-two sides), and
// bilinear lookups at texel centres return the texels.
TEST(TextureTable, PyramidAndBilinearLookupInClosedForm) {
  TextureImage image;
  image.width = 8;
  image.height = 4;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 8 * 4 * 3; ++i) image.rgb.push_back(u(rng));
  TextureTable table;
  const int id = add_texture(table, image, TextureUse::data);
  const TextureEntry& t = table.textures[static_cast<std::size_t>(id)];
  ASSERT_EQ(t.level_count, 4);  // 8×4, 4×2, 2×1, 1×1
  const TextureLevel& top = table.levels[static_cast<std::size_t>(t.first_level + 3)];
  EXPECT_EQ(top.width, 1);
  EXPECT_EQ(top.height, 1);
  double mean = 0.0;
  for (std::size_t i = 0; i < image.rgb.size(); i += 3) mean += image.rgb[i];
  mean /= 32.0;
  EXPECT_NEAR(table.rgb[top.first].x, mean, 1e-6);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) {
      // Texel (x, y) of the file (rows from the top) sits at u = (x + ½)/8, v = 1 − (y + ½)/4.
      const Vec3 c = texture_rgb(table, texel_blend(table, id, {(x + 0.5) / 8.0, 1.0 - (y + 0.5) / 4.0}, 0.0));
      const float* p = &image.rgb[static_cast<std::size_t>(y * 8 + x) * 3];
      EXPECT_NEAR(c.x, p[0], 1e-6);
      EXPECT_NEAR(c.y, p[1], 1e-6);
      EXPECT_NEAR(c.z, p[2], 1e-6);
    }
  // Halfway between two texels: their mean; wrapping past u = 1 reads column 0 again.
  const Vec3 mid = texture_rgb(table, texel_blend(table, id, {1.0 / 8.0, 1.0 - 0.5 / 4.0}, 0.0));
  EXPECT_NEAR(mid.x, (image.rgb[0] + image.rgb[3]) / 2.0, 1e-6);
  const Vec3 wrapped = texture_rgb(table, texel_blend(table, id, {1.0 + 0.5 / 8.0, 1.0 - 0.5 / 4.0}, 0.0));
  EXPECT_NEAR(wrapped.x, image.rgb[0], 1e-6);
  // Level 3 (or anything beyond it) is the mean.
  EXPECT_NEAR(texture_rgb(table, texel_blend(table, id, {0.3, 0.7}, 9.0)).x, mean, 1e-6);
}

// A 6 × 6 data texture whose texel in column x, row y from the bottom is (x/10, y/10, 0.5).
TextureImage column_row_image() {
  TextureImage image;
  image.width = image.height = 6;
  image.srgb = false;
  for (int row = 0; row < 6; ++row)  // rows from the top in the file
    for (int x = 0; x < 6; ++x)
      image.rgb.insert(image.rgb.end(), {static_cast<float>(x) / 10.0f, static_cast<float>(5 - row) / 10.0f, 0.5f});
  return image;
}

// Wrap modes per axis, at a texel centre outside [0, 1]: u = 1.25 is texel index 1.25·6 − ½ = 7,
// which repeat reads as column 1, clamp as 5 and mirror as 2·6 − 1 − 7 = 4; u = −0.25 is index −2:
// repeat 4, clamp 0, mirror 1. On level 1 (3 × 3, each texel the mean of a 2 × 2 block) clamp at
// u = 1.25 reads its edge column alone, the mean of level 0's columns 4 and 5: 0.45.
TEST(TextureTable, WrapModesInClosedForm) {
  struct Case {
    TextureWrap wrap;
    int at_1_25, at_minus_0_25;
  };
  const Case cases[] = {{TextureWrap::repeat, 1, 4}, {TextureWrap::clamp, 5, 0}, {TextureWrap::mirror, 4, 1}};
  for (const Case& su : cases)
    for (const Case& sv : cases) {
      TextureTable table;
      const int id = add_texture(table, column_row_image(), TextureUse::data, {}, {{su.wrap, sv.wrap}});
      const Vec3 a = texture_rgb(table, texel_blend(table, id, {1.25, -0.25}, 0.0));
      EXPECT_NEAR(a.x, su.at_1_25 / 10.0, 1e-6) << int(su.wrap);
      EXPECT_NEAR(a.y, sv.at_minus_0_25 / 10.0, 1e-6) << int(sv.wrap);
      const Vec3 b = texture_rgb(table, texel_blend(table, id, {-0.25, 1.25}, 0.0));
      EXPECT_NEAR(b.x, su.at_minus_0_25 / 10.0, 1e-6) << int(su.wrap);
      EXPECT_NEAR(b.y, sv.at_1_25 / 10.0, 1e-6) << int(sv.wrap);
    }
  TextureTable table;
  const int clamp = add_texture(table, column_row_image(), TextureUse::data, {}, {{TextureWrap::clamp, TextureWrap::clamp}});
  EXPECT_NEAR(texture_rgb(table, texel_blend(table, clamp, {1.25, 0.5}, 1.0)).x, 0.45, 1e-6);
  EXPECT_NEAR(texture_rgb(table, texel_blend(table, clamp, {-7.0, 0.5}, 1.0)).x, 0.05, 1e-6);
  // Far outside, every mode still reads a texel of the image (no index out of range).
  for (const Case& c : cases) {
    const int id = add_texture(table, column_row_image(), TextureUse::data, {}, {{c.wrap, c.wrap}});
    for (const double u : {-1e15, -3.5, 1e15, 1e300}) {
      const TexelBlend blend = texel_blend(table, id, {u, -u}, 0.0);
      for (int k = 0; k < blend.count; ++k) EXPECT_LT(blend.texel[static_cast<std::size_t>(k)], table.rgb.size());
    }
  }
  // The index map itself: mirror's period is 2n.
  EXPECT_EQ(wrapped_index(-1, 3, TextureWrap::mirror), 0u);
  EXPECT_EQ(wrapped_index(3, 3, TextureWrap::mirror), 2u);
  EXPECT_EQ(wrapped_index(6, 3, TextureWrap::mirror), 0u);
  EXPECT_EQ(wrapped_index(-7, 3, TextureWrap::mirror), 0u);
  EXPECT_EQ(wrapped_index(-1, 3, TextureWrap::repeat), 2u);
  EXPECT_EQ(wrapped_index(-1, 3, TextureWrap::clamp), 0u);
}

// glTF's magFilter NEAREST: magnified (level of detail ≤ 0, or no cone) one texel, the one whose
// square holds (u, v); minified, the same trilinear blend as without it.
TEST(TextureTable, NearestMagnification) {
  TextureTable table;
  TextureSampler nearest;
  nearest.nearest_magnification = true;
  const int id = add_texture(table, column_row_image(), TextureUse::data, {}, nearest);
  const int linear = add_texture(table, column_row_image(), TextureUse::data);
  const TexelBlend b = texel_blend(table, id, {2.9 / 6.0, 0.2 / 6.0}, -3.0);
  ASSERT_EQ(b.count, 1);
  EXPECT_NEAR(texture_rgb(table, b).x, 0.2, 1e-6);
  EXPECT_NEAR(texture_rgb(table, b).y, 0.0, 1e-6);
  EXPECT_NEAR(texture_rgb(table, texel_blend(table, id, {-0.01, 0.5}, 0.0)).x, 0.5, 1e-6);  // repeat: the last column
  EXPECT_NEAR(texture_rgb(table, texel_blend(table, id, {0.3, 0.6}, 1.5)).x,
              texture_rgb(table, texel_blend(table, linear, {0.3, 0.6}, 1.5)).x, 1e-7);
}

// A 256 × 256 grey data texture.
int add_grey_256(TextureTable& table) {
  TextureImage image;
  image.width = image.height = 256;
  image.rgb.assign(256 * 256 * 3, 0.5f);
  return add_texture(table, image, TextureUse::data);
}

// The ray cone's level of detail: a 1 m quad with UVs over [0, 1]² and a 256² texture has 256
// texels per metre; a cone 1/64 m wide covers 4 texels head on (level 2), twice as many at 60°.
TEST(TextureTable, RayConeLevelOfDetailInClosedForm) {
  TextureTable table;
  const int id = add_grey_256(table);
  Mesh quad;
  quad.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  quad.triangles = {{0, 1, 2}, {0, 2, 3}};
  quad.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  EXPECT_NEAR(texture_level_of_detail(table, id, quad, 1, 1.0 / 64.0, 1.0), 2.0, 1e-9);
  EXPECT_NEAR(texture_level_of_detail(table, id, quad, 0, 1.0 / 64.0, 0.5), 3.0, 1e-9);
  EXPECT_TRUE(std::isinf(texture_level_of_detail(table, id, quad, 0, 0.0, 1.0)));
}

// On analytic shapes (no triangles) the density comes from the UV map. A sphere of radius R = 1/π m,
// scaled 2×, on its equator: u spans 2π·2R = 4 m over 256 texels and v spans π·2R = 2 m, so
// 64 × 128 texels per metre; a 1/64 m cone covers √(1 × 2) texel widths (level 0.5). A 2 m disk
// (scaled from r = 0.5) has 128 texels per metre (level 1 for the same cone); a cylinder's side
// of 2 m × 1 m, 128 × 256.
TEST(TextureTable, RayConeLevelOfDetailOnAnalyticShapes) {
  TextureTable table;
  const int id = add_grey_256(table);
  const double r = 1.0 / std::numbers::pi;
  const AnalyticShape sphere{SphereSurface{r}, Transform::scale({2, 2, 2})};
  EXPECT_NEAR(texture_level_of_detail(table, id, sphere, 0, {0.3, 0.5}, 1.0 / 64.0, 1.0), 0.5, 1e-9);
  const AnalyticShape disk{DiskSurface{0.5}, Transform::scale({2, 2, 2})};
  EXPECT_NEAR(texture_level_of_detail(table, id, disk, 0, {0.3, 0.5}, 1.0 / 64.0, 1.0), 1.0, 1e-9);
  const AnalyticShape can{CylinderSurface{r, 1.0}, Transform{}};  // side: 2 m × 1 m for 256²
  EXPECT_NEAR(texture_level_of_detail(table, id, can, 0, {0.3, 0.5}, 1.0 / 64.0, 1.0),
              std::log2(std::sqrt(128.0 * 256.0) / 64.0), 1e-9);
  EXPECT_TRUE(std::isinf(texture_level_of_detail(table, id, sphere, 0, {0.3, 0.5}, 0.0, 1.0)));
}

// A scene of one textured quad facing an orthographic camera, lit head on by a distant light of
// irradiance π (so a reflectance ρ shows as radiance ρ), rendered by Whitted (no noise but the
// pixel jitter).
std::string quad_scene(const fs::path& texture, int resolution, const std::string& integrator, int spp,
                       const std::string& shape = R"({"type": "quad", "size": [1, 1]})") {
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "width": 1,
                "resolution": [{0}, {0}]}},
    "render": {{"integrator": "{1}", "spp": {2}}},
    "objects": [{{"name": "label", "shape": {4},
                  "material": {{"type": "diffuse", "reflectance": {{"texture": "{3}"}}}}}}],
    "lights": [{{"type": "distant", "direction": [0, 0, -1], "spectrum": "D65", "scale": 3.141592653589793}}]
  }})",
                     resolution, integrator, spp, texture.string(), shape);
}

// The quad reproduces its texels: a PNG of 8 × 8 blocks of 2 × 2 equal texels (random sRGB
// colours), seen at 4 pixels per block. The 2 × 2 pixels around each block's centre see only that
// block's texels through the bilinear filter (they lie within half a texel of its centre), so their
// colour is the texel's: mean CIEDE2000 below 1 (measured: see the printout), none above 3.
// The same through an OBJ square with its own UVs (v up, as the quad's): the mesh importer's
// texture coordinates reach the hit.
class TexturedQuad : public ::testing::TestWithParam<bool> {};

TEST_P(TexturedQuad, ReproducesItsTexels) {
  const bool obj = GetParam();
  const fs::path dir = test::scratch_dir(obj ? "TexturedObjQuad" : "TexturedQuad");
  test::write_file(dir / "square.obj", "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 0\nv -0.5 0.5 0\n"
                                       "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n");
  const std::string shape =
      obj ? fmt::format(R"({{"type": "mesh", "file": "{}"}})", (dir / "square.obj").string())
          : std::string(R"({"type": "quad", "size": [1, 1]})");
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.02, 0.95);
  std::vector<Vec3> blocks(64);
  for (Vec3& b : blocks) b = {u(rng), u(rng), u(rng)};
  const fs::path png = write_png_texture(dir, "blocks.png", 16, 16, [&](int x, int y) { return blocks[(y / 2) * 8 + x / 2]; });
  const TextureImage image = read_texture_image(png);
  const Film film = test::render_text(quad_scene(png, 32, "whitted", 16, shape), 2);
  double sum = 0.0, worst = 0.0;
  for (int by = 0; by < 8; ++by)
    for (int bx = 0; bx < 8; ++bx) {
      Vec3 mean{};
      for (int dy = 1; dy <= 2; ++dy)
        for (int dx = 1; dx <= 2; ++dx) {
          const Vec3f p = film.rgb_at(bx * 4 + dx, by * 4 + dy);
          mean = mean + Vec3{p.x, p.y, p.z} * 0.25;
        }
      const double e = delta_e(mean, decoded(image, 2 * bx, 2 * by));
      sum += e;
      worst = std::max(worst, e);
    }
  std::printf("textured %s: mean ΔE00 %.3f, largest %.3f over 64 texels\n", obj ? "OBJ square" : "quad", sum / 64.0,
              worst);
  EXPECT_LT(sum / 64.0, 1.0);
  EXPECT_LT(worst, 3.0);
}
INSTANTIATE_TEST_SUITE_P(TextureRender, TexturedQuad, ::testing::Values(false, true),
                         [](const auto& p) { return p.param ? "ObjMesh" : "Quad"; });

// The grazing checkerboard's scene and what its rows see (below).
struct GrazingCheckerboard {
  static constexpr int kTexels = 256, kWidth = 96, kHeight = 64;
  static constexpr double kFloorM = 20.0, kHeightM = 0.1, kCheckM = 2.0 * kFloorM / kTexels, kFovDeg = 30.0;
  fs::path png;
  double grey = 0.0;
  double pixel_rad = 2.0 * std::tan(kFovDeg * std::numbers::pi / 360.0) / kHeight;

  explicit GrazingCheckerboard(const fs::path& dir) {
    png = write_png_texture(dir, "checks.png", kTexels, kTexels, [](int x, int y) {
      const double v = ((x / 2 + y / 2) % 2) ? 0.8 : 0.2;
      return Vec3{v, v, v};
    });
    const TextureImage image = read_texture_image(png);
    grey = (decoded(image, 0, 0).y + decoded(image, 2, 0).y) / 2.0;
  }
  Film render(const std::string& integrator, int spp) const {
    return test::render_text(fmt::format(R"({{
    "camera": {{"position": [0, {0}, 0], "look_at": [0, {0}, -1], "fov_deg": {1}, "resolution": [{2}, {3}]}},
    "render": {{"integrator": "{7}", "spp": {8}}},
    "objects": [{{"name": "floor", "shape": {{"type": "quad", "size": [{4}, {4}]}},
                  "transform": [{{"rotate_deg": [-90, [1, 0, 0]]}}, {{"translate": [0, 0, {5}]}}],
                  "material": {{"type": "diffuse", "reflectance": {{"texture": "{6}"}}}}}}],
    "lights": [{{"type": "distant", "direction": [0, -1, 0], "spectrum": "D65", "scale": 3.141592653589793}}]
  }})",
                                         kHeightM, kFovDeg, kWidth, kHeight, kFloorM, -kFloorM / 2.0 + 0.01,
                                         png.string(), integrator, spp),
                             2);
  }
  // Row r below the horizon (the middle of the image) looks down at α ≈ (r + ½)·pixel and meets the
  // floor at d = h/tan α; one check there spans h·check/d² radians along the view. Returns that in
  // pixels, or 0 beyond the floor's far edge.
  double check_px(int r) const {
    const double alpha = (r + 0.5) * pixel_rad, d = kHeightM / std::tan(alpha);
    if (d > kFloorM - 0.5) return 0.0;
    return kHeightM * kCheckM / (d * d) / pixel_rad;
  }
  // The mean and the spread of the green channel along row r below the horizon.
  static std::pair<double, double> stats(const Film& film, int r) {
    double sum = 0.0, sum2 = 0.0;
    for (int x = 0; x < kWidth; ++x) {
      const double g = film.rgb_at(x, kHeight / 2 + r).y;
      sum += g;
      sum2 += g * g;
    }
    const double mean = sum / kWidth;
    return std::pair{mean, std::sqrt(std::max(0.0, sum2 / kWidth - mean * mean))};
  }
};

// A checkerboard floor seen at grazing angles by a pinhole camera at 1 sample per pixel (Whitted,
// a distant light from straight above: no noise but where in the pixel the sample lands). Checks
// of 2 × 2 texels, linear reflectances 0.2 and 0.8 (mean 0.5).
//   Far rows — where one check spans less than half a pixel along the view — hold many checks per
//   pixel. Without MIP maps each pixel would read one texel (0.2 or 0.8: a spread of 0.3); with the
//   ray cone the footprint covers at least two checks (level ≥ 2, where every texel is the mean),
//   so their mean lies within 0.01 of 0.5 (8-bit quantisation and the blend with level 1 where the
//   footprint just reaches it) and their spread below 0.05.
//   Near rows — a check over more than 4 pixels — must read level 0. There the bilinear filter
//   turns each axis of the 2-texel checks into flats half the time and linear ramps the other half,
//   so the pixels' spread is 0.3·(½ + ½·⅓) = 0.2; one level coarser (1-texel checks, ramps all the
//   way) it would be 0.3·⅓ = 0.1. Bound: above 0.17 (over-blurring fails).
TEST(TextureRender, GrazingCheckerboardDoesNotAlias) {
  const GrazingCheckerboard board(test::scratch_dir("GrazingCheckerboard"));
  const Film film = board.render("whitted", 1);
  const int w = GrazingCheckerboard::kWidth;
  int far_rows = 0, near_rows = 0;
  double near_sum = 0.0, near_sum2 = 0.0;
  for (int r = 0; r < GrazingCheckerboard::kHeight / 2; ++r) {
    const double check_px = board.check_px(r);
    if (check_px == 0.0) continue;
    const auto [mean, spread] = GrazingCheckerboard::stats(film, r);
    if (check_px < 0.5) {
      ++far_rows;
      std::printf("far row %d (check %.2f px): mean %.4f (grey %.4f), spread %.4f\n", r, check_px, mean, board.grey,
                  spread);
      EXPECT_NEAR(mean, board.grey, 0.01) << "row " << r;
      EXPECT_LT(spread, 0.05) << "row " << r;
    } else if (check_px > 4.0) {
      ++near_rows;
      near_sum += mean * w;
      near_sum2 += (spread * spread + mean * mean) * w;
    }
  }
  EXPECT_GE(far_rows, 3);
  ASSERT_GE(near_rows, 3);
  const double near_mean = near_sum / (near_rows * w);
  const double near_spread = std::sqrt(near_sum2 / (near_rows * w) - near_mean * near_mean);
  std::printf("near rows (%d): spread %.4f (level 0: 0.2, level 1: 0.1)\n", near_rows, near_spread);
  EXPECT_GT(near_spread, 0.17);
}

// The same floor under bdpt and vcm at 16 spp: their camera subpaths carry the pixel's cone, so the
// rows whose checks span 0.2 to 0.5 pixels read the grey levels. Their light-tracing strategy
// (t = 1) reads the finest level, as every light subpath does, and adds noise nearest the horizon,
// so the rows checked are those where the camera's strategies carry the light: measured spreads
// 0.003–0.007 (without the cone 0.037–0.047, each pixel's 16 samples reading single texels).
TEST(TextureRender, GrazingCheckerboardDoesNotAliasInTheBidirectionalEstimators) {
  const GrazingCheckerboard board(test::scratch_dir("GrazingCheckerboardBidirectional"));
  for (const char* integrator : {"bdpt", "vcm"}) {
    const Film film = board.render(integrator, 16);
    int rows = 0;
    for (int r = 0; r < GrazingCheckerboard::kHeight / 2; ++r) {
      const double check_px = board.check_px(r);
      if (!(check_px >= 0.2 && check_px < 0.5)) continue;
      ++rows;
      const auto [mean, spread] = GrazingCheckerboard::stats(film, r);
      std::printf("%s, row %d (check %.2f px): mean %.4f (grey %.4f), spread %.4f\n", integrator, r, check_px, mean,
                  board.grey, spread);
      EXPECT_NEAR(mean, board.grey, 0.01) << integrator << " row " << r;
      EXPECT_LT(spread, 0.02) << integrator << " row " << r;
    }
    EXPECT_GE(rows, 2) << integrator;
  }
}

// A 4 × 4 PNG (as bytes) of four 2 × 2 quadrants: red, green (top), blue, grey (bottom).
std::string quadrant_png() {
  const std::array<Vec3, 4> quadrant{Vec3{0.8, 0.1, 0.1}, Vec3{0.1, 0.7, 0.1}, Vec3{0.1, 0.1, 0.6}, Vec3{0.5, 0.5, 0.5}};
  Film image(4, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 4; ++x) {
      const Vec3& c = quadrant[static_cast<std::size_t>((y / 2) * 2 + x / 2)];
      image.set_rgb(x, y, {static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)});
    }
  return encode_png(image);
}

// A glTF square whose baseColorTexture is a PNG embedded in the .glb (decoded by OpenImageIO through
// tinygltf's image loader): 4 × 4 texels in four 2 × 2 quadrants, UV (0, 0) at the top-left corner
// (glTF's v runs down). Seen head on, each quadrant's middle pixels show its texels; with
// KHR_texture_transform's offset of half the texture along u, the left shows what was on the right.
TEST(TextureRender, GltfBaseColorTextureAndTransform) {
  const fs::path dir = test::scratch_dir("GltfTexture");
  const std::string png = quadrant_png();
  for (const bool shifted : {false, true}) {
    test::GltfDoc g;
    nlohmann::json info = {{"index", 0}};
    if (shifted) {
      info["extensions"] = {{"KHR_texture_transform", {{"offset", {0.5, 0.0}}}}};
      g.doc["extensionsUsed"] = {"KHR_texture_transform"};
    }
    const int material = g.material({{"name", "Label"},
                                      {"pbrMetallicRoughness", {{"baseColorTexture", info}, {"metallicFactor", 0.0}}}});
    const int mesh = g.mesh({{-0.5, 0.5, 0}, {0.5, 0.5, 0}, {0.5, -0.5, 0}, {-0.5, -0.5, 0}}, {0, 3, 2, 0, 2, 1}, material);
    const std::vector<float> uv{0, 0, 1, 0, 1, 1, 0, 1};
    g.doc["accessors"].push_back({{"bufferView", g.view(uv.data(), uv.size() * sizeof(float))},
                                  {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
    g.doc["meshes"][mesh]["primitives"][0]["attributes"]["TEXCOORD_0"] = g.doc["accessors"].size() - 1;
    g.doc["images"] = {{{"bufferView", g.view(png.data(), png.size())}, {"mimeType", "image/png"}}};
    g.doc["textures"] = {{{"source", 0}}};
    g.node({{"mesh", mesh}});
    const fs::path glb = dir / (shifted ? "shifted.glb" : "label.glb");
    g.write(glb);
    const Film film = test::render_text(fmt::format(R"({{
      "camera": {{"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "width": 1, "resolution": [8, 8]}},
      "render": {{"integrator": "whitted", "spp": 4}},
      "objects": [{{"gltf": "{}"}}],
      "lights": [{{"type": "distant", "direction": [0, 0, -1], "spectrum": "D65", "scale": 3.141592653589793}}]
    }})", glb.string()), 2);
    const TextureImage decoded_png = read_texture_image(std::span(reinterpret_cast<const unsigned char*>(png.data()), png.size()), "label.png");
    for (int qy = 0; qy < 2; ++qy)
      for (int qx = 0; qx < 2; ++qx) {
        const int source_x = shifted ? 1 - qx : qx;  // the offset moves u by half: left reads right
        const Vec3 expected = decoded(decoded_png, source_x * 2, qy * 2);
        const Vec3f p = film.rgb_at(qx * 4 + 1, qy * 4 + 1);
        const double e = delta_e({p.x, p.y, p.z}, expected);
        EXPECT_LT(e, 1.0) << (shifted ? "shifted, " : "") << "quadrant " << qx << ", " << qy;
      }
  }
}

// A glTF square whose UVs run from −0.5 to 1.5 (the image covers its middle half), its texture the
// four quadrants above, embedded. With a sampler of CLAMP_TO_EDGE on both axes, the pixels outside
// the image show its edge texels: every pixel of the 8 × 8 film whose UVs lie below 0 or above 1
// on an axis reads the edge row or column there (the image's 2 × 2 quadrants make an edge texel the
// quadrant's colour), e.g. the corner pixels show the corner quadrants. Under repeat (no sampler)
// the corner pixel (0, 0) at u, v ∈ [−0.5, −0.25] reads the texture around (0.5 … 0.75): not the
// top-left quadrant. A sampler's unknown wrap code is one line naming it.
TEST(TextureRender, GltfClampSamplerShowsTheEdgeTexelOutsideTheImage) {
  const fs::path dir = test::scratch_dir("GltfClampSampler");
  const std::string png = quadrant_png();
  const TextureImage decoded_png =
      read_texture_image(std::span(reinterpret_cast<const unsigned char*>(png.data()), png.size()), "label.png");
  auto asset = [&](const nlohmann::json& sampler, const std::string& name) {
    test::GltfDoc g;
    const int material = g.material({{"name", "Label"},
                                     {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"metallicFactor", 0.0}}}});
    const int mesh = g.mesh({{-0.5, 0.5, 0}, {0.5, 0.5, 0}, {0.5, -0.5, 0}, {-0.5, -0.5, 0}}, {0, 3, 2, 0, 2, 1}, material);
    const std::vector<float> uv{-0.5f, -0.5f, 1.5f, -0.5f, 1.5f, 1.5f, -0.5f, 1.5f};
    g.doc["accessors"].push_back({{"bufferView", g.view(uv.data(), uv.size() * sizeof(float))},
                                  {"componentType", 5126}, {"count", 4}, {"type", "VEC2"}});
    g.doc["meshes"][mesh]["primitives"][0]["attributes"]["TEXCOORD_0"] = g.doc["accessors"].size() - 1;
    g.doc["images"] = {{{"bufferView", g.view(png.data(), png.size())}, {"mimeType", "image/png"}}};
    g.doc["textures"] = {{{"source", 0}}};
    if (!sampler.is_null()) {
      g.doc["samplers"] = {sampler};
      g.doc["textures"][0]["sampler"] = 0;
    }
    g.node({{"mesh", mesh}});
    g.write(dir / name);
    return test::render_text(fmt::format(R"({{
      "camera": {{"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "width": 1, "resolution": [8, 8]}},
      "render": {{"integrator": "whitted", "spp": 4}},
      "objects": [{{"gltf": "{}"}}],
      "lights": [{{"type": "distant", "direction": [0, 0, -1], "spectrum": "D65", "scale": 3.141592653589793}}]
    }})", (dir / name).string()), 2);
  };
  const Film clamped = asset({{"wrapS", 33071}, {"wrapT", 33071}}, "clamp.glb");
  // Pixel p covers u ∈ [−0.5 + p/4, −0.25 + p/4]: outside the image for p ≤ 1 (the left or top
  // edge texels) and p ≥ 6 (the right or bottom ones).
  for (const int py : {0, 1, 6, 7})
    for (const int px : {0, 1, 6, 7}) {
      const int tx = px < 4 ? 0 : 3, ty = py < 4 ? 0 : 3;
      const Vec3f p = clamped.rgb_at(px, py);
      EXPECT_LT(delta_e({p.x, p.y, p.z}, decoded(decoded_png, tx, ty)), 1.0) << "pixel " << px << ", " << py;
    }
  const Film repeated = asset(nullptr, "repeat.glb");
  const Vec3f r = repeated.rgb_at(0, 0);
  EXPECT_GT(delta_e({r.x, r.y, r.z}, decoded(decoded_png, 0, 0)), 10.0);
  // Mirror on u, clamp on v: pixel (1, 0) covers u ∈ [−0.25, 0], mirrored to [0, 0.25]: the top-left quadrant.
  const Film mirrored = asset({{"wrapS", 33648}, {"wrapT", 33071}}, "mirror.glb");
  const Vec3f m = mirrored.rgb_at(1, 0);
  EXPECT_LT(delta_e({m.x, m.y, m.z}, decoded(decoded_png, 0, 0)), 1.0);
  try {
    asset({{"wrapS", 12345}}, "bad.glb");
    ADD_FAILURE() << "an unknown wrap code was accepted";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad.glb: samplers[0].wrapS: 12345 is not a wrap mode"), std::string::npos) << msg;
    EXPECT_EQ(test::line_count(msg), 1) << msg;
  }
}

// An embedded image whose buffer view runs past its buffer (tinygltf would hand the image loader
// bytes beyond the buffer; found by the gltf fuzz harness) is one line naming the view and image.
TEST(TextureRender, GltfImageViewBeyondItsBufferIsOneLine) {
  const fs::path dir = test::scratch_dir("GltfImageViewBeyond");
  test::GltfDoc g;
  const int mesh = g.mesh({{-0.5, 0.5, 0}, {0.5, 0.5, 0}, {0.5, -0.5, 0}}, {0, 2, 1});
  const std::string png = quadrant_png();
  const int view = g.view(png.data(), png.size());
  g.doc["images"] = {{{"bufferView", view}, {"mimeType", "image/png"}}};
  g.doc["bufferViews"][std::size_t(view)]["byteLength"] = png.size() + 4096;
  g.node({{"mesh", mesh}});
  g.write(dir / "bad_view.glb");
  const test::RunResult r = test::run_bouguer({"render", (dir / "bad_view.glb").string(), "-o", (dir / "out.png").string()});
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(test::line_count(r.err), 1) << r.err;
  EXPECT_NE(r.err.find(fmt::format("bad_view.glb: bufferViews[{}]: bytes", view)), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("where images[0] is read"), std::string::npos) << r.err;
}

// The same seed gives the same image on 1 and 2 threads (the path tracer, textures, MIP levels).
TEST(TextureRender, IndependentOfTheThreadCount) {
  const fs::path dir = test::scratch_dir("TextureThreads");
  const fs::path png = write_png_texture(dir, "t.png", 16, 16, [](int x, int y) { return Vec3{x / 15.0, y / 15.0, 0.3}; });
  const std::string scene = quad_scene(png, 12, "path", 4);
  const Film one = test::render_text(scene, 1), two = test::render_text(scene, 2);
  ASSERT_EQ(one.rgb.size(), two.rgb.size());
  for (std::size_t i = 0; i < one.rgb.size(); ++i) ASSERT_EQ(one.rgb[i], two.rgb[i]) << i;
}

// From a scene file: a missing texture, a text file, a huge one; each one line naming the file and
// the key, exit 1.
TEST(TextureRender, BadTexturesInASceneAreOneLine) {
  const fs::path dir = test::scratch_dir("BadTextureScenes");
  test::write_file(dir / "notes.png", "not an image\n");
  test::write_file(dir / "huge.hdr", "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 60000 +X 60000\n");
  for (const char* name : {"missing.png", "notes.png", "huge.hdr"}) {
    const fs::path scene = dir / fmt::format("{}.json", name);
    test::write_file(scene, quad_scene(dir / name, 8, "whitted", 1));
    const test::RunResult r = test::run_bouguer({"render", scene.string(), "-o", (dir / "out.png").string()});
    SCOPED_TRACE(r.err);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(test::line_count(r.err), 1);
    EXPECT_NE(r.err.find(name), std::string::npos);
    EXPECT_NE(r.err.find("reflectance.texture"), std::string::npos);
  }
}

// scenes/examples: the script writes the committed bottle (deterministic, numpy only), and its scene
// renders (the label's texture embedded in the .glb, the glass and wine given media by name).
TEST(TextureRender, ExampleTexturedBottle) {
  const fs::path examples = fs::path(BOUGUER_SOURCE_DIR) / "scenes" / "examples";
  const fs::path dir = test::scratch_dir("ExampleTexturedBottle");
  const test::RunResult script =
      test::run_program("/usr/bin/python3", {(examples / "make_textured_bottle.py").string(), (dir / "b.glb").string()});
  ASSERT_EQ(script.exit_code, 0) << script.err;
  EXPECT_EQ(test::read_file(dir / "b.glb"), test::read_file(examples / "textured-bottle.glb"))
      << "the committed textured-bottle.glb is not what the script writes";
  const test::RunResult r = test::run_bouguer({"render", (examples / "textured-bottle.json").string(), "--resolution",
                                               "16x24", "--spp", "1", "-o", (dir / "bottle.png").string(), "--quiet"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// An OBJ square of two materials from its MTL ("material": "mtl"): the left half Kd, the right
// half a map_Kd texture of one colour. Each half shows its own (ΔE00 below 1 at its middle).
std::string mtl_scene(const fs::path& obj) {
  return fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "width": 1, "resolution": [8, 8]}},
    "render": {{"integrator": "whitted", "spp": 4}},
    "objects": [{{"name": "card", "shape": {{"type": "mesh", "file": "{}"}}, "material": "mtl"}}],
    "lights": [{{"type": "distant", "direction": [0, 0, -1], "spectrum": "D65", "scale": 3.141592653589793}}]
  }})",
                     obj.string());
}

const char* kTwoMaterialSquare =
    "mtllib card.mtl\nv -0.5 -0.5 0\nv 0 -0.5 0\nv 0.5 -0.5 0\nv -0.5 0.5 0\nv 0 0.5 0\nv 0.5 0.5 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "usemtl Red\nf 1/1 2/2 5/3 4/4\nusemtl Paper\nf 2/1 3/2 6/3 5/4\n";

TEST(TextureRender, ObjMtlDiffuseColourAndTexturePerFace) {
  const fs::path dir = test::scratch_dir("ObjMtl");
  const fs::path png = write_png_texture(dir, "paper.png", 4, 4, [](int, int) { return Vec3{0.2, 0.4, 0.7}; });
  test::write_file(dir / "card.obj", kTwoMaterialSquare);
  test::write_file(dir / "card.mtl", "newmtl Red\nKd 0.8 0.1 0.1\n\nnewmtl Paper\nKd 1 1 1\nmap_Kd paper.png\n");
  const Film film = test::render_text(mtl_scene(dir / "card.obj"), 2);
  const TextureImage paper = read_texture_image(png);
  for (int y : {3, 4}) {
    const Vec3f left = film.rgb_at(1, y), right = film.rgb_at(6, y);
    EXPECT_LT(delta_e({left.x, left.y, left.z}, {0.8, 0.1, 0.1}), 1.0) << "Kd";
    EXPECT_LT(delta_e({right.x, right.y, right.z}, decoded(paper, 0, 0)), 1.0) << "map_Kd";
  }
}

// A bad MTL, or one it names: one line naming the file, exit 1.
TEST(TextureRender, BadMtlIsOneLine) {
  const fs::path dir = test::scratch_dir("BadMtl");
  test::write_file(dir / "notes.png", "not an image\n");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"", "card.mtl' not found"},                                   // no MTL beside the OBJ
      {"newmtl Red\nKd nan 0.1 0.1\nnewmtl Paper\n", "line 2: 'nan' is not a finite number"},
      {"newmtl Red\nKd 1.5 0.1 0.1\nnewmtl Paper\n", "material 'Red': Kd 1.5 must lie between 0 and 1"},
      {"newmtl Red\nnewmtl Paper\nmap_Kd notes.png\n", "notes.png"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path sub = dir / std::to_string(i);
    fs::create_directories(sub);
    test::write_file(sub / "card.obj", kTwoMaterialSquare);
    if (!cases[i].first.empty()) test::write_file(sub / "card.mtl", cases[i].first);
    fs::copy_file(dir / "notes.png", sub / "notes.png");
    test::write_file(sub / "scene.json", mtl_scene(sub / "card.obj"));
    const test::RunResult r = test::run_bouguer({"render", (sub / "scene.json").string(), "-o", (sub / "o.png").string()});
    SCOPED_TRACE(r.err);
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_EQ(test::line_count(r.err), 1);
    EXPECT_NE(r.err.find(cases[i].second), std::string::npos);
    if (i < 3) {  // the OBJ or the MTL (a texture names itself)
      EXPECT_NE(r.err.find("card."), std::string::npos);
    }
  }
}

}  // namespace
}  // namespace bouguer
