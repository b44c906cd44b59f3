#pragma once
// An orthonormal frame around a unit normal, for the BSDFs' local coordinates (z = normal).
#include <cmath>

#include "bouguer/core/math.h"

namespace bouguer {

struct Frame {
  Vec3 s, t, n;

  // Duff et al. 2017, "Building an Orthonormal Basis, Revisited".
  explicit Frame(const Vec3& normal) : n(normal) {
    const double sign = std::copysign(1.0, n.z);
    const double a = -1.0 / (sign + n.z), b = n.x * n.y * a;
    s = {1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x};
    t = {b, sign + n.y * n.y * a, -n.y};
  }
  Vec3 to_local(const Vec3& v) const { return {dot(v, s), dot(v, t), dot(v, n)}; }
  Vec3 to_world(const Vec3& v) const { return s * v.x + t * v.y + n * v.z; }
};

}  // namespace bouguer
