#include "bouguer/scene/texture.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <type_traits>
#include <variant>

#include "bouguer/spectra/color_space.h"
#include "bouguer/spectra/rgb_to_spectrum.h"

namespace bouguer {
namespace {

// Level 0 from the image (rows from the top in the file, from the bottom here), decoded for its use.
std::vector<Vec3f> base_level(const TextureImage& image, TextureUse use) {
  const auto w = static_cast<std::size_t>(image.width), h = static_cast<std::size_t>(image.height);
  std::vector<Vec3f> texels(w * h);
  const bool decode = image.srgb && use != TextureUse::data;
  for (std::size_t y = 0; y < h; ++y)
    for (std::size_t x = 0; x < w; ++x) {
      const float* p = &image.rgb[((h - 1 - y) * w + x) * 3];
      Vec3f& t = texels[y * w + x];
      for (std::size_t c = 0; c < 3; ++c) t[c] = decode ? srgb_to_linear(p[c]) : p[c];
      if (use == TextureUse::reflectance)
        for (std::size_t c = 0; c < 3; ++c) t[c] = std::clamp(t[c], 0.0f, 1.0f);
    }
  return texels;
}

// The next level: each texel the mean of a 2 × 2 block (at an odd edge the last row or column
// stands in for the missing one).
std::vector<Vec3f> halved(const std::vector<Vec3f>& level, int width, int height, int& out_width, int& out_height) {
  out_width = std::max(1, (width + 1) / 2);
  out_height = std::max(1, (height + 1) / 2);
  std::vector<Vec3f> next(static_cast<std::size_t>(out_width) * static_cast<std::size_t>(out_height));
  auto at = [&](int x, int y) {
    return level[static_cast<std::size_t>(std::min(y, height - 1)) * static_cast<std::size_t>(width) +
                 static_cast<std::size_t>(std::min(x, width - 1))];
  };
  for (int y = 0; y < out_height; ++y)
    for (int x = 0; x < out_width; ++x)
      next[static_cast<std::size_t>(y) * static_cast<std::size_t>(out_width) + static_cast<std::size_t>(x)] =
          (at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) + at(2 * x, 2 * y + 1) + at(2 * x + 1, 2 * y + 1)) * 0.25f;
  return next;
}

void append_level(TextureTable& table, const std::vector<Vec3f>& texels, int width, int height, TextureUse use) {
  table.levels.push_back({width, height, table.rgb.size()});
  table.rgb.insert(table.rgb.end(), texels.begin(), texels.end());
  for (const Vec3f& t : texels) {
    std::array<float, 3> c{};
    if (use == TextureUse::reflectance) {
      const SigmoidPolynomial s = rgb_to_reflectance(Vec3{t.x, t.y, t.z});
      c = {static_cast<float>(s.c0), static_cast<float>(s.c1), static_cast<float>(s.c2)};
    }
    table.sigmoid.push_back(c);
  }
}

std::array<double, 2> transformed(const UvTransform& t, std::array<double, 2> uv) {
  // KHR_texture_transform works in glTF's v-down coordinates.
  const double u = uv[0] * t.scale[0], v = (1.0 - uv[1]) * t.scale[1];
  const double c = std::cos(t.rotation_rad), s = std::sin(t.rotation_rad);
  return {c * u + s * v + t.offset[0], 1.0 - (-s * u + c * v + t.offset[1])};
}

// A texel coordinate as a whole-texel floor that fits a long: beyond ±2^40 texels (or for a
// coordinate that is not finite) a texture's transform has lost all precision anyway.
double texel_floor(double x) { return std::isfinite(x) ? std::floor(std::clamp(x, -0x1p40, 0x1p40)) : 0.0; }

void add_bilinear(const TextureLevel& level, const TextureSampler& sampler, std::array<double, 2> uv, float weight,
                  TexelBlend& blend) {
  const double x = uv[0] * level.width - 0.5, y = uv[1] * level.height - 0.5;
  const double x0 = texel_floor(x), y0 = texel_floor(y);
  const auto fx = std::clamp(static_cast<float>(x - x0), 0.0f, 1.0f);
  const auto fy = std::clamp(static_cast<float>(y - y0), 0.0f, 1.0f);
  for (int dy = 0; dy < 2; ++dy)
    for (int dx = 0; dx < 2; ++dx) {
      const std::size_t col = wrapped_index(static_cast<long>(x0) + dx, level.width, sampler.wrap[0]);
      const std::size_t row = wrapped_index(static_cast<long>(y0) + dy, level.height, sampler.wrap[1]);
      const auto k = static_cast<std::size_t>(blend.count++);
      blend.texel[k] = level.first + row * static_cast<std::size_t>(level.width) + col;
      blend.weight[k] = weight * (dx ? fx : 1.0f - fx) * (dy ? fy : 1.0f - fy);
    }
}

// The one texel whose square holds (u, v) (glTF's NEAREST).
void add_nearest(const TextureLevel& level, const TextureSampler& sampler, std::array<double, 2> uv,
                 TexelBlend& blend) {
  const auto x = static_cast<long>(texel_floor(uv[0] * level.width));
  const auto y = static_cast<long>(texel_floor(uv[1] * level.height));
  const std::size_t col = wrapped_index(x, level.width, sampler.wrap[0]);
  const std::size_t row = wrapped_index(y, level.height, sampler.wrap[1]);
  blend.texel[0] = level.first + row * static_cast<std::size_t>(level.width) + col;
  blend.weight[0] = 1.0f;
  blend.count = 1;
}

}  // namespace

