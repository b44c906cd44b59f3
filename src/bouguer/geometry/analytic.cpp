#include "bouguer/geometry/analytic.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace bouguer {
namespace {

constexpr double kPi = std::numbers::pi;

struct Roots {
  int count = 0;
  double t0 = 0.0, t1 = 0.0;  // t0 ≤ t1
};

// Roots of a·t² + 2b·t + c = 0 with the discriminant given as b² − a·c computed without
// cancellation by the caller (a > 0); the smaller-magnitude root from c/q, as in Numerical Recipes.
Roots quadratic_roots(double a, double b, double c, double discriminant) {
  if (!(discriminant >= 0.0) || !(a > 0.0)) return {};
  const double q = -(b + std::copysign(std::sqrt(discriminant), b));
  if (q == 0.0) return {};
  double t0 = q / a, t1 = c / q;
  if (t0 > t1) std::swap(t0, t1);
  return {2, t0, t1};
}

// Longitude about +y, measured from +x towards −z, in [0, 1).
double longitude(const Vec3& p) {
  const double phi = std::atan2(-p.z, p.x);
  return (phi < 0.0 ? phi + 2.0 * kPi : phi) / (2.0 * kPi);
}

void keep_nearest(std::optional<LocalHit>& best, const LocalHit& h) {
  if (!best || h.t < best->t) best = h;
}

std::optional<LocalHit> hit_sphere(const SphereSurface& s, const Vec3& o, const Vec3& d, double t_min, double t_max) {
  const double a = dot(d, d), b = dot(o, d), r = s.radius_m;
  // b² − a·c as a·(r² − |f|²), f the ray's closest point to the centre: no cancellation when the
  // ray starts far away (pbrt-v4 and Ray Tracing Gems ch. 7 do the same).
  const Vec3 f = o - d * (b / a);
  const Roots roots = quadratic_roots(a, b, dot(o, o) - r * r, a * (r - length(f)) * (r + length(f)));
  for (const double t : {roots.t0, roots.t1}) {
    if (roots.count == 0 || !(t > t_min && t < t_max)) continue;
    LocalHit h;
    h.t = t;
    h.normal = normalize(o + d * t);
    h.point = h.normal * r;
    h.uv = {longitude(h.normal), std::acos(std::clamp(h.normal.y, -1.0, 1.0)) / kPi};
    return h;
  }
  return std::nullopt;
}

// A flat circular cap: the plane coordinate `axis` (1: y, 2: z) equals `level`, radius r.
std::optional<LocalHit> hit_cap(int axis, double level, double r, const Vec3& normal, const Vec3& o, const Vec3& d,
                                double t_min, double t_max) {
  if (d[static_cast<std::size_t>(axis)] == 0.0) return std::nullopt;
  const double t = (level - o[static_cast<std::size_t>(axis)]) / d[static_cast<std::size_t>(axis)];
  if (!(t > t_min && t < t_max)) return std::nullopt;
  Vec3 p = o + d * t;
  p[static_cast<std::size_t>(axis)] = level;
  const double u = p.x, v = axis == 1 ? p.z : p.y;
  if (u * u + v * v > r * r) return std::nullopt;
  LocalHit h;
  h.t = t;
  h.point = p;
  h.normal = normal;
  h.uv = {0.5 + 0.5 * u / r, 0.5 + 0.5 * v / r};
  return h;
}

std::optional<LocalHit> hit_tube(const CylinderSurface& c, const Vec3& o, const Vec3& d, double t_min, double t_max) {
  const double a = d.x * d.x + d.z * d.z, b = o.x * d.x + o.z * d.z, r = c.radius_m;
  if (!(a > 0.0)) return std::nullopt;  // parallel to the axis
  const double fx = o.x - d.x * (b / a), fz = o.z - d.z * (b / a), f = std::hypot(fx, fz);
  const Roots roots = quadratic_roots(a, b, o.x * o.x + o.z * o.z - r * r, a * (r - f) * (r + f));
  for (const double t : {roots.t0, roots.t1}) {
    if (roots.count == 0 || !(t > t_min && t < t_max)) continue;
    const Vec3 p = o + d * t;
    if (p.y < 0.0 || p.y > c.height_m) continue;
    LocalHit h;
    h.t = t;
    h.normal = normalize(Vec3{p.x, 0.0, p.z});
    h.point = {h.normal.x * r, p.y, h.normal.z * r};
    h.uv = {longitude(h.normal), p.y / c.height_m};
    return h;
  }
  return std::nullopt;
}

std::optional<LocalHit> hit_cylinder(const CylinderSurface& c, const Vec3& o, const Vec3& d, double t_min,
                                     double t_max) {
  std::optional<LocalHit> best = hit_tube(c, o, d, t_min, t_max);
  const double limit = best ? best->t : t_max;
  if (auto h = hit_cap(1, 0.0, c.radius_m, {0, -1, 0}, o, d, t_min, limit)) {
    h->part = AnalyticPart::bottom;
    keep_nearest(best, *h);
  }
  if (auto h = hit_cap(1, c.height_m, c.radius_m, {0, 1, 0}, o, d, t_min, best ? best->t : t_max)) {
    h->part = AnalyticPart::top;
    keep_nearest(best, *h);
  }
  return best;
}

}  // namespace

