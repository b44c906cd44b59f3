#include "bouguer/integrators/manifold.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "bouguer/core/frame.h"

namespace bouguer {

namespace {

// The arc a sphere's or a cylinder's solve scans, in the plane's angle φ: all of [−φmax, φmax] in
// `intervals`, or, given the point a solution was at for a neighbouring vertex, its window around
// that point's angle in two.
struct ScanRange {
  double from, to;
  int intervals;
};
ScanRange scan_range(double phi_max, const NearSolution* near, const Vec3& centre, const Vec3& e1, const Vec3& e2,
                     int intervals) {
  if (!near) return {-phi_max, phi_max, intervals};
  const double phi = std::atan2(dot(near->point - centre, e2), dot(near->point - centre, e1));
  return {std::max(-phi_max, phi - near->window_rad), std::min(phi_max, phi + near->window_rad), 2};
}

// The root of f in [lo, hi], where f(lo) and f(hi) have opposite signs (neither 0): the Illinois
// method (regula falsi that halves the value kept at the end that stays), to 1e-14 of a radian in
// about ten steps where bisection took 47; nothing where f is undefined at a step (`f` returns
// NaN there: a sliver of total internal reflection inside the bracket, no root of this branch).
// |(x, y)| of values near 1 (no need of hypot's care, at a tenth of its cost).
inline double norm2(double x, double y) { return std::sqrt(x * x + y * y); }

template <typename F>
std::optional<double> bracketed_root(F f, double lo, double hi, double f_lo, double f_hi) {
  int kept = 0;  // which end stayed at the last step: −1 lo, +1 hi
  for (int k = 0; k < 100 && hi - lo > 1e-14; ++k) {
    double r = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
    if (!(r > lo && r < hi)) r = 0.5 * (lo + hi);
    const double f_r = f(r);
    if (std::isnan(f_r)) return std::nullopt;
    if (f_r == 0.0) return r;
    if ((f_r < 0.0) == (f_hi < 0.0)) {
      hi = r, f_hi = f_r;
      if (kept == -1) f_lo *= 0.5;
      kept = -1;
    } else {
      lo = r, f_lo = f_r;
      if (kept == 1) f_hi *= 0.5;
      kept = 1;
    }
  }
  return 0.5 * (lo + hi);
}

// The minimum of f over [a, b]: golden-section steps until the bracket is a hundredth of the
// interval (the probes a golden-section search makes, which follow a narrow dip beside a wide bowl
// as far as it did), then Brent's method within that bracket (its parabola's vertex where the
// parabola through the three best probes can be trusted); stopping once f is negative at a probe
// (a sign change found), at a NaN, or once the minimum is placed to about 2e-9 of a radian: closer,
// the parabola's vertex and f's rounding decide nothing more about the minimum's sign. A golden-
// section search to the end took all of its 60 steps wherever no pair lay (always, on a glass
// rod's shadow): 62 evaluations, against about 22. Brent's method from the start took 14, but
// settled in the bowl and missed the dip in 3 % of a synthetic family of such functions where the
// golden-section search found it; these steps miss none of them. Returns the best probe and the
// last one.
struct MinimumProbes {
  double x1, f1, x2, f2;
  double at() const { return f1 <= f2 ? x1 : x2; }
  double value() const { return std::min(f1, f2); }
};
template <typename F>
MinimumProbes find_minimum(F f, double a, double b) {
  const double ratio = 0.5 * (std::sqrt(5.0) - 1.0), width = b - a;
  double x1 = b - ratio * (b - a), x2 = a + ratio * (b - a);
  double f1 = f(x1), f2 = f(x2);
  while (f1 > 0.0 && f2 > 0.0 && b - a > 0.01 * width) {
    if (f1 < f2) {
      b = x2, x2 = x1, f2 = f1, x1 = b - ratio * (b - a), f1 = f(x1);
    } else {
      a = x1, x1 = x2, f1 = f2, x2 = a + ratio * (b - a), f2 = f(x2);
    }
  }
  if (!(f1 > 0.0) || !(f2 > 0.0)) return {x1, f1, x2, f2};
  // Brent's method in [a, b]: x the best probe, w the second best, v the one before; `step` the
  // last step, `before` the one before it.
  const double golden = 1.0 - ratio;
  double x = f1 <= f2 ? x1 : x2, w = f1 <= f2 ? x2 : x1, v = w;
  double fx = std::min(f1, f2), fw = std::max(f1, f2), fv = fw;
  double u = x, fu = fx;  // the last probe
  double step = 0.0, before = 0.0;
  for (int k = 0; k < 100 && fu > 0.0; ++k) {
    const double middle = 0.5 * (a + b), tol = 1e-9 * (1.0 + std::abs(x)), tol2 = 2.0 * tol;
    if (std::abs(x - middle) <= tol2 - 0.5 * (b - a)) break;
    bool parabolic = false;
    if (std::abs(before) > tol) {
      double r = (x - w) * (fx - fv), q = (x - v) * (fx - fw), p = (x - v) * q - (x - w) * r;
      q = 2.0 * (q - r);
      if (q > 0.0) p = -p;
      q = std::abs(q);
      const double older = before;
      before = step;
      if (std::abs(p) < std::abs(0.5 * q * older) && p > q * (a - x) && p < q * (b - x)) {
        step = p / q;
        const double at_u = x + step;
        if (at_u - a < tol2 || b - at_u < tol2) step = x < middle ? tol : -tol;
        parabolic = true;
      }
    }
    if (!parabolic) {
      before = (x < middle ? b : a) - x;
      step = golden * before;
    }
    u = x + (std::abs(step) >= tol ? step : std::copysign(tol, step));
    fu = f(u);
    if (std::isnan(fu)) break;
    if (fu <= fx) {
      (u < x ? b : a) = x;
      v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu <= fw || w == x) {
        v = w, fv = fw, w = u, fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u, fv = fu;
      }
    }
  }
  return {x, fx, u, fu};
}

// The roots of a solve's slope (the derivative of the optical length along an arc) over the arc's
// angles [from, to]: its sign changes between `intervals` + 1 points, whose (cos, sin) come by
// rotation (96 steps lose no more than 1e-14; scan_cs(cos, sin) at them: its sign is all that is
// read), each refined by the Illinois method (slope_cs at (cos φ, sin φ)); root(φ) for each, at
// most `most`. With `pairs`, a scan point where |slope| is smaller than at both its neighbours,
// all three of one sign, may hide two roots close together (a caustic's fold between them): the
// slope's extremum over the two intervals is found by find_minimum, and where its sign
// differs, each side's root is refined.
template <typename ScanCS, typename SlopeCS, typename Root>
void scan_roots(ScanCS scan_cs, SlopeCS slope_cs, double from, double to, int intervals, int most, Root root,
                bool pairs = false) {
  auto slope = [&](double phi) { return slope_cs(std::cos(phi), std::sin(phi)); };
  double lo = from, g_lo = scan_cs(std::cos(from), std::sin(from));
  double before = lo, g_before = 0.0;  // the scan point before lo (none yet: 0)
  const double step = (to - from) / intervals, cos_step = std::cos(step), sin_step = std::sin(step);
  double c = std::cos(from), sn = std::sin(from);
  int found = 0;
  auto refine = [&](double a, double b, double g_a, double g_b) {
    if (found >= most) return;
    if (const std::optional<double> phi = bracketed_root(slope, a, b, g_a, g_b)) {
      root(*phi);
      ++found;
    }
  };
  for (int i = 1; i <= intervals && found < most; ++i) {
    const double hi = from + (to - from) * i / intervals;
    const double c_next = c * cos_step - sn * sin_step;
    sn = sn * cos_step + c * sin_step, c = c_next;
    const double g_hi = scan_cs(c, sn);
    if (g_lo == 0.0 || (g_hi != 0.0 && (g_lo < 0.0) != (g_hi < 0.0))) {
      if (g_lo == 0.0) {
        root(lo);
        ++found;
      } else {
        refine(lo, hi, g_lo, g_hi);
      }
    } else if (pairs && g_before != 0.0 && (g_before < 0.0) == (g_lo < 0.0) && (g_lo < 0.0) == (g_hi < 0.0) &&
               std::abs(g_lo) < std::abs(g_before) && std::abs(g_lo) < std::abs(g_hi)) {
      // The extremum of sign·slope over [before, hi] (stopping once it changes sign).
      const double sign = g_lo < 0.0 ? -1.0 : 1.0;
      const MinimumProbes g = find_minimum([&](double phi) { return sign * slope(phi); }, before, hi);
      const double m = g.at(), f_m = g.value();
      if (f_m < 0.0) {  // two roots, either side of the extremum
        refine(before, m, g_before, sign * f_m);
        refine(m, hi, sign * f_m, g_hi);
      }
    }
    // (A root exactly at hi is taken in the next interval, as its lo.)
    before = lo, g_before = g_lo;
    lo = hi, g_lo = g_hi;
  }
}

// The root t of η_a·t/√(t² + a²) = η_b·(d − t)/√((d − t)² + b²) on [0, d] (a, b > 0: two points at
// heights a and b on either side of a line, their feet d apart; t from the first foot): unique,
// since the difference of the two sides grows monotonically; Newton safeguarded by bisection, to
// `tolerance`·d (1e-13 by default), from `start`·d (a neighbour's root saves most of the steps).
double snell_split(double d, double a, double b, double eta_a, double eta_b, double start = 0.5,
                   double tolerance = 1e-13) {
  if (!(d > 1e-15 * (a + b))) return 0.0;  // one above the other: straight through
  auto g = [&](double t) {
    return eta_a * t / std::sqrt(t * t + a * a) - eta_b * (d - t) / std::sqrt((d - t) * (d - t) + b * b);
  };
  auto dg = [&](double t) {
    const double p = t * t + a * a, q = (d - t) * (d - t) + b * b;
    return eta_a * a * a / (p * std::sqrt(p)) + eta_b * b * b / (q * std::sqrt(q));
  };
  double lo = 0.0, hi = d, t = std::clamp(start, 0.0, 1.0) * d;
  for (int i = 0; i < 100; ++i) {
    const double value = g(t);
    if (value == 0.0) break;
    (value < 0.0 ? lo : hi) = t;
    const double newton = t - value / dg(t);  // safeguarded: bisect where Newton leaves the bracket
    const double next = newton > lo && newton < hi ? newton : 0.5 * (lo + hi);
    const bool done = std::abs(next - t) <= tolerance * d || hi - lo <= tolerance * d;
    t = next;
    if (done) break;
  }
  return t;
}

}  // namespace