std::size_t wrapped_index(long i, int n, TextureWrap wrap) {
  switch (wrap) {
    case TextureWrap::clamp: return static_cast<std::size_t>(std::clamp(i, 0L, static_cast<long>(n) - 1));
    case TextureWrap::mirror: {  // period 2n: n texels forward, then the same n backward
      const long m = i % (2L * n), k = m < 0 ? m + 2L * n : m;
      return static_cast<std::size_t>(k < n ? k : 2L * n - 1 - k);
    }
    case TextureWrap::repeat: break;
  }
  const long m = i % n;
  return static_cast<std::size_t>(m < 0 ? m + n : m);
}

UvTransform uv_transform_v_up(std::array<double, 2> offset, double rotation_rad, std::array<double, 2> scale) {
  return {{offset[0] - std::sin(rotation_rad) * scale[1], 1.0 - std::cos(rotation_rad) * scale[1] - offset[1]},
          rotation_rad,
          scale};
}

int add_texture(TextureTable& table, const TextureImage& image, TextureUse use, const UvTransform& transform,
                const TextureSampler& sampler) {
  assert(image.width > 0 && image.height > 0);
  TextureEntry entry{static_cast<int>(table.levels.size()), 0, transform, sampler};
  int width = image.width, height = image.height;
  std::vector<Vec3f> level = base_level(image, use);
  for (;;) {
    append_level(table, level, width, height, use);
    ++entry.level_count;
    if (width == 1 && height == 1) break;
    int w2 = 0, h2 = 0;
    level = halved(level, width, height, w2, h2);
    width = w2;
    height = h2;
  }
  table.textures.push_back(entry);
  return static_cast<int>(table.textures.size()) - 1;
}

std::array<double, 2> texture_coordinates(const TextureTable& table, int id, std::array<double, 2> uv) {
  return transformed(table.textures[static_cast<std::size_t>(id)].transform, uv);
}

TexelBlend texel_blend(const TextureTable& table, int id, std::array<double, 2> uv, double level_of_detail) {
  const TextureEntry& t = table.textures[static_cast<std::size_t>(id)];
  const std::array<double, 2> st = transformed(t.transform, uv);
  // −∞ (no cone) and NaN read the finest level, +∞ the coarsest.
  const double lod = std::min(level_of_detail > 0.0 ? level_of_detail : 0.0, static_cast<double>(t.level_count - 1));
  const int l0 = std::min(static_cast<int>(lod), t.level_count - 1);
  const auto f = static_cast<float>(lod - l0);
  TexelBlend blend;
  const auto level = [&](int l) { return table.levels[static_cast<std::size_t>(t.first_level + l)]; };
  if (t.sampler.nearest_magnification && !(level_of_detail > 0.0)) {
    add_nearest(level(0), t.sampler, st, blend);
    return blend;
  }
  add_bilinear(level(l0), t.sampler, st, 1.0f - f, blend);
  if (f > 0.0f && l0 + 1 < t.level_count) add_bilinear(level(l0 + 1), t.sampler, st, f, blend);
  return blend;
}

namespace {

// log2 of a footprint in level-0 texels, from the UV area per square metre at the hit (before
// the texture's own transform).
double level_of_detail(const TextureTable& table, int id, double uv_per_m2, double cone_width_m, double cos_theta) {
  const TextureEntry& t = table.textures[static_cast<std::size_t>(id)];
  const TextureLevel& base = table.levels[static_cast<std::size_t>(t.first_level)];
  const double texels_per_m2 = uv_per_m2 * std::abs(t.transform.scale[0] * t.transform.scale[1]) * base.width * base.height;
  if (!(texels_per_m2 > 0.0) || !std::isfinite(texels_per_m2)) return -std::numeric_limits<double>::infinity();
  const double footprint_m = cone_width_m / std::max(std::abs(cos_theta), 1e-3);
  return std::log2(footprint_m * std::sqrt(texels_per_m2));
}

}  // namespace