std::optional<LocalHit> intersect_local(const AnalyticSurface& s, const Vec3& o, const Vec3& d, double t_min,
                                        double t_max) {
  struct Visitor {
    const Vec3 &o, &d;
    double t_min, t_max;
    std::optional<LocalHit> operator()(const SphereSurface& x) const { return hit_sphere(x, o, d, t_min, t_max); }
    std::optional<LocalHit> operator()(const CylinderSurface& x) const { return hit_cylinder(x, o, d, t_min, t_max); }
    std::optional<LocalHit> operator()(const DiskSurface& x) const {
      return hit_cap(2, 0.0, x.radius_m, {0, 0, 1}, o, d, t_min, t_max);
    }
  };
  return std::visit(Visitor{o, d, t_min, t_max}, s);
}

double distance_local(const AnalyticSurface& s, const Vec3& p) {
  struct Visitor {
    const Vec3& p;
    double operator()(const SphereSurface& x) const { return std::abs(length(p) - x.radius_m); }
    double operator()(const CylinderSurface& x) const {
      const double rho = std::hypot(p.x, p.z);
      const double side = std::hypot(rho - x.radius_m, p.y - std::clamp(p.y, 0.0, x.height_m));
      const double outside = std::max(rho - x.radius_m, 0.0);
      return std::min({side, std::hypot(p.y, outside), std::hypot(p.y - x.height_m, outside)});
    }
    double operator()(const DiskSurface& x) const {
      return std::hypot(p.z, std::max(std::hypot(p.x, p.y) - x.radius_m, 0.0));
    }
  };
  return std::visit(Visitor{p}, s);
}

Vec3 nearest_local(const AnalyticSurface& s, const Vec3& p) {
  // (x, z) pulled in to radius r at most, or out onto it with `onto`.
  auto radial = [](double x, double z, double r, bool onto) {
    const double rho = std::hypot(x, z);
    if (!(rho > 0.0)) return std::array<double, 2>{onto ? r : 0.0, 0.0};
    const double k = onto ? r / rho : std::min(1.0, r / rho);
    return std::array<double, 2>{x * k, z * k};
  };
  struct Visitor {
    const Vec3& p;
    decltype(radial)& towards;
    Vec3 operator()(const SphereSurface& x) const {
      const double l = length(p);
      return l > 0.0 ? p * (x.radius_m / l) : Vec3{x.radius_m, 0.0, 0.0};
    }
    Vec3 operator()(const CylinderSurface& x) const {
      const auto side = towards(p.x, p.z, x.radius_m, true), cap = towards(p.x, p.z, x.radius_m, false);
      const Vec3 candidates[3] = {{side[0], std::clamp(p.y, 0.0, x.height_m), side[1]},
                                  {cap[0], 0.0, cap[1]},
                                  {cap[0], x.height_m, cap[1]}};
      const Vec3* nearest = &candidates[0];
      for (const Vec3& c : candidates)
        if (length(p - c) < length(p - *nearest)) nearest = &c;
      return *nearest;
    }
    Vec3 operator()(const DiskSurface& x) const {
      const auto in = towards(p.x, p.y, x.radius_m, false);
      return {in[0], in[1], 0.0};
    }
  };
  return std::visit(Visitor{p, radial}, s);
}

std::array<Vec3, 2> local_bounds(const AnalyticSurface& s) {
  struct Visitor {
    std::array<Vec3, 2> operator()(const SphereSurface& x) const {
      const double r = x.radius_m;
      return {Vec3{-r, -r, -r}, Vec3{r, r, r}};
    }
    std::array<Vec3, 2> operator()(const CylinderSurface& x) const {
      return {Vec3{-x.radius_m, 0.0, -x.radius_m}, Vec3{x.radius_m, x.height_m, x.radius_m}};
    }
    std::array<Vec3, 2> operator()(const DiskSurface& x) const {
      return {Vec3{-x.radius_m, -x.radius_m, 0.0}, Vec3{x.radius_m, x.radius_m, 0.0}};
    }
  };
  return std::visit(Visitor{}, s);
}

std::optional<CircularSide> circular_side(const CylinderSurface& c, const Transform& to_world) {
  const Vec3 a = to_world.linear * Vec3{1, 0, 0}, b = to_world.linear * Vec3{0, 1, 0},
             d = to_world.linear * Vec3{0, 0, 1};
  const double scale = length(a), along = length(b), tolerance = 1e-9 * scale;
  if (!(scale > 0.0) || !(along > 0.0) || std::abs(length(d) - scale) > tolerance ||
      std::abs(dot(a, d)) > tolerance * scale || std::abs(dot(a, b)) > 1e-9 * scale * along ||
      std::abs(dot(d, b)) > 1e-9 * scale * along)
    return std::nullopt;
  return CircularSide{to_world.apply(Vec3{}), b / along, c.radius_m * scale};
}

}  // namespace bouguer