std::optional<Vec3> refraction_point(const Vec3& x, const Vec3& p, const Vec3& on_plane, const Vec3& n, double eta_x,
                                     double eta_p) {
  const double hx = dot(x - on_plane, n), hp = dot(p - on_plane, n);
  if (!(hx * hp < 0.0)) return std::nullopt;
  const Vec3 fx = x - n * hx, fp = p - n * hp;  // the feet on the plane
  const Vec3 along = fp - fx;
  const double d = length(along), ax = std::abs(hx), ap = std::abs(hp);
  if (!(d > 1e-15 * (ax + ap))) return fx;  // one above the other: straight through
  return fx + (along / d) * snell_split(d, ax, ap, eta_x, eta_p);
}

SphereRefraction sphere_refraction_points(const Vec3& inner, const Vec3& outer, const Vec3& centre, double radius_m,
                                          double eta_inner, double eta_outer, const NearSolution* near) {
  SphereRefraction out;
  // In the plane of the centre and both points, in units of the radius: the outer point at (b, 0)
  // on e1, the inner one at (a1, a2) with a2 ≥ 0, y(φ) = (cos φ, sin φ).
  const Vec3 to_outer = outer - centre, to_inner = inner - centre;
  const double b = length(to_outer) / radius_m;
  if (!(b > 1.0) || !(length(to_inner) < radius_m)) return out;
  const Vec3 e1 = to_outer / (b * radius_m);
  const Vec3 across = to_inner - e1 * dot(to_inner, e1);
  const double across_m = length(across);
  // On the line through the centre and the outer point, every plane through it holds the paths:
  // the one along the line is the solution that stays (the others form a ring, met with
  // probability 0).
  const Vec3 e2 = across_m > 1e-12 * radius_m ? across / across_m : Frame(e1).s;
  const double a1 = dot(to_inner, e1) / radius_m, a2 = dot(to_inner, e2) / radius_m;
  // The derivative of the optical length along the circle: η_i·(tangential part of the direction
  // inner → y) − η_o·(that of y → outer).
  auto slope_cs = [&](double c, double s) {
    const double to_y = norm2(c - a1, s - a2), from_y = norm2(b - c, s);
    return eta_inner * (a1 * s - a2 * c) / to_y + eta_outer * b * s / from_y;
  };
  // The arc the outer point sees: cos φ > 1/b.
  const double phi_max = std::acos(1.0 / b) * (1.0 - 1e-12);
  const auto [from, to, intervals] = scan_range(phi_max, near, centre, e1, e2, 48);
  scan_roots(slope_cs, slope_cs, from, to, intervals, static_cast<int>(out.points.size()), [&](double phi) {
    out.points[static_cast<std::size_t>(out.count++)] = centre + (e1 * std::cos(phi) + e2 * std::sin(phi)) * radius_m;
  }, true);
  return out;
}

SphereRefraction sphere_refraction_towards(const Vec3& inner, const Vec3& to_lamp, const Vec3& centre, double radius_m,
                                           double eta_inner, double eta_outer, const NearSolution* near) {
  SphereRefraction out;
  // As sphere_refraction_points with the outer point infinitely far along e1 = to_lamp: in the
  // plane of the centre, the inner point and that direction (the normal at a crossing passes
  // through the centre, so Snell's law keeps the path in it), the optical length
  // η_i·|inner − y| − η_o·y·e1 (a plane wave's phase) is stationary along the circle where its
  // slope η_i·(a1·sin φ − a2·cos φ)/|inner − y| + η_o·sin φ is 0; its arc the half of the sphere
  // whose outward normal has a part along e1.
  const Vec3 to_inner = inner - centre;
  if (!(length(to_inner) < radius_m)) return out;
  const Vec3 e1 = to_lamp;
  const Vec3 across = to_inner - e1 * dot(to_inner, e1);
  const double across_m = length(across);
  const Vec3 e2 = across_m > 1e-12 * radius_m ? across / across_m : Frame(e1).s;
  const double a1 = dot(to_inner, e1) / radius_m, a2 = dot(to_inner, e2) / radius_m;
  auto slope_cs = [&](double c, double s) {
    return eta_inner * (a1 * s - a2 * c) / norm2(c - a1, s - a2) + eta_outer * s;
  };
  const double phi_max = 0.5 * std::numbers::pi * (1.0 - 1e-12);
  const auto [from, to, intervals] = scan_range(phi_max, near, centre, e1, e2, 48);
  scan_roots(slope_cs, slope_cs, from, to, intervals, static_cast<int>(out.points.size()), [&](double phi) {
    out.points[static_cast<std::size_t>(out.count++)] = centre + (e1 * std::cos(phi) + e2 * std::sin(phi)) * radius_m;
  }, true);
  return out;
}

namespace {

// Two points in a cylinder's frame: `ref` at (r, 0) across the axis on e1 (r its distance from the
// axis in radii; e2 = axis × e1), `other` at (x1, x2) in radii and other_across_m from the axis,
// `rise` radii above `ref` along it; their heights along the axis from on_axis (metres).
struct AcrossAxis {
  Vec3 e1, e2;
  double r = 0.0, x1 = 0.0, x2 = 0.0, rise = 0.0, other_across_m = 0.0, z_ref_m = 0.0, z_other_m = 0.0;
};
AcrossAxis across_axis(const Vec3& ref, const Vec3& other, const Vec3& on_axis, const Vec3& axis, double radius_m) {
  AcrossAxis f;
  const Vec3 to_ref = ref - on_axis, to_other = other - on_axis;
  f.z_ref_m = dot(to_ref, axis), f.z_other_m = dot(to_other, axis);
  const Vec3 ref_across = to_ref - axis * f.z_ref_m, other_across = to_other - axis * f.z_other_m;
  f.r = length(ref_across) / radius_m;
  f.other_across_m = length(other_across);
  f.e1 = ref_across / (f.r * radius_m), f.e2 = cross(axis, f.e1);
  f.x1 = dot(other_across, f.e1) / radius_m, f.x2 = dot(other_across, f.e2) / radius_m;
  f.rise = (f.z_other_m - f.z_ref_m) / radius_m;
  return f;
}

}  // namespace

