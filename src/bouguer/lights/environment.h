#pragma once
// An environment light: a latitude-longitude image of the radiance arriving from every direction,
// infinitely far away. Texel (column i, row j) of a W × H map covers the directions
//   φ = 2π (i + ½) / W − π measured from −z towards +x (so the image centre looks along −z),
//   θ = π (j + ½) / H from +y (the top row is straight up),
// turned about +y by `rotate_deg`. Each texel is constant over its patch (no filtering), which
// makes the sampling density below exact.
//
// Colour: the file's linear Rec.709 RGB (OpenEXR) times `scale`, each texel lifted to a spectrum
// with rgb_to_illuminant (Jakob & Hanika 2019): RGB (1, 1, 1) is D65 at luminance Y = 1.
//
// Sampling: a texel with probability p_t ∝ luminance × sin θ (≈ its solid angle), then uniformly
// in (φ, θ) within it; the solid-angle density is p_t · W H / (2π² sin θ) at the sampled θ.
//
// Lobes: next-event estimation at a non-specular surface (integrators/direct_light.h:
// environment_lobe says which) draws from the map times about the surface's cosine. The image is
// cut into cells (kCellColumns × kCellRows blocks of texels), and the directions of normals into
// kLobeRows × kLobeColumns bins, each a "lobe" (its rows centred on θ = 0, 11.25°, …, 180° from +y
// and its columns on φ = 0, 11.25°, …, so that floors, ceilings and walls facing an axis have a
// lobe of their own); lobe k draws cell c with probability ∝ P_c·g_kc, P_c the cell's share of the
// map's density and g_kc = max(0, n_k·m_c + kLobeSlack) + kLobeFloor (n_k the lobe's normal, m_c
// the cell's power-weighted mean direction; the slack for the normals a lobe stands for and the
// directions a cell spans), then a texel within the cell by the map's own probabilities, then a
// point within the texel as above. Its density is the map's times
// g_kc / Σ_c P_c·g_kc: exact, positive wherever the map's is (the floor), and a function of the
// direction and the lobe alone, so that MIS weighs a BSDF direction against it (the lobe is the
// surface's, kept by the path: integrators/radiance.h). Under the studio map a lit floor's noise
// a sample falls from 0.50 of its mean to 0.35: half the variance (docs/performance.md).
inline constexpr int kCellColumns = 32, kCellRows = 16;
inline constexpr int kLobeRows = 17, kLobeColumns = 32;
inline constexpr double kLobeSlack = 0.1, kLobeFloor = 0.02;
#include <filesystem>
#include <optional>
#include <vector>

#include "bouguer/core/math.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

struct EnvironmentDesc {
  std::filesystem::path file;
  double scale = 1.0;
  double rotate_deg = 0.0;
};

struct EnvironmentMap {
  int width = 0, height = 0;
  std::vector<RgbIlluminantSpectrum> spectra;  // per texel, scale applied
  std::vector<Vec3f> rgb;                      // per texel, linear Rec.709, scale applied (rgb3 mode)
  double rotate_rad = 0.0;
  std::vector<double> row_cdf;     // height + 1 entries, 0 .. 1
  std::vector<double> column_cdf;  // height × (width + 1), each row 0 .. 1
  std::vector<double> texel_probability;
  double total_weight = 0.0;  // Σ luminance × sin θ; 0: nothing to sample
  // The luminance's second moment over the sphere over its mean squared, E[Y²]/E[Y]² by solid
  // angle: 1 for a uniform map, about 12 for a studio's strips and softboxes. It is the variance
  // ratio of a direction drawn uniformly to one drawn by the map, for the map's light alone: how
  // much the map's own sampling has to win (integrators/events.h: the exit guide). 1 where dark.
  double contrast = 1.0;
  // The lobes (above): the cells' first columns and rows (cell_columns + 1, cell_rows + 1 entries),
  // per cell the running sum from 0 of its texel rows' density within its columns (cell (a, b)'s
  // rows + 1 entries from a·(height + cell_rows) + first row + b), per lobe the CDF over the cells
  // (lobes × (cells + 1), cells row by row) and the density's factor per cell (lobes × cells).
  // Empty where the map is black.
  std::vector<int> cell_column_start, cell_row_start;
  std::vector<double> cell_row_cdf, lobe_cdf, lobe_factor;

  int texel(const Vec3& world_direction) const;
  Vec3 direction(double column, double row) const;  // continuous texel coordinates

  struct Sample {
    Vec3 wi;
    double pdf = 0.0;  // per steradian
    int texel = 0;
  };
  std::optional<Sample> sample(double u1, double u2) const;
  double pdf(const Vec3& world_direction) const;
  // The lobe a surface with this normal (unit, on the side the light arrives from) draws from; −1
  // where the map has none (black). sample and pdf with a lobe < 0 are the map's own.
  int lobe(const Vec3& normal) const;
  // (Three numbers: the cell, the row within it, the column within the row; each also places the
  // point within its interval.)
  std::optional<Sample> sample(double u1, double u2, double u3, int lobe) const;
  double pdf(const Vec3& world_direction, int lobe) const;
};

// Reads the image (an Error naming the file when it cannot) and builds the sampling tables.
EnvironmentMap load_environment(const EnvironmentDesc& desc);

// From an image already in memory (width × height, linear Rec.709, rows from the top).
EnvironmentMap make_environment(int width, int height, const std::vector<float>& rgb, double scale,
                                double rotate_deg);

}  // namespace bouguer
