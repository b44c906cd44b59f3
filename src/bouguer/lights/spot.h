#pragma once
// A spot's angular profile: full within falloff_deg of the axis, smoothstep to zero at cone_deg
// (as pbrt). Shared by point spots and spot disks (area emitters with the same profile).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "bouguer/core/math.h"

namespace bouguer {

struct SpotProfile {
  Vec3 axis{0, -1, 0};  // unit, the direction the light goes
  double cone_deg = 30.0, falloff_deg = 25.0;
};

inline double spot_falloff(double cos_theta, double cone_deg, double falloff_deg) {
  const double cos_end = std::cos(cone_deg * std::numbers::pi / 180.0);
  const double cos_start = std::cos(falloff_deg * std::numbers::pi / 180.0);
  if (cos_theta <= cos_end) return 0.0;
  const double t = cos_start > cos_end ? std::clamp((cos_theta - cos_end) / (cos_start - cos_end), 0.0, 1.0) : 1.0;
  return t * t * (3.0 - 2.0 * t);
}

inline double spot_falloff(const SpotProfile& s, const Vec3& direction) {
  return spot_falloff(dot(direction, s.axis), s.cone_deg, s.falloff_deg);
}

}  // namespace bouguer