SphereRefraction cylinder_refraction_points(const Vec3& inner, const Vec3& outer, const Vec3& on_axis,
                                            const Vec3& axis, double radius_m, double eta_inner, double eta_outer,
                                            const NearSolution* near) {
  SphereRefraction out;
  // Across the axis, in units of the radius: the outer point at (b, 0) on e1, the inner one at
  // (a1, a2); along it, the outer point dz above the inner one; y(φ, z) = (cos φ, sin φ, z).
  const AcrossAxis frame = across_axis(outer, inner, on_axis, axis, radius_m);
  if (!(frame.r > 1.0) || !(frame.other_across_m < radius_m)) return out;
  const Vec3 e1 = frame.e1, e2 = frame.e2;
  const double b = frame.r, a1 = frame.x1, a2 = frame.x2, dz = -frame.rise, z_inner = frame.z_other_m;
  // At (cos φ, sin φ): the height from the inner point's where the path crosses (Snell's law
  // along the axis over the two distances across it), and the path's two lengths.
  struct Crossing {
    double z, to_y, from_y;
  };
  // (Each from the last one's root: the scan's and the refinement's angles come in small steps.)
  double last = 0.5;
  auto crossing_at = [&](double c, double s, double tolerance = 1e-13) {
    const double to_foot = norm2(c - a1, s - a2), from_foot = norm2(b - c, s);
    const double split = snell_split(std::abs(dz), to_foot, from_foot, eta_inner, eta_outer, last, tolerance);
    if (dz != 0.0) last = split / std::abs(dz);
    const double z = std::copysign(split, dz);
    return Crossing{z, norm2(to_foot, z), norm2(from_foot, dz - z)};
  };
  // The derivative of the optical length around the axis at that height (the envelope's: its
  // derivative along the axis is 0 there).
  auto slope_at = [&](double c, double s, double tolerance) {
    const Crossing k = crossing_at(c, s, tolerance);
    return eta_inner * (a1 * s - a2 * c) / k.to_y + eta_outer * b * s / k.from_y;
  };
  // The scan reads only the slope's sign, which a height to 1e-9 of the way keeps but within
  // about 1e-9 of a root; the refinement and the point take it to 1e-13.
  auto scan_cs = [&](double c, double s) { return slope_at(c, s, 1e-9); };
  auto slope_cs = [&](double c, double s) { return slope_at(c, s, 1e-13); };
  // The arc the outer point sees: cos φ > 1/b.
  const double phi_max = std::acos(1.0 / b) * (1.0 - 1e-12);
  const auto [from, to, intervals] = scan_range(phi_max, near, on_axis, e1, e2, 48);
  scan_roots(
      scan_cs, slope_cs, from, to, intervals, static_cast<int>(out.points.size()),
      [&](double phi) {
        const Crossing k = crossing_at(std::cos(phi), std::sin(phi));
        out.points[static_cast<std::size_t>(out.count++)] =
            on_axis + (e1 * std::cos(phi) + e2 * std::sin(phi)) * radius_m + axis * (z_inner + k.z * radius_m);
      },
      true);
  return out;
}

namespace {

// A passage through a circle, in its plane and in units of its radius: the entry angle φ of the
// point (cos φ, sin φ), and the exit point.
struct CirclePassage {
  double phi, exit_x, exit_y;
};

// The ray from (a, 0) through y1 = (y1x, y1y) on the unit circle, refracted in (eta: the index
// outside over the index inside), across the circle, refracted out: where (b1, b2) lies from it
// (the cross product of its direction with y2 → (b1, b2); 0 on it), if it gets out and that point
// is ahead.
struct CircleTrace {
  bool valid = false, ahead = false, reflected = false;
  double side = 0.0, y2x = 0.0, y2y = 0.0;
};
// (With `extended`, a ray that gets out is valid whichever way (b1, b2) lies along it, `ahead`
// saying which; and one totally reflected at the exit leaves along the tangent there, `reflected`
// saying so: the side is then continuous where a ray stops getting out. With `direction`, (b1, b2)
// is a unit direction, a point infinitely far along it: the side is the exit direction's cross
// product with it, ahead where they agree.)
inline CircleTrace trace_circle(double a, double b1, double b2, double eta, double y1x, double y1y,
                                bool extended = false, bool direction = false) {
  CircleTrace p;
  double dx = y1x - a, dy = y1y;
  const double dl = norm2(dx, dy);
  dx /= dl, dy /= dl;
  // In: normal (y1x, y1y) outward, the ray against it.
  const double cos_i = -(dx * y1x + dy * y1y), sin_t2 = eta * eta * (1.0 - cos_i * cos_i);
  if (!(cos_i > 0.0) || sin_t2 >= 1.0) return p;
  const double k = eta * cos_i - std::sqrt(1.0 - sin_t2);
  const double tx = eta * dx + k * y1x, ty = eta * dy + k * y1y;
  // Across: the chord along t from y1 (unit circle: length −2·y1·t).
  const double chord = -2.0 * (y1x * tx + y1y * ty);
  if (!(chord > 0.0)) return p;
  p.y2x = y1x + chord * tx, p.y2y = y1y + chord * ty;
  // Out: normal y2 outward, the ray along it.
  const double cos_o = tx * p.y2x + ty * p.y2y, inv = 1.0 / eta, sin_u2 = inv * inv * (1.0 - cos_o * cos_o);
  if (!(cos_o > 0.0)) return p;
  p.reflected = sin_u2 >= 1.0;
  if (p.reflected && !extended) return p;
  const double m = std::sqrt(std::max(0.0, 1.0 - sin_u2)) - inv * cos_o;
  double ox = inv * tx + m * p.y2x, oy = inv * ty + m * p.y2y;
  if (p.reflected) {  // the tangent, of unit length
    const double l = norm2(ox, oy);
    ox /= l, oy /= l;
  }
  const double rx = direction ? b1 : b1 - p.y2x, ry = direction ? b2 : b2 - p.y2y;
  p.ahead = ox * rx + oy * ry > 0.0;
  if (!p.ahead && !extended) return p;
  p.valid = true;
  p.side = ox * ry - oy * rx;  // (its sign and roots are all the scan needs)
  return p;
}

// The passages through the unit circle from (a, 0) (a > 1) to (b1, b2) (outside it), eta the
// index outside over the index inside: each entry point (cos φ, sin φ), φ over [first, last] (an
// arc `from` sees) in `intervals`, traces one ray (trace_circle), and the paths are the sign
// changes of the side of it (b1, b2) lies on, refined by the Illinois method to 1e-14 of a radian.
// An interval whose ends differ in whether their rays pass (at an edge of total internal
// reflection, or of the far point being ahead) is split in four, three times over, so a narrow
// window of paths near it is not stepped over. `out(passage)` for each, at most `most`. With
// `direction`, to a point infinitely far along the unit (b1, b2) (trace_circle).
template <typename Out>
void circle_passages(double a, double b1, double b2, double eta, double first, double last, int intervals, int most,
                     Out out, bool direction = false) {
  using Passage = CircleTrace;
  auto passage_cs = [&](double y1x, double y1y) { return trace_circle(a, b1, b2, eta, y1x, y1y, false, direction); };
  auto passage = [&](double phi) { return passage_cs(std::cos(phi), std::sin(phi)); };
  auto side = [&](double phi) {
    const Passage p = passage(phi);
    return p.valid ? p.side : std::numeric_limits<double>::quiet_NaN();
  };
  int count = 0;
  auto interval = [&](auto& self, double lo, double hi, const Passage& p_lo, const Passage& p_hi, int depth) -> void {
    if (count >= most) return;
    if (p_lo.valid && p_hi.valid) {
      if (p_hi.side == 0.0 || (p_lo.side != 0.0 && (p_lo.side < 0.0) == (p_hi.side < 0.0))) return;
      const std::optional<double> phi = p_lo.side == 0.0 ? lo : bracketed_root(side, lo, hi, p_lo.side, p_hi.side);
      const Passage pr = phi ? passage(*phi) : Passage{};
      if (pr.valid) {
        ++count;
        out(CirclePassage{*phi, pr.y2x, pr.y2y});
      }
      return;
    }
    if (p_lo.valid == p_hi.valid || depth == 3) return;
    Passage prev = p_lo;
    for (int j = 1; j <= 4; ++j) {
      const double at = j == 4 ? hi : lo + (hi - lo) * j / 4;
      const Passage next = j == 4 ? p_hi : passage(at);
      self(self, lo + (hi - lo) * (j - 1) / 4, at, prev, next, depth + 1);
      prev = next;
    }
  };
  double lo = first;
  Passage p_lo = passage(lo);
  const double step = (last - first) / intervals, cos_step = std::cos(step), sin_step = std::sin(step);
  double c = std::cos(first), sn = std::sin(first);
  for (int i = 1; i <= intervals; ++i) {
    const double hi = first + (last - first) * i / intervals;
    const double c_next = c * cos_step - sn * sin_step;
    sn = sn * cos_step + c * sin_step, c = c_next;
    const Passage p_hi = passage_cs(c, sn);
    interval(interval, lo, hi, p_lo, p_hi, 0);
    lo = hi, p_lo = p_hi;
  }
}

// What circle_passages hands over, kept as a sphere's passage: its entry and exit points in the
// world (the circle's plane through the centre along e1, e2, in units of the radius).
auto keep_passage(SpherePassages& out, const Vec3& centre, const Vec3& e1, const Vec3& e2, double radius_m) {
  return [&out, centre, e1, e2, radius_m](const CirclePassage& p) {
    const auto k = static_cast<std::size_t>(out.count++);
    out.entry[k] = centre + (e1 * std::cos(p.phi) + e2 * std::sin(p.phi)) * radius_m;
    out.exit[k] = centre + (e1 * p.exit_x + e2 * p.exit_y) * radius_m;
  };
}

}  // namespace

