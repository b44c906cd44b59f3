#include "bouguer/spectra/color_space.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bouguer/spectra/cie.h"

namespace bouguer {
namespace {

bool same_white(Chromaticity a, Chromaticity b) { return a.x == b.x && a.y == b.y; }

Mat3 adaptation_from_d65(const ColorSpace& cs) {
  if (same_white(cs.white, kD65White)) return Mat3::identity();
  return bradford_adaptation(xy_to_xyz(kD65White.x, kD65White.y), xy_to_xyz(cs.white.x, cs.white.y));
}

}  // namespace

Mat3 rgb_to_xyz_matrix(const ColorSpace& cs) {
  // Columns are the primaries' XYZ, each scaled so that RGB (1,1,1) lands on the white at Y = 1.
  const Mat3 primaries = Mat3::from_columns(xy_to_xyz(cs.red.x, cs.red.y), xy_to_xyz(cs.green.x, cs.green.y),
                                            xy_to_xyz(cs.blue.x, cs.blue.y));
  const Vec3 s = inverse(primaries) * xy_to_xyz(cs.white.x, cs.white.y);
  return primaries * Mat3::diagonal(s);
}

Mat3 xyz_to_rgb_matrix(const ColorSpace& cs) { return inverse(rgb_to_xyz_matrix(cs)); }

Mat3 bradford_adaptation(const Vec3& source_white_xyz, const Vec3& target_white_xyz) {
  // Lam (1985) / Bradford cone response matrix.
  constexpr Mat3 kBradford{{{{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}}};
  const Vec3 src = kBradford * source_white_xyz;
  const Vec3 dst = kBradford * target_white_xyz;
  return inverse(kBradford) * Mat3::diagonal({dst.x / src.x, dst.y / src.y, dst.z / src.z}) * kBradford;
}

Vec3 xyz_to_linear_rgb(const ColorSpace& cs, const Vec3& xyz) {
  return xyz_to_rgb_matrix(cs) * (adaptation_from_d65(cs) * xyz);
}

Vec3 linear_rgb_to_xyz(const ColorSpace& cs, const Vec3& rgb) {
  return inverse(adaptation_from_d65(cs)) * (rgb_to_xyz_matrix(cs) * rgb);
}

double srgb_encode(double linear) {
  if (linear <= 0.0031308) return 12.92 * linear;
  return 1.055 * std::pow(linear, 1.0 / 2.4) - 0.055;
}

double srgb_decode(double encoded) {
  if (encoded <= 0.04045) return encoded / 12.92;
  return std::pow((encoded + 0.055) / 1.055, 2.4);
}

unsigned char srgb_encode_8bit(double linear) {
  const double clamped = std::isnan(linear) ? 0.0 : std::clamp(linear, 0.0, 1.0);
  return static_cast<unsigned char>(std::lround(srgb_encode(clamped) * 255.0));
}

std::string srgb_hex(const Vec3& c) {
  return fmt::format("#{:02X}{:02X}{:02X}", srgb_encode_8bit(c.x), srgb_encode_8bit(c.y), srgb_encode_8bit(c.z));
}

}  // namespace bouguer