double texture_level_of_detail(const TextureTable& table, int id, const Mesh& mesh, std::uint32_t primitive,
                               double cone_width_m, double cos_theta) {
  if (!(cone_width_m > 0.0) || mesh.uvs.empty()) return -std::numeric_limits<double>::infinity();
  const auto& tri = mesh.triangles[primitive];
  const Vec3 e1 = mesh.positions[tri[1]] - mesh.positions[tri[0]], e2 = mesh.positions[tri[2]] - mesh.positions[tri[0]];
  const auto& a = mesh.uvs[tri[0]];
  const auto& b = mesh.uvs[tri[1]];
  const auto& c = mesh.uvs[tri[2]];
  const double uv_area = std::abs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]));
  const double world_area = length(cross(e1, e2));
  if (!(world_area > 0.0)) return -std::numeric_limits<double>::infinity();
  return level_of_detail(table, id, uv_area / world_area, cone_width_m, cos_theta);
}

double texture_level_of_detail(const TextureTable& table, int id, const AnalyticShape& shape, std::uint32_t part,
                               std::array<double, 2> uv, double cone_width_m, double cos_theta) {
  if (!(cone_width_m > 0.0)) return -std::numeric_limits<double>::infinity();
  constexpr double kPi = 3.14159265358979323846;
  // d(u, v)/dA of the local UV maps: longitude/2π and colatitude/π on a sphere, longitude/2π and
  // y/height on a cylinder's side, [−r, r]² → [0, 1]² on a disk and the caps. The sphere's
  // sin θ is kept from 0 near the poles, where its map is singular.
  const double uv_per_m2 = std::visit(
      [&](const auto& s) -> double {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, SphereSurface>)
          return 1.0 / (2.0 * kPi * kPi * s.radius_m * s.radius_m * std::max(std::sin(kPi * uv[1]), 1e-3));
        else if constexpr (std::is_same_v<S, CylinderSurface>)
          return part == static_cast<std::uint32_t>(AnalyticPart::side)
                     ? 1.0 / (2.0 * kPi * s.radius_m * s.height_m)
                     : 1.0 / (4.0 * s.radius_m * s.radius_m);
        else
          return 1.0 / (4.0 * s.radius_m * s.radius_m);
      },
      shape.surface);
  // World area = local area × the linear part's mean areal scale, |det|^(2/3) (exact for a uniform scale).
  const double area_scale = std::pow(std::abs(shape.to_world.determinant()), 2.0 / 3.0);
  if (!(area_scale > 0.0)) return -std::numeric_limits<double>::infinity();
  return level_of_detail(table, id, uv_per_m2 / area_scale, cone_width_m, cos_theta);
}

double texture_mean_luminance(const TextureTable& table, int id, const std::array<std::array<double, 2>, 3>& uv) {
  constexpr int kSide = 8;  // a grid of kSide² points, each the centre of a sub-triangle
  const TextureEntry& t = table.textures[static_cast<std::size_t>(id)];
  const TextureLevel& base = table.levels[static_cast<std::size_t>(t.first_level)];
  const double uv_area = 0.5 * std::abs((uv[1][0] - uv[0][0]) * (uv[2][1] - uv[0][1]) -
                                        (uv[2][0] - uv[0][0]) * (uv[1][1] - uv[0][1])) *
                         std::abs(t.transform.scale[0] * t.transform.scale[1]);
  const double texels = uv_area * base.width * base.height;
  const double lod = texels > 0.0 ? 0.5 * std::log2(texels / (kSide * kSide)) : 0.0;
  double sum = 0.0;
  int count = 0;
  // The kSide² sub-triangles of a regular subdivision: their centroids, upward and downward ones.
  for (int i = 0; i < kSide; ++i)
    for (int j = 0; i + j < kSide; ++j)
      for (int down = 0; down < 2 && (down == 0 || i + j + 1 < kSide); ++down) {
        const double b1 = (i + (down ? 2.0 : 1.0) / 3.0) / kSide, b2 = (j + (down ? 2.0 : 1.0) / 3.0) / kSide;
        const double b0 = 1.0 - b1 - b2;
        const std::array<double, 2> p{b0 * uv[0][0] + b1 * uv[1][0] + b2 * uv[2][0],
                                      b0 * uv[0][1] + b1 * uv[1][1] + b2 * uv[2][1]};
        const Vec3 rgb = texture_rgb(table, texel_blend(table, id, p, lod));
        sum += rec709_luminance(rgb.x, rgb.y, rgb.z);
        ++count;
      }
  return sum / count;
}

Vec3 texture_rgb(const TextureTable& table, const TexelBlend& blend) {
  Vec3 rgb{};
  for (int k = 0; k < blend.count; ++k) {
    const Vec3f& t = table.rgb[blend.texel[static_cast<std::size_t>(k)]];
    const double w = blend.weight[static_cast<std::size_t>(k)];
    rgb = rgb + Vec3{t.x * w, t.y * w, t.z * w};
  }
  return rgb;
}

}  // namespace bouguer
