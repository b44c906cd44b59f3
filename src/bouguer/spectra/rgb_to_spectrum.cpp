#include "bouguer/spectra/rgb_to_spectrum.h"

#include <algorithm>
#include <cmath>

#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/rgb_to_spectrum_layout.h"

namespace bouguer {
namespace {

constexpr int kRes = kRgbTableResolution;

// The coefficients for t = (λ − 360) / 470 rewritten for λ in nm.
SigmoidPolynomial to_nanometres(double a, double b, double c) {
  const double s = 1.0 / (kLambdaMaxNm - kLambdaMinNm), o = kLambdaMinNm;
  return {a * s * s, b * s - 2.0 * a * o * s * s, a * o * o * s * s - b * o * s + c};
}

}  // namespace

SigmoidPolynomial rgb_to_reflectance(const Vec3& linear_rec709) {
  const double rgb[3] = {std::clamp(linear_rec709.x, 0.0, 1.0), std::clamp(linear_rec709.y, 0.0, 1.0),
                         std::clamp(linear_rec709.z, 0.0, 1.0)};
  // Greys have an exact constant solution: S(c) = v for c = (v − 1/2) / √(v (1 − v)).
  if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
    const double v = rgb[0];
    if (v <= 0.0) return {0.0, 0.0, -1e12};
    if (v >= 1.0) return {0.0, 0.0, 1e12};
    return {0.0, 0.0, (v - 0.5) / std::sqrt(v * (1.0 - v))};
  }
  const int l = static_cast<int>(std::max_element(rgb, rgb + 3) - rgb);
  const double z = rgb[l];
  const double x = rgb[(l + 1) % 3] / z * (kRes - 1), y = rgb[(l + 2) % 3] / z * (kRes - 1);
  const int xi = std::min(static_cast<int>(x), kRes - 2), yi = std::min(static_cast<int>(y), kRes - 2);
  // The z slice: the last node at or below z.
  int zi = 0;
  while (zi < kRes - 2 && rgb_table_z_node(zi + 1) <= z) ++zi;
  const double z0 = rgb_table_z_node(zi), z1 = rgb_table_z_node(zi + 1);
  const double fx = x - xi, fy = y - yi, fz = (z - z0) / (z1 - z0);
  double c[3] = {0.0, 0.0, 0.0};
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const double w = (dx ? fx : 1.0 - fx) * (dy ? fy : 1.0 - fy) * (dz ? fz : 1.0 - fz);
        const std::size_t at =
            ((static_cast<std::size_t>(l * kRes + zi + dz) * kRes + yi + dy) * kRes + xi + dx) * 3;
        for (int q = 0; q < 3; ++q) c[q] += w * data::kRgbToSpectrumCoefficients[at + q];
      }
  return to_nanometres(c[0], c[1], c[2]);
}

RgbIlluminantSpectrum rgb_to_illuminant(const Vec3& linear_rec709) {
  const Vec3 rgb{std::max(0.0, linear_rec709.x), std::max(0.0, linear_rec709.y), std::max(0.0, linear_rec709.z)};
  const double m = std::max({rgb.x, rgb.y, rgb.z});
  if (m <= 0.0) return {0.0, {0.0, 0.0, -1e12}};
  const double scale = 2.0 * m;
  return {scale, rgb_to_reflectance(rgb / scale)};
}

}  // namespace bouguer
