#include "bouguer/materials/microfacet.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace bouguer {

double GgxDistribution::D(const Vec3& wm) const {
  const double cos2 = wm.z * wm.z;
  if (cos2 <= 0.0) return 0.0;
  const double tan2 = (1.0 - cos2) / cos2;
  const double a2 = alpha * alpha;
  const double e = 1.0 + tan2 / a2;
  return 1.0 / (std::numbers::pi * a2 * cos2 * cos2 * e * e);
}

double GgxDistribution::lambda(const Vec3& w) const {
  const double cos2 = w.z * w.z;
  if (cos2 <= 0.0) return 1e30;
  const double tan2 = std::max(0.0, 1.0 - cos2) / cos2;
  return (std::sqrt(1.0 + alpha * alpha * tan2) - 1.0) / 2.0;
}

double GgxDistribution::D_visible(const Vec3& wo, const Vec3& wm) const {
  const double c = std::abs(wo.z);
  if (c == 0.0) return 0.0;
  return G1(wo) * std::max(0.0, dot(wo, wm)) * D(wm) / c;
}

Vec3 GgxDistribution::sample_visible_normal(const Vec3& wo, double u1, double u2) const {
  // Stretch to the unit-roughness configuration, sample the visible hemisphere there, unstretch.
  const Vec3 wh = normalize(Vec3{alpha * wo.x, alpha * wo.y, wo.z});
  const double len2 = wh.x * wh.x + wh.y * wh.y;
  const Vec3 t1 = len2 > 0.0 ? Vec3{-wh.y, wh.x, 0.0} / std::sqrt(len2) : Vec3{1, 0, 0};
  const Vec3 t2 = cross(wh, t1);
  const double r = std::sqrt(u1), phi = 2.0 * std::numbers::pi * u2;
  double p1 = r * std::cos(phi), p2 = r * std::sin(phi);
  const double s = 0.5 * (1.0 + wh.z);
  p2 = (1.0 - s) * std::sqrt(std::max(0.0, 1.0 - p1 * p1)) + s * p2;
  const Vec3 nh = t1 * p1 + t2 * p2 + wh * std::sqrt(std::max(0.0, 1.0 - p1 * p1 - p2 * p2));
  return normalize(Vec3{alpha * nh.x, alpha * nh.y, std::max(1e-12, nh.z)});
}

}  // namespace bouguer