SpherePassages sphere_passage_points(const Vec3& from, const Vec3& to, const Vec3& centre, double radius_m,
                                     double eta_inside, double eta_outside, const NearSolution* near) {
  SpherePassages out;
  // In the plane of the centre and both points, in units of the radius: `from` at (a, 0) on e1,
  // `to` at (b1, b2) with b2 ≥ 0; the entry point y1(φ) = (cos φ, sin φ) on the arc `from` sees.
  const Vec3 to_from = from - centre, to_to = to - centre;
  const double a = length(to_from) / radius_m;
  if (!(a > 1.0) || !(length(to_to) > radius_m)) return out;
  const Vec3 e1 = to_from / (a * radius_m);
  const Vec3 across = to_to - e1 * dot(to_to, e1);
  const double across_m = length(across);
  const Vec3 e2 = across_m > 1e-12 * radius_m ? across / across_m : Frame(e1).s;
  const double b1 = dot(to_to, e1) / radius_m, b2 = dot(to_to, e2) / radius_m;
  const double eta = eta_outside / eta_inside;  // entering; leaving: its inverse
  // No path where the turn from `from`'s view of the centre to the centre's view of `to` exceeds
  // the most a passage deviates a ray, 2·acos(η_min/η_max) (entering at grazing incidence, or at
  // the critical angle into a lower index), plus the angles the sphere subtends at both.
  {
    const double turn = std::acos(std::clamp(dot(-e1, normalize(to_to)), -1.0, 1.0));
    const double most = 2.0 * std::acos(std::min(eta, 1.0 / eta)) + std::asin(1.0 / a) +
                        std::asin(std::min(1.0, 1.0 / (length(to_to) / radius_m)));
    if (turn > most) return out;
  }
  const double phi_max = std::acos(1.0 / a) * (1.0 - 1e-12);
  const auto [first, last, intervals] = scan_range(phi_max, near, centre, e1, e2, 16);
  circle_passages(a, b1, b2, eta, first, last, intervals, static_cast<int>(out.entry.size()),
                  keep_passage(out, centre, e1, e2, radius_m));
  return out;
}

SpherePassages sphere_passage_towards(const Vec3& from, const Vec3& to_lamp, const Vec3& centre, double radius_m,
                                      double eta_inside, double eta_outside, const NearSolution* near) {
  SpherePassages out;
  // As sphere_passage_points with `to` infinitely far along to_lamp, at (b1, b2) on the unit circle
  // of directions with b2 ≥ 0.
  const Vec3 to_from = from - centre;
  const double a = length(to_from) / radius_m;
  if (!(a > 1.0)) return out;
  const Vec3 e1 = to_from / (a * radius_m);
  const Vec3 across = to_lamp - e1 * dot(to_lamp, e1);
  const double across_m = length(across);
  const Vec3 e2 = across_m > 1e-12 ? across / across_m : Frame(e1).s;
  const double b1 = dot(to_lamp, e1), b2 = dot(to_lamp, e2);
  const double eta = eta_outside / eta_inside;
  // (No path where the turn exceeds the most a passage deviates, plus the angle the sphere subtends
  // at `from`: as there, the lamp's angle 0.)
  const double turn = std::acos(std::clamp(-b1, -1.0, 1.0));
  if (turn > 2.0 * std::acos(std::min(eta, 1.0 / eta)) + std::asin(1.0 / a)) return out;
  const double phi_max = std::acos(1.0 / a) * (1.0 - 1e-12);
  const auto [first, last, intervals] = scan_range(phi_max, near, centre, e1, e2, 16);
  circle_passages(a, b1, b2, eta, first, last, intervals, static_cast<int>(out.entry.size()),
                  keep_passage(out, centre, e1, e2, radius_m), true);
  return out;
}

namespace {

// A cylinder's passage solve at (φ, β) (cylinder_passage_points): whether the ray gets out
// (`valid`) and towards `to` (`passes`: not behind it, not totally reflected), the side of it `to`
// lies on across the axis, its miss along the axis, its exit point and the heights of its
// crossings.
struct PassagePoint {
  bool valid = false, passes = false;
  double side = 0.0, miss = 0.0, exit_x = 0.0, exit_y = 0.0, z1 = 0.0, z2 = 0.0;
};
struct PassageCorner {
  double phi = 0.0, beta = 0.0;
  PassagePoint p;
};
// Crossings of side's zero set with a cell's edges, each with its edge (0 bottom, 1 right, 2 top,
// 3 left, as the corners go round) and whether it is exact or where the straight line between the
// edge's ends puts it, its miss likewise.
template <std::size_t K>
struct CrossingsOf {
  std::array<PassageCorner, K> at{};
  std::array<int, K> edge{};
  std::array<bool, K> exact{};
  int count = 0;
  void add(const std::optional<PassageCorner>& c, int on_edge, bool is_exact) {
    if (!c || count >= static_cast<int>(at.size())) return;
    edge[static_cast<std::size_t>(count)] = on_edge;
    exact[static_cast<std::size_t>(count)] = is_exact;
    at[static_cast<std::size_t>(count++)] = *c;
  }
};

}  // namespace

