#pragma once
// Textures as flat render data: every texture is an id into one TextureTable, which holds each
// texture's MIP pyramid (level 0 the image, each next level a 2 × 2 box average, down to 1 × 1)
// as linear Rec.709 texels, and for reflectance textures each texel's RGB lifted to a spectrum
// (the sigmoid polynomial of spectra/rgb_to_spectrum.h), so a lookup blends spectra, not colours.
//
// Lookup: texture coordinates (u, v), v = 0 at the image's bottom row (the OBJ and quad
// convention; the glTF importer flips its v), outside [0, 1) wrapped per axis as the texture's
// sampler says (repeat by default; clamp to the edge, or mirrored repeat), at every level alike.
// Bilinear within a level,
// linear between the two levels around the level of detail (trilinear). The level of detail comes
// from a ray cone (Akenine-Möller et al., "Texture Level of Detail Strategies for Real-Time Ray
// Tracing", Ray Tracing Gems, 2019): the cone's width at the hit over |cos θ| is the footprint's
// extent in metres; the triangle's texel-to-area ratio turns it into texels, and log2 of that is
// the level (0: the image itself, bilinear, which is also what a path without a cone reads).
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bouguer/core/math.h"
#include "bouguer/geometry/analytic.h"
#include "bouguer/geometry/mesh.h"
#include "bouguer/io/texture_image.h"
#include "bouguer/spectra/sampled_spectrum.h"
#include "bouguer/spectra/sampled_wavelengths.h"

namespace bouguer {

// KHR_texture_transform: uv' = T · R · S · uv, with the rotation counter-clockwise in the
// texture's own (glTF, v down) coordinates. Identity by default.
struct UvTransform {
  std::array<double, 2> offset{0.0, 0.0};
  double rotation_rad = 0.0;
  std::array<double, 2> scale{1.0, 1.0};
};

// The transform Bouguer's JSON gives (docs/scene-format.md), in Bouguer's own v-up coordinates:
// uv' = offset + R(rotation) · (scale ⊙ uv), R counter-clockwise in the (u, v) plane as the image
// is seen. Returned as the same map in glTF's v-down convention: the angle and scale carry over,
// the offset becomes (o_u − sin θ·s_v, 1 − cos θ·s_v − o_v).
UvTransform uv_transform_v_up(std::array<double, 2> offset, double rotation_rad, std::array<double, 2> scale);

// How texture coordinates outside [0, 1) reach the image, per axis (glTF's sampler wrapS and
// wrapT): repeat, clamp to the edge texel (CLAMP_TO_EDGE), or mirrored repeat (every other tile
// mirrored). Applied to the texel indices the bilinear filter reads, so at an edge under clamp or
// mirror the filter blends the edge texel with itself.
enum class TextureWrap { repeat, clamp, mirror };

struct TextureSampler {
  std::array<TextureWrap, 2> wrap{TextureWrap::repeat, TextureWrap::repeat};  // along u (glTF's s), v (t)
  // glTF's magFilter NEAREST: where the footprint is under a texel (level of detail ≤ 0, and every
  // lookup without a ray cone) the nearest level-0 texel instead of the bilinear blend.
  bool nearest_magnification = false;
};

// How texels are read: a reflectance (sRGB-decoded where the file is sRGB, each channel in [0, 1],
// lifted to a spectrum), a colour used as it is (sRGB-decoded), or data (roughness, metalness:
// the values as stored).
enum class TextureUse { reflectance, colour, data };

struct TextureLevel {
  int width = 0, height = 0;
  std::size_t first = 0;  // index of its top-left texel in TextureTable::rgb
};

struct TextureEntry {
  int first_level = 0, level_count = 0;
  UvTransform transform;
  TextureSampler sampler;
};

struct TextureTable {
  std::vector<TextureEntry> textures;
  std::vector<TextureLevel> levels;
  std::vector<Vec3f> rgb;                       // linear, rows from the bottom, every level
  std::vector<std::array<float, 3>> sigmoid;    // reflectance textures: c0, c1, c2 per texel
};

// Adds the image's pyramid; returns its id.
int add_texture(TextureTable& table, const TextureImage& image, TextureUse use, const UvTransform& transform = {},
                const TextureSampler& sampler = {});

// The index in [0, n) that texel index i of a row or column of n texels reads under `wrap`.
std::size_t wrapped_index(long i, int n, TextureWrap wrap);

// Texture coordinates (u, v), v up, as texture `id` reads them: its transform applied (no wrap).
std::array<double, 2> texture_coordinates(const TextureTable& table, int id, std::array<double, 2> uv);

// The texels a lookup blends (up to 4 in each of 2 levels) and their weights (summing to 1).
struct TexelBlend {
  std::array<std::size_t, 8> texel{};
  std::array<float, 8> weight{};
  int count = 0;
};
TexelBlend texel_blend(const TextureTable& table, int id, std::array<double, 2> uv, double level_of_detail);

// The level of detail of a cone of width cone_width_m (metres, at the hit) meeting triangle
// `primitive` of `mesh` (which has UVs) at |cos θ| = cos_theta: log2 of the footprint in texels
// of level 0; −∞ for a width of 0 (the finest level).
double texture_level_of_detail(const TextureTable& table, int id, const Mesh& mesh, std::uint32_t primitive,
                               double cone_width_m, double cos_theta);
// The same on an analytic surface, whose texel density follows from its UV map (geometry/analytic.h)
// at the hit's part and UV, its size scaled by the transform's mean linear scale.
double texture_level_of_detail(const TextureTable& table, int id, const AnalyticShape& shape, std::uint32_t part,
                               std::array<double, 2> uv, double cone_width_m, double cos_theta);

Vec3 texture_rgb(const TextureTable& table, const TexelBlend& blend);

// The mean Rec.709 luminance of texture `id` over the triangle with these corner UVs: 64 points of
// an even barycentric grid, each read at the level whose texels are about the grid's spacing (so
// the grid sees every texel through the pyramid's box filter).
double texture_mean_luminance(const TextureTable& table, int id, const std::array<std::array<double, 2>, 3>& uv);

// A reflectance texture's spectrum at the path's wavelengths: the blend of its texels' spectra.
template <std::size_t N>
SampledSpectrum<N> texture_reflectance(const TextureTable& table, const TexelBlend& blend,
                                       const SampledWavelengths<N>& w) {
  SampledSpectrum<N> s;
  for (int k = 0; k < blend.count; ++k) {
    const auto& c = table.sigmoid[blend.texel[static_cast<std::size_t>(k)]];
    const float weight = blend.weight[static_cast<std::size_t>(k)];
    for (std::size_t i = 0; i < N; ++i) {
      const double x = (c[0] * w.nm[i] + c[1]) * w.nm[i] + c[2];
      s[i] += weight * static_cast<float>(0.5 + x / (2.0 * std::sqrt(1.0 + x * x)));
    }
  }
  return s;
}

}  // namespace bouguer
