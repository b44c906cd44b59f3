#include "bouguer/lights/environment.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bouguer/core/error.h"
#include "bouguer/io/image_io.h"
#include "bouguer/core/limits.h"
#include "bouguer/spectra/color_space.h"
#include "bouguer/spectra/rgb_to_spectrum.h"

namespace bouguer {
namespace {
constexpr double kPi = std::numbers::pi;

// Index of the interval of a CDF (size n + 1, from 0 to 1) that holds u.
int find_interval(const double* cdf, int n, double u) {
  const double* it = std::upper_bound(cdf, cdf + n + 1, u);
  return std::clamp(static_cast<int>(it - cdf) - 1, 0, n - 1);
}

// The direction at θ from +y and φ from −z towards +x (environment.h's convention).
Vec3 lat_long_direction(double theta, double phi) {
  const double s = std::sin(theta);
  return {s * std::sin(phi), std::cos(theta), -s * std::cos(phi)};
}

// Lobe k's normal (without the map's rotation): rows at θ = π·r/(rows − 1), columns at
// φ = 2π·c/columns (environment.h).
Vec3 lobe_normal(int k) {
  const int r = k / kLobeColumns, c = k % kLobeColumns;
  return lat_long_direction(kPi * r / (kLobeRows - 1), 2.0 * kPi * c / kLobeColumns);
}

// The cells and lobes of a map whose texel probabilities are set (environment.h: Lobes).
void build_lobes(EnvironmentMap& m) {
  if (m.total_weight <= 0.0) return;
  const int cx = std::min(kCellColumns, m.width), cy = std::min(kCellRows, m.height);
  const int w = m.width, h = m.height;
  m.cell_column_start.resize(cx + 1);
  m.cell_row_start.resize(cy + 1);
  for (int a = 0; a <= cx; ++a) m.cell_column_start[a] = (a * w + cx - 1) / cx;
  for (int b = 0; b <= cy; ++b) m.cell_row_start[b] = (b * h + cy - 1) / cy;
  m.cell_row_cdf.assign(static_cast<std::size_t>(cx) * (h + cy), 0.0);
  const int cells = cx * cy;
  std::vector<double> mass(cells, 0.0);
  std::vector<Vec3> mean(cells);
  // The texels' middle directions (lat_long_direction, as EnvironmentMap::direction gives them),
  // from one sine and cosine per column and per row (a large map has tens of millions of texels).
  std::vector<double> sin_phi(w), cos_phi(w), sin_theta(h), cos_theta(h);
  for (int i = 0; i < w; ++i) {
    const double phi = 2.0 * kPi * (i + 0.5) / w - kPi + m.rotate_rad;
    sin_phi[i] = std::sin(phi), cos_phi[i] = std::cos(phi);
  }
  for (int j = 0; j < h; ++j) {
    const double theta = kPi * (j + 0.5) / h;
    sin_theta[j] = std::sin(theta), cos_theta[j] = std::cos(theta);
  }
  for (int a = 0; a < cx; ++a)
    for (int b = 0; b < cy; ++b) {
      // (each cell's sum from 0: a dim cell below a bright one keeps its precision)
      const int r0 = m.cell_row_start[b];
      double* cdf = &m.cell_row_cdf[static_cast<std::size_t>(a) * (h + cy) + r0 + b] - r0;
      for (int j = r0; j < m.cell_row_start[b + 1]; ++j) {
        double row = 0.0;
        Vec3 sum;
        for (int i = m.cell_column_start[a]; i < m.cell_column_start[a + 1]; ++i) {
          const double p = m.texel_probability[static_cast<std::size_t>(j) * w + i];
          row += p;
          sum += Vec3{sin_phi[i] * p, 0.0, -cos_phi[i] * p};
        }
        mean[b * cx + a] += Vec3{sum.x * sin_theta[j], row * cos_theta[j], sum.z * sin_theta[j]};
        cdf[j + 1] = cdf[j] + row;
        mass[b * cx + a] += row;
      }
    }
  const int lobes = kLobeRows * kLobeColumns;
  m.lobe_cdf.assign(static_cast<std::size_t>(lobes) * (cells + 1), 0.0);
  m.lobe_factor.assign(static_cast<std::size_t>(lobes) * cells, 0.0);
  std::vector<bool> aimed(cells);  // (a cell whose mean direction has a length: most do)
  for (int c = 0; c < cells; ++c) {
    const double l = length(mean[c]);
    aimed[c] = l > 0.0;
    if (aimed[c]) mean[c] = mean[c] / l;
  }
  for (int k = 0; k < lobes; ++k) {
    const Vec3 n = lobe_normal(k);
    double* cdf = &m.lobe_cdf[static_cast<std::size_t>(k) * (cells + 1)];
    double* factor = &m.lobe_factor[static_cast<std::size_t>(k) * cells];
    for (int c = 0; c < cells; ++c) {
      const double g = (aimed[c] ? std::max(0.0, dot(n, mean[c]) + kLobeSlack) : 0.0) + kLobeFloor;
      factor[c] = g;
      cdf[c + 1] = cdf[c] + mass[c] * g;
    }
    const double total = cdf[cells];  // (≥ kLobeFloor: the masses sum to 1)
    for (int c = 0; c <= cells; ++c) cdf[c] /= total;
    for (int c = 0; c < cells; ++c) factor[c] /= total;
  }
}
}  // namespace

EnvironmentMap make_environment(int width, int height, const std::vector<float>& rgb, double scale,
                                double rotate_deg) {
  EnvironmentMap m;
  m.width = width;
  m.height = height;
  m.rotate_rad = rotate_deg * kPi / 180.0;
  const std::size_t n = static_cast<std::size_t>(width) * height;
  m.spectra.resize(n);
  m.rgb.resize(n);
  m.texel_probability.assign(n, 0.0);
  m.row_cdf.assign(height + 1, 0.0);
  m.column_cdf.assign(static_cast<std::size_t>(height) * (width + 1), 0.0);
  std::vector<double> row_weight(height, 0.0);
  // Luminance of linear Rec.709; negative (out-of-gamut) components do not count.
  auto luminance = [](double r, double g, double b) {
    return rec709_luminance(std::max(0.0, r), std::max(0.0, g), std::max(0.0, b));
  };
  // For the contrast, Σ sin θ, Σ Y·sin θ and Σ Y²·sin θ (the texels' solid angles ∝ sin θ), of the
  // texels as stored: the ratio does not depend on the scale, and floats squared stay finite and
  // nonzero in double wherever the scale would push them.
  double solid_angle = 0.0, first_moment = 0.0, second_moment = 0.0;
  for (int j = 0; j < height; ++j) {
    const double sin_theta = std::sin(kPi * (j + 0.5) / height);
    double* cdf = &m.column_cdf[static_cast<std::size_t>(j) * (width + 1)];
    for (int i = 0; i < width; ++i) {
      const std::size_t t = static_cast<std::size_t>(j) * width + i;
      const Vec3 c{rgb[3 * t] * scale, rgb[3 * t + 1] * scale, rgb[3 * t + 2] * scale};
      m.rgb[t] = {static_cast<float>(c.x), static_cast<float>(c.y), static_cast<float>(c.z)};
      m.spectra[t] = rgb_to_illuminant(c);
      const double y = luminance(c.x, c.y, c.z), w = y * sin_theta;
      const double stored = luminance(rgb[3 * t], rgb[3 * t + 1], rgb[3 * t + 2]);
      solid_angle += sin_theta;
      first_moment += stored * sin_theta;
      second_moment += stored * stored * sin_theta;
      m.texel_probability[t] = w;
      cdf[i + 1] = cdf[i] + w;
    }
    row_weight[j] = cdf[width];
    if (cdf[width] > 0.0)
      for (int i = 1; i <= width; ++i) cdf[i] /= cdf[width];
    m.row_cdf[j + 1] = m.row_cdf[j] + row_weight[j];
  }
  m.total_weight = m.row_cdf[height];
  if (m.total_weight > 0.0 && first_moment > 0.0)
    m.contrast = (second_moment / first_moment) * (solid_angle / first_moment);
  if (m.total_weight > 0.0) {
    for (double& c : m.row_cdf) c /= m.total_weight;
    for (double& p : m.texel_probability) p /= m.total_weight;
  }
  build_lobes(m);
  return m;
}

EnvironmentMap load_environment(const EnvironmentDesc& desc) {
  const Film image = read_image(desc.file);
  if (image.width < 2 || image.height < 2) fail("{}: an environment map needs at least 2 × 2 pixels", desc.file.string());
  // The image readers accept finite values only; the radiance is the texel times the scale, and
  // is bounded here, where it is formed (docs/limits.md).
  if (!std::isfinite(desc.scale)) fail("{}: the environment scale {} is not a finite number", desc.file.string(), desc.scale);
  for (std::size_t i = 0; i < image.rgb.size(); ++i) {
    const double v = static_cast<double>(image.rgb[i]) * desc.scale;
    if (!std::isfinite(v) || std::abs(v) > kMaxEnvironmentRadiance)
      fail("{}: pixel ({}, {}) channel {}: {} × scale {} is beyond the ±{} an environment map may hold (docs/limits.md)",
           desc.file.string(), i / 3 % image.width, i / 3 / image.width, "RGB"[i % 3],
           static_cast<double>(image.rgb[i]), desc.scale, kMaxEnvironmentRadiance);
  }
  return make_environment(image.width, image.height, image.rgb, desc.scale, desc.rotate_deg);
}

int EnvironmentMap::texel(const Vec3& d) const {
  const double phi = std::atan2(d.x, -d.z) - rotate_rad;  // −π .. π before rotation
  double u = phi / (2.0 * kPi) + 0.5;
  u -= std::floor(u);
  const double v = std::acos(std::clamp(d.y, -1.0, 1.0)) / kPi;
  const int i = std::min(static_cast<int>(u * width), width - 1);
  const int j = std::min(static_cast<int>(v * height), height - 1);
  return j * width + i;
}

Vec3 EnvironmentMap::direction(double column, double row) const {
  return lat_long_direction(kPi * row / height, 2.0 * kPi * column / width - kPi + rotate_rad);
}

namespace {
// Where x lies in [lo, hi), in [0, 1] (the middle where rounding left the interval empty).
double place(double x, double lo, double hi) { return hi > lo ? std::clamp((x - lo) / (hi - lo), 0.0, 1.0) : 0.5; }

// The sample at continuous texel coordinates (row, column) inside texel t, drawn with the map's
// texel probability times `factor` (a lobe's; 1: the map's own).
std::optional<EnvironmentMap::Sample> texel_sample(const EnvironmentMap& m, int t, double row, double column,
                                                   double factor) {
  const double sin_theta = std::sin(kPi * row / m.height);
  if (sin_theta <= 0.0) return std::nullopt;
  // Density in image space p_t·W·H; dω = 2π² sin θ du dv.
  return EnvironmentMap::Sample{m.direction(column, row),
                                m.texel_probability[t] * factor * m.width * m.height / (2.0 * kPi * kPi * sin_theta), t};
}
}  // namespace

std::optional<EnvironmentMap::Sample> EnvironmentMap::sample(double u1, double u2) const {
  if (total_weight <= 0.0) return std::nullopt;
  const int j = find_interval(row_cdf.data(), height, u1);
  const double* cdf = &column_cdf[static_cast<std::size_t>(j) * (width + 1)];
  const int i = find_interval(cdf, width, u2);
  const int t = j * width + i;
  if (texel_probability[t] <= 0.0) return std::nullopt;
  // The numbers' positions inside the chosen intervals are again uniform: the point within the
  // texel, uniform in (φ, θ).
  const double row = j + std::clamp((u1 - row_cdf[j]) / (row_cdf[j + 1] - row_cdf[j]), 0.0, 1.0);
  const double column = i + std::clamp((u2 - cdf[i]) / (cdf[i + 1] - cdf[i]), 0.0, 1.0);
  return texel_sample(*this, t, row, column, 1.0);
}

int EnvironmentMap::lobe(const Vec3& n) const {
  if (lobe_cdf.empty()) return -1;
  // The nearest row and column centre.
  const double theta = std::acos(std::clamp(n.y, -1.0, 1.0));
  const int r = std::clamp(static_cast<int>(std::lround(theta / kPi * (kLobeRows - 1))), 0, kLobeRows - 1);
  double u = std::atan2(n.x, -n.z) / (2.0 * kPi);
  u -= std::floor(u);
  const int c = static_cast<int>(std::lround(u * kLobeColumns)) % kLobeColumns;
  return r * kLobeColumns + c;
}

std::optional<EnvironmentMap::Sample> EnvironmentMap::sample(double u1, double u2, double u3, int lobe) const {
  if (lobe < 0 || lobe_cdf.empty()) return sample(u1, u2);
  const int cx = static_cast<int>(cell_column_start.size()) - 1, cy = static_cast<int>(cell_row_start.size()) - 1;
  const int cells = cx * cy;
  const double* cell_cdf = &lobe_cdf[static_cast<std::size_t>(lobe) * (cells + 1)];
  const int c = find_interval(cell_cdf, cells, u1);
  const int a = c % cx, b = c / cx;
  // Within the cell, a row by its density there (u2), then a column of that row by the row's own
  // CDF restricted to the cell's columns (u3); each number's place within its interval places the
  // point within the texel.
  const int r0 = cell_row_start[b], r1 = cell_row_start[b + 1];
  const double* rows = &cell_row_cdf[static_cast<std::size_t>(a) * (height + cy) + r0 + b];
  const double at_row = u2 * rows[r1 - r0];
  const int jj = find_interval(rows, r1 - r0, at_row), j = r0 + jj;
  const double* cdf = &column_cdf[static_cast<std::size_t>(j) * (width + 1)];
  const int i0 = cell_column_start[a], i1 = cell_column_start[a + 1];
  const double at_column = cdf[i0] + u3 * (cdf[i1] - cdf[i0]);
  const int i = i0 + find_interval(cdf + i0, i1 - i0, at_column);
  const int t = j * width + i;
  if (texel_probability[t] <= 0.0) return std::nullopt;
  return texel_sample(*this, t, j + place(at_row, rows[jj], rows[jj + 1]), i + place(at_column, cdf[i], cdf[i + 1]),
                      lobe_factor[static_cast<std::size_t>(lobe) * cells + c]);
}

namespace {
// The map's own density at d, in texel t = m.texel(d).
double texel_density(const EnvironmentMap& m, const Vec3& d, int t) {
  if (m.total_weight <= 0.0) return 0.0;
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - d.y * d.y));
  if (sin_theta <= 0.0) return 0.0;
  return m.texel_probability[t] * m.width * m.height / (2.0 * kPi * kPi * sin_theta);
}
}  // namespace

double EnvironmentMap::pdf(const Vec3& d, int lobe) const {
  if (lobe < 0 || lobe_cdf.empty()) return pdf(d);
  const int cx = static_cast<int>(cell_column_start.size()) - 1, cy = static_cast<int>(cell_row_start.size()) - 1;
  const int t = texel(d);
  const int i = t % width, j = t / width;
  // (The cell of a column or row: the last start at or before it.)
  const int a = static_cast<int>(std::upper_bound(cell_column_start.begin(), cell_column_start.end(), i) -
                                 cell_column_start.begin()) - 1;
  const int b = static_cast<int>(std::upper_bound(cell_row_start.begin(), cell_row_start.end(), j) -
                                 cell_row_start.begin()) - 1;
  return texel_density(*this, d, t) * lobe_factor[static_cast<std::size_t>(lobe) * (cx * cy) + b * cx + a];
}

double EnvironmentMap::pdf(const Vec3& d) const { return texel_density(*this, d, texel(d)); }

}  // namespace bouguer