SpherePassages cylinder_passage_points(const Vec3& from, const Vec3& to, const Vec3& on_axis, const Vec3& axis,
                                       double radius_m, double eta_inside, double eta_outside,
                                       const NearSolution* near) {
  SpherePassages out;
  // Across the axis, in units of the radius: `from` at (a, 0) on e1, `to` at (b1, b2); along
  // it, `to` dz above `from`.
  const AcrossAxis frame = across_axis(from, to, on_axis, axis, radius_m);
  if (!(frame.r > 1.0) || !(frame.other_across_m > radius_m)) return out;
  const Vec3 e1 = frame.e1, e2 = frame.e2;
  const double a = frame.r, b1 = frame.x1, b2 = frame.x2, dz = frame.rise, z_from = frame.z_ref_m;
  const double eta_min = std::min(eta_inside, eta_outside), eta_max = std::max(eta_inside, eta_outside);
  const double phi_max = std::acos(1.0 / a) * (1.0 - 1e-12), beta_max = 0.5 * std::numbers::pi * (1.0 - 1e-9);
  // A path entering at angle φ around the axis with the invariant α = η_min·sin β (η times the
  // direction's part along the axis, the same on every segment, since each crossing's normal lies
  // across the axis): across the axis it refracts as through a circle with Bravais' effective
  // indices √(η² − α²), and each segment rises α/√(η² − α²) per unit of its length across. At
  // (φ, β): the side of the ray across the axis `to` lies on, and the miss along the axis (the
  // rise of the three segments, the last to `to`'s foot, less dz). The paths are where both are 0.
  // (The grid's points reuse their column's cos φ, sin φ and their row's sin β.)
  using Point = PassagePoint;
  using Corner = PassageCorner;
  auto at_cs = [&](double phi, double c, double s, double beta, double sin_beta) {
    Point p;
    if (!(std::abs(beta) <= beta_max) || !(std::abs(phi) <= phi_max)) return p;
    const double alpha = eta_min * sin_beta;
    const double eo = std::sqrt(std::max(0.0, eta_outside * eta_outside - alpha * alpha));
    const double ei = std::sqrt(std::max(0.0, eta_inside * eta_inside - alpha * alpha));
    if (!(eo > 0.0) || !(ei > 0.0)) return p;
    const CircleTrace t = trace_circle(a, b1, b2, eo / ei, c, s, true);
    if (!t.valid) return p;
    const double h0 = norm2(c - a, s), h1 = norm2(t.y2x - c, t.y2y - s), h2 = norm2(b1 - t.y2x, b2 - t.y2y);
    const double z1 = alpha * h0 / eo, z2 = z1 + alpha * h1 / ei;
    return Point{true, t.ahead && !t.reflected, t.side, z2 + alpha * h2 / eo - dz, t.y2x, t.y2y, z1, z2};
  };
  auto at = [&](double phi, double beta) { return at_cs(phi, std::cos(phi), std::sin(phi), beta, std::sin(beta)); };
  auto negative = [](double x) { return x < 0.0; };
  // (side scales with the way from the exit to `to`, at most its distance from the axis and 1.)
  const double miss_tolerance = 1e-9 * (1.0 + std::abs(dz)), side_tolerance = 1e-12 * (1.0 + norm2(b1, b2));
  // Where side = 0 meets miss = 0, cell by cell of a grid over (φ, β) (marching squares): side's
  // zero set is the circle's passages as β changes its indices, a set of curves that fold back in
  // β and in φ (passages appear and end in pairs at a caustic's fold), so neither can be followed
  // as a function of the other.
  // - Each cell edge whose ends' sides differ in sign holds a crossing of the curve, first guessed
  //   where side is 0 on the straight line between them (no evaluation), exact where that guess's
  //   miss is nearer 0 than the ends' misses differ (its sign may be wrong) or a refinement starts
  //   from it. Along a row, two crossings close together are found where |side| at a grid point is
  //   below its neighbours', all of one sign, and its extremum between them changes sign (as
  //   scan_roots).
  // - Where two crossings of a cell miss on opposite sides, the curve between them holds a path:
  //   Newton's method on (side, miss) from the one nearer 0, and where that ends outside the cell,
  //   the curve followed between the two (t along the segment between them, the curve found
  //   across it, the Illinois method on t).
  // - Where all miss on one side but the miss could reach 0 in the cell (the corners' misses
  //   straddle 0, or a crossing's is within their spread of it), two paths may lie close together
  //   on one stretch of the curve (near a caustic's fold): Newton's method from each crossing where
  //   the miss heads towards 0 along the curve into the cell.
  // - Side is continued past where a ray stops getting out (totally reflected at the exit: it
  //   leaves along the tangent) and past `to` lying behind it, so that the curves run on and a
  //   path found there is dropped. A cell whose corners still differ in whether their rays pass
  //   (entering a lower index at more than the critical angle; α beyond the lower index) is split
  //   in four, four times over.
  std::array<Corner, 4> found{};
  int count = 0;
  auto keep = [&](const Corner& r) {
    if (!r.p.passes) return;  // the line through `to` of a ray leaving away from it, or totally reflected
    for (int k = 0; k < count; ++k)
      if (std::abs(found[static_cast<std::size_t>(k)].phi - r.phi) < 1e-9 &&
          std::abs(found[static_cast<std::size_t>(k)].beta - r.beta) < 1e-9)
        return;
    if (count < static_cast<int>(found.size())) found[static_cast<std::size_t>(count++)] = r;
  };
  // The paths found, as points.
  auto result = [&] {
    for (int k = 0; k < count; ++k) {
      const Corner& f = found[static_cast<std::size_t>(k)];
      out.entry[static_cast<std::size_t>(k)] = on_axis + (e1 * std::cos(f.phi) + e2 * std::sin(f.phi)) * radius_m +
                                               axis * (z_from + f.p.z1 * radius_m);
      out.exit[static_cast<std::size_t>(k)] = on_axis + (e1 * f.p.exit_x + e2 * f.p.exit_y) * radius_m +
                                              axis * (z_from + f.p.z2 * radius_m);
    }
    out.count = count;
    return out;
  };
  // side's root on the straight line from c0 to c1 (their sides of opposite signs).
  auto root_between = [&](const Corner& c0, const Corner& c1, double side0, double side1) -> std::optional<Corner> {
    auto side = [&](double t) {
      const Point p = at(c0.phi + (c1.phi - c0.phi) * t, c0.beta + (c1.beta - c0.beta) * t);
      return p.valid ? p.side : std::numeric_limits<double>::quiet_NaN();
    };
    const std::optional<double> t = side0 == 0.0 ? 0.0 : bracketed_root(side, 0.0, 1.0, side0, side1);
    if (!t) return std::nullopt;
    const double phi = c0.phi + (c1.phi - c0.phi) * *t, beta = c0.beta + (c1.beta - c0.beta) * *t;
    const Point p = at(phi, beta);
    if (!p.valid) return std::nullopt;
    return Corner{phi, beta, p};
  };
  auto crossing_on = [&](const Corner& c0, const Corner& c1) -> std::optional<Corner> {
    if (negative(c0.p.side) == negative(c1.p.side)) return std::nullopt;
    return root_between(c0, c1, c0.p.side, c1.p.side);
  };
  // The path on the curve between crossings n and q (missing on opposite sides) of a cell of size
  // (dphi, dbeta): t along the segment from n to q, the curve found across it (in the cell's own
  // units, within a growing distance either side), the miss there.
  auto refine = [&](const Corner& n, const Corner& q, double dphi, double dbeta) {
    const double u = (q.phi - n.phi) / dphi, v = (q.beta - n.beta) / dbeta, len = norm2(u, v);
    if (!(len > 0.0)) return;
    const double nu = -v / len, nv = u / len;  // across the segment, in cell units
    std::optional<Corner> last;
    auto miss = [&](double t) {
      const double phi = n.phi + (q.phi - n.phi) * t, beta = n.beta + (q.beta - n.beta) * t;
      auto side = [&](double s) {
        const Point p = at(phi + nu * dphi * s, beta + nv * dbeta * s);
        return p.valid ? p.side : std::numeric_limits<double>::quiet_NaN();
      };
      last.reset();
      const double s0 = side(0.0);
      if (std::isnan(s0)) return s0;
      for (double reach = 0.125; reach <= 1.5; reach *= 2.0) {
        const double lo = side(-reach), hi = side(reach);
        if (std::isnan(lo) || std::isnan(hi)) break;
        // The curve nearer the segment: the half from 0 whose end differs in sign.
        const bool below = negative(lo) != negative(s0), above = negative(hi) != negative(s0);
        if (!below && !above) continue;
        const std::optional<double> s = s0 == 0.0 ? 0.0
                                         : below && (!above || std::abs(lo) < std::abs(hi))
                                             ? bracketed_root(side, -reach, 0.0, lo, s0)
                                             : bracketed_root(side, 0.0, reach, s0, hi);
        if (!s) break;
        const double phi_s = phi + nu * dphi * *s, beta_s = beta + nv * dbeta * *s;
        const Point p = at(phi_s, beta_s);
        if (!p.valid) break;
        last = Corner{phi_s, beta_s, p};
        return p.miss;
      }
      return std::numeric_limits<double>::quiet_NaN();
    };
    const std::optional<double> t = bracketed_root(miss, 0.0, 1.0, n.p.miss, q.p.miss);
    if (!t || std::isnan(miss(*t)) || !last) return;
    if (std::abs(last->p.miss) <= miss_tolerance) keep(*last);  // (not a jump across to another stretch)
  };
  // Newton's method on (side, miss) from a crossing (the Jacobian by differences of 1e-7 rad),
  // each step within half the cell's size; the root it reaches, kept, or nothing.
  auto newton = [&](const Corner& start, double dphi, double dbeta) -> std::optional<Corner> {
    double phi = start.phi, beta = start.beta;
    Point p = at(phi, beta);  // (a guessed crossing's own values are interpolated)
    if (!p.valid) return std::nullopt;
    for (int k = 0; k < 40; ++k) {
      constexpr double h = 1e-7;
      const Point pp = at(phi + h, beta), pb = at(phi, beta + h);
      if (!pp.valid || !pb.valid) return std::nullopt;
      const double g_p = (pp.side - p.side) / h, g_b = (pb.side - p.side) / h;
      const double m_p = (pp.miss - p.miss) / h, m_b = (pb.miss - p.miss) / h;
      const double det = g_p * m_b - g_b * m_p;
      if (!(std::abs(det) > 0.0)) return std::nullopt;
      double step_phi = -(m_b * p.side - g_b * p.miss) / det, step_beta = -(g_p * p.miss - m_p * p.side) / det;
      const double scale =
          std::max({1.0, std::abs(step_phi) / (0.5 * std::abs(dphi)), std::abs(step_beta) / (0.5 * std::abs(dbeta))});
      phi += step_phi / scale, beta += step_beta / scale;
      p = at(phi, beta);
      if (!p.valid) return std::nullopt;
      if (std::abs(step_phi) < 1e-15 && std::abs(step_beta) < 1e-15) break;
    }
    if (!(std::abs(p.miss) <= miss_tolerance) || !(std::abs(p.side) <= side_tolerance)) return std::nullopt;
    keep(Corner{phi, beta, p});
    return Corner{phi, beta, p};
  };
  // A cell's crossings: at most two on each edge.
  using Crossings = CrossingsOf<8>;
  // A crossing where side, linear between the ends of an edge, is 0 (no evaluation: most cells
  // need no more than its miss's sign).
  auto guess_on = [&](const Corner& c0, const Corner& c1) -> std::optional<Corner> {
    if (negative(c0.p.side) == negative(c1.p.side)) return std::nullopt;
    const double t = c0.p.side / (c0.p.side - c1.p.side);
    Corner k{c0.phi + (c1.phi - c0.phi) * t, c0.beta + (c1.beta - c0.beta) * t, c0.p};
    k.p.side = 0.0, k.p.miss = c0.p.miss + (c1.p.miss - c0.p.miss) * t;
    return k;
  };
  // c: the corners (φ0, β0), (φ1, β0), (φ1, β1), (φ0, β1), in order around the cell.
  auto solve_cell = [&](const std::array<Corner, 4>& c, Crossings x) {
    if (x.count < 2) return;
    // A guessed crossing whose miss is nearer 0 than its edge's ends differ by may have the wrong
    // sign: exact, as is every crossing a refinement starts from.
    auto make_exact = [&](int i) {
      const auto k = static_cast<std::size_t>(i);
      if (x.exact[k]) return true;
      const auto e = static_cast<std::size_t>(x.edge[k]);
      const auto r = crossing_on(c[e], c[(e + 1) % 4]);
      if (!r) return false;
      x.at[k] = *r, x.exact[k] = true;
      return true;
    };
    // (One that cannot be made exact is dropped: the last takes its place.)
    for (int i = 0; i < x.count; ++i) {
      const auto e = static_cast<std::size_t>(x.edge[static_cast<std::size_t>(i)]);
      if (std::abs(x.at[static_cast<std::size_t>(i)].p.miss) <= std::abs(c[e].p.miss - c[(e + 1) % 4].p.miss) &&
          !make_exact(i)) {
        const auto last = static_cast<std::size_t>(--x.count), k = static_cast<std::size_t>(i--);
        x.at[k] = x.at[last], x.edge[k] = x.edge[last], x.exact[k] = x.exact[last];
      }
    }
    if (x.count < 2) return;
    const double dphi = c[1].phi - c[0].phi, dbeta = c[3].beta - c[0].beta;
    const double spread = std::max({c[0].p.miss, c[1].p.miss, c[2].p.miss, c[3].p.miss}) -
                          std::min({c[0].p.miss, c[1].p.miss, c[2].p.miss, c[3].p.miss});
    // (Newton's root is taken where it lies in the cell; the refinement along the curve where it
    // does not.)
    auto inside = [&](const Corner& r) {
      return (r.phi - c[0].phi) * (r.phi - c[1].phi) <= 0.0 && (r.beta - c[0].beta) * (r.beta - c[3].beta) <= 0.0;
    };
    double nearest = std::numeric_limits<double>::infinity();
    bool both_sides = false;
    for (int i = 0; i < x.count; ++i) {
      const Corner& n = x.at[static_cast<std::size_t>(i)];
      nearest = std::min(nearest, std::abs(n.p.miss));
      for (int j = i + 1; j < x.count; ++j) {
        const Corner& q = x.at[static_cast<std::size_t>(j)];
        if (negative(n.p.miss) == negative(q.p.miss)) continue;
        both_sides = true;
        const Corner& start = std::abs(n.p.miss) < std::abs(q.p.miss) ? n : q;
        if (const auto r = newton(start, dphi, dbeta); r && r->p.passes && inside(*r)) continue;
        if (!make_exact(i) || !make_exact(j)) continue;
        negative(n.p.miss) ? refine(n, q, dphi, dbeta) : refine(q, n, dphi, dbeta);
      }
    }
    const double lowest = std::min({c[0].p.miss, c[1].p.miss, c[2].p.miss, c[3].p.miss});
    if (both_sides || !((lowest <= 0.0 && lowest + spread >= 0.0) || nearest <= spread)) return;
    // Two paths close together on one stretch of the curve: the miss heads towards 0 from both
    // of its ends (along the curve's tangent, into the cell: the gradients by differences).
    int heading = 0;
    std::array<bool, 8> towards{};
    for (int i = 0; i < x.count; ++i) {
      if (!make_exact(i)) continue;
      const Corner& k = x.at[static_cast<std::size_t>(i)];
      constexpr double h = 1e-7;
      const Point pp = at(k.phi + h, k.beta), pb = at(k.phi, k.beta + h);
      if (!pp.valid || !pb.valid) continue;
      double t_phi = -(pb.side - k.p.side), t_beta = pp.side - k.p.side;  // along the curve
      const int e = x.edge[static_cast<std::size_t>(i)];
      const double in = e == 0 ? t_beta : e == 1 ? -t_phi : e == 2 ? -t_beta : t_phi;
      if (in < 0.0) t_phi = -t_phi, t_beta = -t_beta;
      const double change = (pp.miss - k.p.miss) * t_phi + (pb.miss - k.p.miss) * t_beta;
      towards[static_cast<std::size_t>(i)] = negative(k.p.miss) ? change > 0.0 : change < 0.0;
      heading += towards[static_cast<std::size_t>(i)];
    }
    if (heading < 1) return;
    for (int i = 0; i < x.count; ++i)
      if (towards[static_cast<std::size_t>(i)]) newton(x.at[static_cast<std::size_t>(i)], dphi, dbeta);
  };
  auto split_cell = [&](auto& self, const std::array<Corner, 4>& c, int depth) -> void {
    const int valid = c[0].p.valid + c[1].p.valid + c[2].p.valid + c[3].p.valid;
    if (valid == 4) {
      Crossings x;
      for (std::size_t e = 0; e < 4; ++e) x.add(guess_on(c[e], c[(e + 1) % 4]), static_cast<int>(e), false);
      solve_cell(c, x);
      return;
    }
    if (valid == 0 || depth == 4) return;
    const double pm = 0.5 * (c[0].phi + c[1].phi), bm = 0.5 * (c[0].beta + c[3].beta);
    const Corner mid{pm, bm, at(pm, bm)};
    const Corner bottom{pm, c[0].beta, at(pm, c[0].beta)}, top{pm, c[3].beta, at(pm, c[3].beta)};
    const Corner left{c[0].phi, bm, at(c[0].phi, bm)}, right{c[1].phi, bm, at(c[1].phi, bm)};
    self(self, {c[0], bottom, mid, left}, depth + 1);
    self(self, {bottom, c[1], right, mid}, depth + 1);
    self(self, {mid, right, c[2], top}, depth + 1);
    self(self, {left, mid, top, c[3]}, depth + 1);
  };
  // The grid: all of φ's arc that `from` sees in 16 columns; β in 12 rows over the window where
  // the paths' β lie (the length across of any path is at least the straight distance across,
  // h_lo, and at most the tangents from both ends and a diameter, h_hi; each segment rises at least
  // α/√(η_max² − α²) and at most α/√(η_min² − α²) per unit across). With `near`, a window around the
  // φ and β of the path through that entry point, 2 by 2 (a neighbour's step moves β by about the
  // step over the way to the entry point, and φ by about the step over the radius).
  constexpr int kColumns = 16;
  double phi_from = -phi_max, phi_to = phi_max, beta_from = 0.0, beta_to = 0.0;
  int columns = kColumns, rows = 12;
  {
    const double h_lo = norm2(b1 - a, b2), h_hi = std::sqrt(a * a - 1.0) + 2.0 + std::sqrt(b1 * b1 + b2 * b2 - 1.0);
    const double k_hi = std::abs(dz) / h_lo, k_lo = std::abs(dz) / h_hi;
    const double hi = std::asin(std::min(1.0, eta_max * k_hi / std::sqrt(1.0 + k_hi * k_hi) / eta_min));
    const double lo = std::asin(std::min(1.0, eta_min * k_lo / std::sqrt(1.0 + k_lo * k_lo) / eta_min));
    const double margin = 1e-6 + 1e-3 * (hi - lo);
    beta_from = std::max(-beta_max, (dz < 0.0 ? -hi : lo) - margin);
    beta_to = std::min(beta_max, (dz < 0.0 ? -lo : hi) + margin);
  }
  if (near) {
    const Vec3 d = near->point - from;
    const double way = length(d);
    const double beta = std::asin(std::clamp(eta_outside * dot(d, axis) / (way * eta_min), -1.0, 1.0));
    const double window = near->window_rad * (1.0 + radius_m / way) / std::max(std::cos(beta), 1e-2);
    beta_from = std::max(beta_from, beta - window), beta_to = std::min(beta_to, beta + window);
    const double phi = std::atan2(dot(near->point - on_axis, e2), dot(near->point - on_axis, e1));
    // A neighbour of a path already solved (the ray tube's, a millionth of the path away): Newton's
    // method from the φ and β of the straight line to that path's entry point reaches it in a few
    // evaluations, where the window's grid below took about 130. The grid only where it does not.
    // (A root outside the window may be another path, near a fold: the grid's then.)
    const auto r = newton(Corner{phi, beta, {}}, near->window_rad, window);
    if (r && count > 0 && std::abs(r->phi - phi) <= near->window_rad && std::abs(r->beta - beta) <= window)
      return result();
    count = 0;
    phi_from = std::max(-phi_max, phi - near->window_rad), phi_to = std::min(phi_max, phi + near->window_rad);
    columns = 2, rows = 2;
  }
  if (!(phi_from < phi_to) || !(beta_from < beta_to)) return out;
  // Row by row in β: the grid points and the crossings on the edges between them, of the row
  // below and of this one.
  struct Row {
    std::array<Corner, kColumns + 1> point{};
    std::array<CrossingsOf<2>, kColumns> edge{};
  };
  std::array<double, kColumns + 1> column_cos{}, column_sin{};
  for (int i = 0; i <= columns; ++i) {
    const double phi = phi_from + (phi_to - phi_from) * i / columns;
    column_cos[static_cast<std::size_t>(i)] = std::cos(phi), column_sin[static_cast<std::size_t>(i)] = std::sin(phi);
  }
  auto grid_row = [&](double beta) {
    Row r;
    const double sin_beta = std::sin(beta);
    for (std::size_t i = 0; i <= static_cast<std::size_t>(columns); ++i) {
      const double phi = phi_from + (phi_to - phi_from) * static_cast<double>(i) / columns;
      r.point[i] = Corner{phi, beta, at_cs(phi, column_cos[i], column_sin[i], beta, sin_beta)};
    }
    for (std::size_t i = 0; i < static_cast<std::size_t>(columns); ++i)
      if (r.point[i].p.valid && r.point[i + 1].p.valid) r.edge[i].add(guess_on(r.point[i], r.point[i + 1]), 0, false);
    // Two crossings close together about a grid point whose |side| is below its neighbours'.
    for (std::size_t i = 1; i < static_cast<std::size_t>(columns); ++i) {
      const Corner &l = r.point[i - 1], &m = r.point[i], &h = r.point[i + 1];
      if (!l.p.valid || !m.p.valid || !h.p.valid || negative(l.p.side) != negative(m.p.side) ||
          negative(m.p.side) != negative(h.p.side) || !(std::abs(m.p.side) < std::abs(l.p.side)) ||
          !(std::abs(m.p.side) < std::abs(h.p.side)))
        continue;
      const double sign = negative(m.p.side) ? -1.0 : 1.0;
      const MinimumProbes g = find_minimum(
          [&](double phi) {
            const Point p = at(phi, beta);
            return p.valid ? sign * p.side : std::numeric_limits<double>::quiet_NaN();
          },
          l.phi, h.phi);
      if (std::isnan(g.f1) || std::isnan(g.f2) || !(g.value() < 0.0)) continue;
      const double phi_m = g.at();
      const Corner turn{phi_m, beta, at(phi_m, beta)};
      if (!turn.p.valid) continue;
      for (const auto& c : {root_between(l, turn, l.p.side, turn.p.side), root_between(turn, h, turn.p.side, h.p.side)})
        if (c) r.edge[c->phi < m.phi ? i - 1 : i].add(c, 0, true);
    }
    return r;
  };
  Row below = grid_row(beta_from);
  for (int j = 1; j <= rows; ++j) {
    const Row row = grid_row(beta_from + (beta_to - beta_from) * j / rows);
    std::optional<Corner> left = guess_on(below.point[0], row.point[0]);
    for (std::size_t i = 0; i < static_cast<std::size_t>(columns); ++i) {
      const std::array<Corner, 4> c{below.point[i], below.point[i + 1], row.point[i + 1], row.point[i]};
      std::optional<Corner> right = guess_on(below.point[i + 1], row.point[i + 1]);
      if (c[0].p.valid && c[1].p.valid && c[2].p.valid && c[3].p.valid) {
        Crossings x;
        for (int k = 0; k < below.edge[i].count; ++k)
          x.add(below.edge[i].at[static_cast<std::size_t>(k)], 0, below.edge[i].exact[static_cast<std::size_t>(k)]);
        for (int k = 0; k < row.edge[i].count; ++k)
          x.add(row.edge[i].at[static_cast<std::size_t>(k)], 2, row.edge[i].exact[static_cast<std::size_t>(k)]);
        x.add(left, 3, false), x.add(right, 1, false);
        solve_cell(c, x);
      } else {
        split_cell(split_cell, c, 0);
      }
      left = right;
    }
    below = row;
  }
  return result();
}

