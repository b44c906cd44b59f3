#include "bouguer/integrators/manifold.h"

#include <cmath>

namespace bouguer {

std::optional<Vec3> refraction_point(const Vec3& x, const Vec3& p, const Vec3& on_plane, const Vec3& n, double eta_x,
                                     double eta_p) {
  const double hx = dot(x - on_plane, n), hp = dot(p - on_plane, n);
  if (!(hx * hp < 0.0)) return std::nullopt;
  const Vec3 fx = x - n * hx, fp = p - n * hp;  // the feet on the plane
  const Vec3 along = fp - fx;
  const double d = length(along), ax = std::abs(hx), ap = std::abs(hp);
  if (!(d > 1e-15 * (ax + ap))) return fx;  // one above the other: straight through
  const Vec3 u = along / d;
  // g(t) = η_x·t/√(t² + hx²) − η_p·(d − t)/√((d − t)² + hp²): increasing, g(0) < 0 < g(d).
  auto g = [&](double t) {
    return eta_x * t / std::sqrt(t * t + ax * ax) - eta_p * (d - t) / std::sqrt((d - t) * (d - t) + ap * ap);
  };
  auto dg = [&](double t) {
    const double a = t * t + ax * ax, b = (d - t) * (d - t) + ap * ap;
    return eta_x * ax * ax / (a * std::sqrt(a)) + eta_p * ap * ap / (b * std::sqrt(b));
  };
  double lo = 0.0, hi = d, t = 0.5 * d;
  for (int i = 0; i < 100; ++i) {
    const double value = g(t);
    if (value == 0.0) break;
    (value < 0.0 ? lo : hi) = t;
    const double newton = t - value / dg(t);  // safeguarded: bisect where Newton leaves the bracket
    const double next = newton > lo && newton < hi ? newton : 0.5 * (lo + hi);
    const bool done = std::abs(next - t) <= 1e-13 * d || hi - lo <= 1e-13 * d;
    t = next;
    if (done) break;
  }
  return fx + u * t;
}

}  // namespace bouguer
