#include "bouguer/integrators/manifold.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

// The roots of a solve's slope (the derivative of the optical length along an arc) over the arc's
// angles [from, to]: its sign changes between `intervals` + 1 points, whose (cos, sin) come by
// rotation (96 steps lose no more than 1e-14; scan_cs(cos, sin) at them: its sign is all that is
// read), each refined by the Illinois method (slope_cs at (cos φ, sin φ)); root(φ) for each, at
// most `most`. With `pairs`, a scan point where |slope| is smaller than at both its neighbours,
// all three of one sign, may hide two roots close together (a caustic's fold between them): the
// slope's extremum over the two intervals is found by golden-section search, and where its sign
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
      // The extremum of sign·slope over [before, hi], by golden section (stopping once it changes sign).
      const double sign = g_lo < 0.0 ? -1.0 : 1.0, ratio = 0.5 * (std::sqrt(5.0) - 1.0);
      double a = before, b = hi, x1 = b - ratio * (b - a), x2 = a + ratio * (b - a);
      double f1 = sign * slope(x1), f2 = sign * slope(x2);
      for (int k = 0; k < 60 && f1 > 0.0 && f2 > 0.0 && b - a > 1e-14; ++k) {
        if (f1 < f2) {
          b = x2, x2 = x1, f2 = f1, x1 = b - ratio * (b - a), f1 = sign * slope(x1);
        } else {
          a = x1, x1 = x2, f1 = f2, x2 = a + ratio * (b - a), f2 = sign * slope(x2);
        }
      }
      const double m = f1 <= f2 ? x1 : x2, f_m = std::min(f1, f2);
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

