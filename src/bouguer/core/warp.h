#pragma once
// Warps of the unit square onto the domains that samplers draw directions and points from; shared
// by the BSDFs (materials/) and the lights (lights/), so they live below both.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "bouguer/core/math.h"

namespace bouguer {

// Cosine-weighted hemisphere about +z (Malley's method): density cos θ / π.
inline Vec3 sample_cosine_hemisphere(double u1, double u2) {
  const double r = std::sqrt(u1), phi = 2.0 * std::numbers::pi * u2;
  return {r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0, 1.0 - u1))};
}

}  // namespace bouguer