// Whether the segment from a to b certainly crosses a caster's sphere (RenderScene::casters: exact
// smooth refracting spheres): then the straight shadow ray to the area lamp's point is blocked, and
// nothing but the connections through the caster (through_casters) reaches that point from a (a
// chain of mesh faces does not seed through an analytic sphere). Skipping the ray saves its trace
// and its ratio tracking from every scattering event inside a ball of milk. Only without
// priorities (an object with one may make the sphere's boundary a false one), and not within a
// millionth of the radius of the sphere, where rounding decides what the ray meets. (Not for point
// and spot lamps: the first surface their ray meets may be a flat face or a cylinder's side whose
// own solve bends the path past the caster.)
bool caster_between(const RenderScene& s, const Vec3& a, const Vec3& b) {
  if (!s.nested.empty()) return false;
  for (const ManifoldCaster& c : s.casters) {
    const double r = c.radius_m, near = r * (1.0 - 1e-6), far = r * (1.0 + 1e-6);
    const double da = length(a - c.centre_m), db = length(b - c.centre_m);
    if ((da < near && db > far) || (da > far && db < near)) return true;
    if (da <= far || db <= far || !std::isfinite(db)) continue;
    // Both outside: blocked where the segment's nearest point to the centre is inside.
    const Vec3 ab = b - a;
    const double len2 = dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(dot(c.centre_m - a, ab) / len2, 0.0, 1.0) : 0.0;
    if (length(a + ab * t - c.centre_m) < near) return true;
  }
  return false;
}