SphereRefraction cylinder_refraction_points(const Vec3& inner, const Vec3& outer, const Vec3& on_axis,
                                            const Vec3& axis, double radius_m, double eta_inner, double eta_outer,
                                            const NearSolution* near) {
  SphereRefraction out;
  // Across the axis, in units of the radius: the outer point at (b, 0) on e1, the inner one at
  // (a1, a2); along it, the outer point dz above the inner one; y(φ, z) = (cos φ, sin φ, z).
  const Vec3 to_outer = outer - on_axis, to_inner = inner - on_axis;
  const double z_outer = dot(to_outer, axis), z_inner = dot(to_inner, axis);
  const Vec3 outer_across = to_outer - axis * z_outer, inner_across = to_inner - axis * z_inner;
  const double b = length(outer_across) / radius_m;
  if (!(b > 1.0) || !(length(inner_across) < radius_m)) return out;
  const Vec3 e1 = outer_across / (b * radius_m), e2 = cross(axis, e1);
  const double a1 = dot(inner_across, e1) / radius_m, a2 = dot(inner_across, e2) / radius_m;
  const double dz = (z_outer - z_inner) / radius_m;
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
  struct Passage {
    bool valid = false;
    double side = 0.0, y2x = 0.0, y2y = 0.0;
  };
  // The ray from `from` through y1(φ), refracted in, across the circle, refracted out: where `to`
  // lies from it (the cross product of its direction with y2 → to; 0 on it), if it gets out and
  // `to` is ahead.
  auto passage_cs = [&](double y1x, double y1y) {
    Passage p;
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
    if (!(cos_o > 0.0) || sin_u2 >= 1.0) return p;
    const double m = std::sqrt(1.0 - sin_u2) - inv * cos_o;
    const double ox = inv * tx + m * p.y2x, oy = inv * ty + m * p.y2y;
    const double rx = b1 - p.y2x, ry = b2 - p.y2y;
    if (!(ox * rx + oy * ry > 0.0)) return p;
    p.valid = true;
    p.side = ox * ry - oy * rx;  // (its sign and roots are all the scan needs)
    return p;
  };
  auto passage = [&](double phi) { return passage_cs(std::cos(phi), std::sin(phi)); };
  const double phi_max = std::acos(1.0 / a) * (1.0 - 1e-12);
  const auto [first, last, intervals] = scan_range(phi_max, near, centre, e1, e2, 16);
  auto side = [&](double phi) {
    const Passage p = passage(phi);
    return p.valid ? p.side : std::numeric_limits<double>::quiet_NaN();
  };
  // An interval whose ends both pass and lie on opposite sides holds a path; one whose ends
  // differ in whether they pass (an edge of total internal reflection, or of `to` being ahead)
  // may hold a narrow window that does: split it in four, three times over.
  auto interval = [&](auto& self, double lo, double hi, const Passage& p_lo, const Passage& p_hi, int depth) -> void {
    if (out.count >= static_cast<int>(out.entry.size())) return;
    if (p_lo.valid && p_hi.valid) {
      if (p_hi.side == 0.0 || (p_lo.side != 0.0 && (p_lo.side < 0.0) == (p_hi.side < 0.0))) return;
      const std::optional<double> phi = p_lo.side == 0.0 ? lo : bracketed_root(side, lo, hi, p_lo.side, p_hi.side);
      const Passage pr = phi ? passage(*phi) : Passage{};
      if (pr.valid) {
        const auto k = static_cast<std::size_t>(out.count++);
        out.entry[k] = centre + (e1 * std::cos(*phi) + e2 * std::sin(*phi)) * radius_m;
        out.exit[k] = centre + (e1 * pr.y2x + e2 * pr.y2y) * radius_m;
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
  return out;
}

CasterPathDensities caster_path_densities(const RenderScene& s, const ManifoldCaster& c, const Vec3& x,
                                          const std::array<Vec3, 2>& ys, int crossings, const Hit& light_hit) {
  using namespace manifold_detail;
  CasterPathDensities out;
  const Interface f = caster_interface(s, c);
  const double eta_front = s.media[static_cast<std::size_t>(f.medium_front)].ior_reference;
  const double eta_behind = s.media[static_cast<std::size_t>(f.medium_behind)].ior_reference;
  const Vec3& q = light_hit.point;
  // The walk's refraction choices, at the crossings where it made them.
  Vec3 from = x;
  bool front = f.front(x);
  for (int k = 0; k < crossings; ++k) {
    const Vec3 y = ys[static_cast<std::size_t>(k)], n = f.normal_at(y), d = normalize(y - from);
    const double eta_i = front ? eta_front : eta_behind, eta_t = front ? eta_behind : eta_front;
    const double cos_i = std::abs(dot(d, n)), cos_t = cos_theta_transmitted(cos_i, eta_i, eta_t);
    out.refraction *= cos_t > 0.0 ? 1.0 - fresnel_dielectric(cos_i, cos_t, eta_i, eta_t) : 0.0;
    from = y, front = !front;
  }
  // The point's density: the light's choice by power, its point by area (a sphere: on its cap).
  const Surface& surface = s.surfaces[light_hit.geometry];
  const auto index = static_cast<std::size_t>(surface.first_light) + light_hit.primitive;
  const Light& light = s.lights[index];
  double area_pdf = 0.0;
  if (const auto* a = std::get_if<AreaLight>(&light)) {
    area_pdf = a->area_m2 > 0.0 ? 1.0 / a->area_m2 : 0.0;
  } else if (const auto* sphere = std::get_if<SphereLight>(&light)) {
    const auto cap = facing_cap(*sphere, c);
    if (cap && dot(normalize(q - sphere->centre_m), cap->axis) > cap->mu0) area_pdf = cap->pdf_area;
  }
  area_pdf *= s.area_lights.pmf[index];
  if (!(area_pdf > 0.0)) return out;
  // The connection's own solve for this point, the path among its solutions (to the walk's
  // single precision), and the ray tube there.
  const Paths paths = solve(f, x, q, eta_front, eta_behind);
  if (paths.crossings != crossings) return out;
  const double tolerance = 1e-5 * (c.radius_m + length(q - x));
  for (int k = 0; k < paths.count; ++k) {
    const auto& exact = paths.crossing[static_cast<std::size_t>(k)];
    if (length(exact[0] - ys[0]) > tolerance) continue;
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
