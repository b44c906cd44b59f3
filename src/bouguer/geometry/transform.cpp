#include "bouguer/geometry/transform.h"

#include <cmath>
#include <numbers>

namespace bouguer {

Transform Transform::scale(const Vec3& s) { return {Mat3::diagonal(s), {}}; }

Transform Transform::rotate_deg(double angle_deg, const Vec3& axis) {
  // Rodrigues' rotation formula.
  const Vec3 a = normalize(axis);
  const double th = angle_deg * std::numbers::pi / 180.0, c = std::cos(th), s = std::sin(th), t = 1.0 - c;
  Mat3 r{{{{t * a.x * a.x + c, t * a.x * a.y - s * a.z, t * a.x * a.z + s * a.y},
           {t * a.x * a.y + s * a.z, t * a.y * a.y + c, t * a.y * a.z - s * a.x},
           {t * a.x * a.z - s * a.y, t * a.y * a.z + s * a.x, t * a.z * a.z + c}}}};
  return {r, {}};
}

Transform Transform::translate(const Vec3& t) { return {Mat3::identity(), t}; }

Transform Transform::then(const Transform& next) const {
  return {next.linear * linear, next.linear * translation + next.translation};
}

double Transform::determinant() const {
  const auto& m = linear.m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Mesh transformed(Mesh m, const Transform& t) {
  for (Vec3& p : m.positions) p = t.apply(p);
  if (!m.normals.empty()) {
    // Normals by the inverse transpose: that keeps them on the geometric normal's side, mirrored
    // or not, so the winding below is reversed without flipping them again.
    const Mat3 inv = inverse(t.linear);
    for (Vec3& n : m.normals) {
      const Vec3 tn{inv.m[0][0] * n.x + inv.m[1][0] * n.y + inv.m[2][0] * n.z,
                    inv.m[0][1] * n.x + inv.m[1][1] * n.y + inv.m[2][1] * n.z,
                    inv.m[0][2] * n.x + inv.m[1][2] * n.y + inv.m[2][2] * n.z};
      const double l = length(tn);
      n = l > 0.0 ? tn / l : n;
    }
  }
  // Tangents lie in the surface: they go by the linear part itself. Their sign follows the
  // determinant's: with n by the inverse transpose, cross(n', t') turns against M·b under a mirror.
  const double handedness = t.determinant() < 0.0 ? -1.0 : 1.0;
  for (Tangent& g : m.tangents) {
    const Vec3 d = t.linear * g.direction;
    const double l = length(d);
    g = {l > 0.0 ? d / l : g.direction, g.sign * handedness};
  }
  if (t.determinant() < 0.0)
    for (auto& tri : m.triangles) std::swap(tri[1], tri[2]);
  return m;
}

double Transform::similarity_scale() const {
  const Vec3 a = linear * Vec3{1, 0, 0}, b = linear * Vec3{0, 1, 0}, c = linear * Vec3{0, 0, 1};
  const double scale = length(a), tolerance = 1e-9 * scale;
  const bool similar = scale > 0.0 && std::abs(length(b) - scale) <= tolerance &&
                       std::abs(length(c) - scale) <= tolerance && std::abs(dot(a, b)) <= tolerance * scale &&
                       std::abs(dot(b, c)) <= tolerance * scale && std::abs(dot(a, c)) <= tolerance * scale;
  return similar ? scale : 0.0;
}

}  // namespace bouguer