namespace {

// A walk's path from x through interface f (crossings ys, in order) to a lamp hit, whose point the
// connection draws with density area_pdf per m² (0: it does not): the walk's refraction
// probabilities at its crossings, and the connection's density for the path (its full solve for
// that point, the walk's path among its solutions to the walk's single precision, and the ray tube
// there).
CasterPathDensities interface_path_densities(const RenderScene& s, const manifold_detail::Interface& f,
                                             const Vec3& x, std::span<const Vec3> ys, const Hit& light_hit,
                                             double area_pdf) {
  using namespace manifold_detail;
  CasterPathDensities out;
  const double eta_front = s.media[static_cast<std::size_t>(f.medium_front)].ior_reference;
  const double eta_behind = s.media[static_cast<std::size_t>(f.medium_behind)].ior_reference;
  const Vec3& q = light_hit.point;
  const int crossings = static_cast<int>(ys.size());
  // The walk's refraction choices, at the crossings where it made them.
  Vec3 from = x;
  bool front = f.front(x);
  for (const Vec3& y : ys) {
    const Vec3 n = f.normal_at(y), d = normalize(y - from);
    const double eta_i = front ? eta_front : eta_behind, eta_t = front ? eta_behind : eta_front;
    const double cos_i = std::abs(dot(d, n)), cos_t = cos_theta_transmitted(cos_i, eta_i, eta_t);
    out.refraction *= cos_t > 0.0 ? 1.0 - fresnel_dielectric(cos_i, cos_t, eta_i, eta_t) : 0.0;
    from = y, front = !front;
  }
  if (!(area_pdf > 0.0) || crossings < 1 || crossings > 2) return out;
  const Paths paths = solve(f, x, q, eta_front, eta_behind);
  if (paths.crossings != crossings) return out;
  const double tolerance = 1e-5 * (f.radius_m + length(q - x));
  for (int k = 0; k < paths.count; ++k) {
    const auto& exact = paths.crossing[static_cast<std::size_t>(k)];
    bool same = true;
    for (int c = 0; c < crossings; ++c)
      same = same && length(exact[static_cast<std::size_t>(c)] - ys[static_cast<std::size_t>(c)]) <= tolerance;
    if (!same) continue;
    const Vec3& last = exact[static_cast<std::size_t>(crossings - 1)];
    double path_m = length(exact[0] - x) + length(q - last);
    if (crossings == 2) path_m += length(exact[1] - exact[0]);
    const double t = tube(f, x, normalize(exact[0] - x), exact, crossings, q, path_m, eta_front, eta_behind);
    const double cos_light = std::abs(dot(light_hit.normal, normalize(q - last)));
    out.connection = connection_density(area_pdf, cos_light, t, f.front(x) ? eta_front : eta_behind,
                                        f.front(q) ? eta_front : eta_behind);
    return out;
  }
  return out;
}

}  // namespace

