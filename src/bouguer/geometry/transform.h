#pragma once
// Affine transforms of points: p' = linear · p + translation.
#include "bouguer/core/math.h"
#include "bouguer/geometry/mesh.h"

namespace bouguer {

struct Transform {
  Mat3 linear = Mat3::identity();
  Vec3 translation{};

  static Transform scale(const Vec3& s);
  static Transform rotate_deg(double angle_deg, const Vec3& axis);
  static Transform translate(const Vec3& t);

  Vec3 apply(const Vec3& p) const { return linear * p + translation; }
  // This transform followed by `next`.
  Transform then(const Transform& next) const;
  double determinant() const;
  // The factor every length is scaled by where the transform is a similarity (a rotation or
  // mirror, a uniform scale and a translation: a sphere stays a sphere), to 1e-9; 0 otherwise.
  double similarity_scale() const;
};

// Applies t to every vertex; a mirroring transform (negative determinant) also reverses the
// winding, so outward faces stay outward.
Mesh transformed(Mesh m, const Transform& t);

}  // namespace bouguer