CasterPathDensities caster_path_densities(const RenderScene& s, const ManifoldCaster& c, const Vec3& x,
                                          const std::array<Vec3, 2>& ys, int crossings, const Hit& light_hit) {
  using namespace manifold_detail;
  // The point's density: the light's choice by power, its point by area (a sphere: on its cap).
  const Surface& surface = s.surfaces[light_hit.geometry];
  const auto index = static_cast<std::size_t>(surface.first_light) + light_hit.primitive;
  const Light& light = s.lights[index];
  double area_pdf = 0.0;
  if (const auto* a = std::get_if<AreaLight>(&light)) {
    area_pdf = a->area_m2 > 0.0 ? 1.0 / a->area_m2 : 0.0;
  } else if (const auto* sphere = std::get_if<SphereLight>(&light)) {
    const auto cap = facing_cap(*sphere, c);
    if (cap && dot(normalize(light_hit.point - sphere->centre_m), cap->axis) > cap->mu0) area_pdf = cap->pdf_area;
  }
  area_pdf *= s.area_lights.pmf[index];
  return interface_path_densities(s, caster_interface(s, c), x,
                                  std::span<const Vec3>(ys.data(), static_cast<std::size_t>(crossings)), light_hit,
                                  area_pdf);
}

CasterPathDensities cylinder_path_densities(const RenderScene& s, const Vec3& x, const Hit* x_hit, InsideSet inside,
                                            std::span<const Vec3> ys, const Hit& light_hit, std::uint64_t& rays) {
  using namespace manifold_detail;
  const Vec3& q = light_hit.point;
  const auto index = static_cast<std::size_t>(s.surfaces[light_hit.geometry].first_light) + light_hit.primitive;
  const double point_pdf = s.area_lights.pmf[index] * pdf_point(s.lights[index], x, q);
  // Where a caster lies across the straight segment, next-event estimation draws no shadow ray
  // and no connection (direct_light.h); elsewhere, the connection's own cylinder for this point.
  if (caster_between(s, x, q)) return {};
  const auto met = cylinder_met_first(s, x, x_hit, inside, q, rays);
  if (!met) return {};  // (it does not draw the path)
  return interface_path_densities(s, met->f, x, ys, light_hit, point_pdf);
}

CasterPathDensities chain_path_densities(const RenderScene& s, const Vec3& x, const Hit* x_hit, InsideSet inside,
                                         std::span<const Vec3> ys, const Hit& light_hit, std::uint64_t& rays) {
  CasterPathDensities out;
  if (ys.empty()) return out;
  const Vec3& q = light_hit.point;
  const auto index = static_cast<std::size_t>(s.surfaces[light_hit.geometry].first_light) + light_hit.primitive;
  const double point_pdf = s.area_lights.pmf[index] * pdf_point(s.lights[index], x, q);
  if (!(point_pdf > 0.0)) return out;
  // The connection's own seed and solve for this point, and the walk's path among them (to the
  // walk's single precision).
  const InsideSet towards = x_hit ? inside_towards(s, *x_hit, inside, normalize(q - x)) : inside;
  auto c = seed_chain(s, x, x_hit, towards, q, rays);
  if (!c || c->count != static_cast<int>(ys.size()) || !solve_chain(s, x, x_hit, q, *c, rays)) return out;
  Vec3 from = x;
  for (int k = 0; k < c->count; ++k) {
    const ChainCrossing& o = c->crossing[static_cast<std::size_t>(k)];
    const double tolerance = 1e-5 * std::max(length(q - x), s.rays.rounding_scale_m(o.hit.point));
    if (length(o.hit.point - ys[static_cast<std::size_t>(k)]) > tolerance) return out;
    // The walk's choice to refract here, by the shading normal it refracted by.
    const Vec3 n = chain_shading_normal(s, o.hit, o.hit.point), d = normalize(o.hit.point - from);
    const double cos_i = std::abs(dot(d, n)), cos_t = cos_theta_transmitted(cos_i, o.eta_from, o.eta_to);
    out.refraction *= cos_t > 0.0 ? 1.0 - fresnel_dielectric(cos_i, cos_t, o.eta_from, o.eta_to) : 0.0;
    from = o.hit.point;
  }
  const double reverse = chain_reverse_tube(s, x, q, *c);
  const double cos_light = std::abs(dot(light_hit.normal, normalize(q - from)));
  if (cos_light > 0.0 && reverse > 0.0 && std::isfinite(reverse)) out.connection = point_pdf / (cos_light * reverse);
  return out;
}

}  // namespace bouguer
