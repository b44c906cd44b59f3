#include "bouguer/geometry/shapes.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <numbers>
#include <sstream>

#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/geometry/ply.h"
#include "bouguer/core/csv.h"
#include "bouguer/core/limits.h"

namespace bouguer {
namespace {

constexpr double kPi = std::numbers::pi;
double radians(double deg) { return deg * kPi / 180.0; }

// ---- convex shapes as intersections of half-spaces dot(n, x) <= d ----------------------------

struct Plane {
  Vec3 n;  // unit, outward
  double d;
};

Plane plane_through(const Vec3& normal, const Vec3& point) {
  const Vec3 n = normalize(normal);
  return {n, dot(n, point)};
}

std::vector<Vec3> clip(const std::vector<Vec3>& poly, const Plane& p) {
  std::vector<Vec3> out;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Vec3& a = poly[i];
    const Vec3& b = poly[(i + 1) % poly.size()];
    const double da = dot(p.n, a) - p.d, db = dot(p.n, b) - p.d;
    if (da <= 0.0) out.push_back(a);
    if ((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0)) out.push_back(a + (b - a) * (da / (da - db)));
  }
  return out;
}

double polygon_area(const std::vector<Vec3>& poly) {
  Vec3 sum;
  for (std::size_t i = 1; i + 1 < poly.size(); ++i) sum += cross(poly[i] - poly[0], poly[i + 1] - poly[0]);
  return 0.5 * length(sum);
}

// Each plane's face is a large square on the plane clipped by all other planes; faces that
// shrink to nothing are dropped, so superfluous planes are harmless. `scale_m` bounds the shape.
Mesh convex_from_planes(const std::vector<Plane>& planes, double scale_m) {
  Mesh out;
  const double tolerance = 1e-9 * scale_m;
  for (std::size_t i = 0; i < planes.size(); ++i) {
    const Vec3 n = planes[i].n;
    const Vec3 u = normalize(cross(std::abs(n.y) < 0.9 ? Vec3{0, 1, 0} : Vec3{1, 0, 0}, n));
    const Vec3 v = cross(n, u);  // u × v = n: the square below runs counter-clockwise about n
    const Vec3 c = n * planes[i].d;
    const double big = 4.0 * scale_m;
    std::vector<Vec3> poly = {c - u * big - v * big, c + u * big - v * big, c + u * big + v * big,
                              c - u * big + v * big};
    for (std::size_t j = 0; j < planes.size() && poly.size() >= 3; ++j)
      if (j != i) poly = clip(poly, planes[j]);
    std::vector<Vec3> clean;
    for (const Vec3& p : poly)
      if (clean.empty() || length(p - clean.back()) > tolerance) clean.push_back(p);
    while (clean.size() > 1 && length(clean.front() - clean.back()) <= tolerance) clean.pop_back();
    if (clean.size() < 3 || polygon_area(clean) <= tolerance * tolerance) continue;
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    out.positions.insert(out.positions.end(), clean.begin(), clean.end());
    for (std::uint32_t k = 1; k + 1 < clean.size(); ++k) out.triangles.push_back({base, base + k, base + k + 1});
  }
  return welded(out, tolerance);
}

// ---- surfaces of revolution about +y ---------------------------------------------------------

using Profile = std::vector<std::array<double, 2>>;

// Revolves (r, y) points about +y. A profile walked with increasing y at the outside gives outward
// normals. Each vertex carries the exact normal of the surface of revolution at its angle, from
// the profile's normal there: the mean of its two segments' normals where they turn by at most
// crease_angle_deg (the polyline samples a smooth curve: a circle's points get its radial normal
// exactly), each segment's own where they turn more (a crease: two rings at the same place). A
// point with r = 0 is one vertex on the axis, normal ±y, unless its segment meets the axis at more
// than the crease angle (a cone's apex: one vertex per segment, with that segment's normal).
Mesh revolve(const Profile& profile_in, int segments, double crease_angle_deg) {
  Profile profile;  // repeated points say nothing about the normal
  for (const auto& p : profile_in)
    if (profile.empty() || p != profile.back()) profile.push_back(p);
  const std::size_t n = profile.size();
  if (n < 2) return {};  // no surface: the closedness check says so
  std::vector<std::array<double, 2>> seg(n > 0 ? n - 1 : 0);  // each segment's unit normal in (r, y)
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double dr = profile[i + 1][0] - profile[i][0], dy = profile[i + 1][1] - profile[i][1], l = std::hypot(dr, dy);
    seg[i] = {dy / l, -dr / l};
  }
  const double cos_crease = std::cos(radians(crease_angle_deg));
  auto unit = [](std::array<double, 2> a) {
    const double l = std::hypot(a[0], a[1]);
    return l > 0.0 ? std::array<double, 2>{a[0] / l, a[1] / l} : a;
  };
  Mesh m;
  // A ring of vertices at profile point j with normal nrm; `apex`: one vertex per segment, each
  // with the normal at the middle of its wedge.
  auto ring = [&](std::size_t j, std::array<double, 2> nrm, bool apex) {
    const auto [r, y] = profile[j];
    std::vector<std::uint32_t> idx;
    const int count = r == 0.0 && !apex ? 1 : segments;
    for (int k = 0; k < count; ++k) {
      const double th = 2.0 * kPi * (k + (apex ? 0.5 : 0.0)) / segments;
      idx.push_back(static_cast<std::uint32_t>(m.positions.size()));
      m.positions.push_back({r * std::cos(2.0 * kPi * k / segments), y, r * std::sin(2.0 * kPi * k / segments)});
      m.normals.push_back(count == 1 ? Vec3{0.0, nrm[1] >= 0.0 ? 1.0 : -1.0, 0.0}
                                     : Vec3{nrm[0] * std::cos(th), nrm[1], nrm[0] * std::sin(th)});
    }
    return idx;
  };
  // below[j] / above[j]: the ring the segment below / above point j uses.
  std::vector<std::vector<std::uint32_t>> below(n), above(n);
  for (std::size_t j = 0; j < n; ++j) {
    const bool has_below = j > 0, has_above = j + 1 < n;
    const auto nb = has_below ? seg[j - 1] : seg[j], na = has_above ? seg[j] : seg[j - 1];
    if (profile[j][0] == 0.0) {  // on the axis
      if (has_below) below[j] = ring(j, nb, std::abs(nb[1]) < cos_crease);
      if (has_above) above[j] = ring(j, na, std::abs(na[1]) < cos_crease);
      continue;
    }
    if (nb[0] * na[0] + nb[1] * na[1] >= cos_crease) {
      below[j] = above[j] = ring(j, unit({nb[0] + na[0], nb[1] + na[1]}), false);
    } else {
      if (has_below) below[j] = ring(j, nb, false);
      if (has_above) above[j] = ring(j, na, false);
    }
  }
  auto at = [&](const std::vector<std::uint32_t>& r, int k) { return r[r.size() == 1 ? 0 : k % r.size()]; };
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const auto &a = above[i], &b = below[i + 1];
    const bool a_axis = profile[i][0] == 0.0, b_axis = profile[i + 1][0] == 0.0;
    if (a_axis && b_axis) continue;
    for (int k = 0; k < segments; ++k) {
      if (!a_axis) m.triangles.push_back({at(a, k), at(b, k), at(a, k + 1)});
      if (!b_axis) m.triangles.push_back({at(a, a_axis ? k : k + 1), at(b, k), at(b, k + 1)});
    }
  }
  return m;
}

double profile_scale(const Profile& p) {
  double s = 0.0;
  for (const auto& [r, y] : p) s = std::max({s, std::abs(r), std::abs(y)});
  return s;
}

Mesh regular_polygon_planes_shape(int sides, double radius, double height, bool apex, const std::string& what) {
  if (sides < 3) fail("{}: 'sides' must be at least 3 (got {})", what, sides);
  std::vector<Plane> planes = {{{0, -1, 0}, 0.0}};
  if (!apex) planes.push_back({{0, 1, 0}, height});
  const Vec3 top{0, height, 0};
  for (int k = 0; k < sides; ++k) {
    const double a0 = 2.0 * kPi * k / sides, a1 = 2.0 * kPi * (k + 1) / sides;
    const Vec3 v0{radius * std::cos(a0), 0, radius * std::sin(a0)}, v1{radius * std::cos(a1), 0, radius * std::sin(a1)};
    if (apex) {
      planes.push_back(plane_through(cross(top - v0, v1 - v0), v0));
    } else {
      const double mid = 0.5 * (a0 + a1);
      planes.push_back(plane_through({std::cos(mid), 0, std::sin(mid)}, v0));
    }
  }
  return convex_from_planes(planes, std::max(radius, height));
}

// ---- one function per shape ------------------------------------------------------------------

void require_positive(double v, const char* name, const std::string& what) {
  if (!(v > 0.0) || !std::isfinite(v)) fail("{}: '{}' must be a positive length (got {} m)", what, name, v);
}

void require_segments(int segments, const std::string& what) {
  if (segments < 3 || segments > 4096) fail("{}: 'segments' must be between 3 and 4096 (got {})", what, segments);
}

Mesh make_quad(const QuadShape& q, const std::string& what) {
  require_positive(q.width_m, "size", what);
  require_positive(q.height_m, "size", what);
  const double w = q.width_m / 2, h = q.height_m / 2;
  Mesh m;
  m.positions = {{-w, -h, 0}, {w, -h, 0}, {w, h, 0}, {-w, h, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // the quad's own parametrisation, for textures
  return m;
}

Mesh make_disk(const DiskShape& d, const std::string& what) {
  require_positive(d.radius_m, "radius", what);
  require_segments(d.segments, what);
  Mesh m;
  m.positions.push_back({0, 0, 0});
  for (int k = 0; k < d.segments; ++k) {
    const double th = 2.0 * kPi * k / d.segments;
    m.positions.push_back({d.radius_m * std::cos(th), d.radius_m * std::sin(th), 0});
  }
  for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(d.segments); ++k)
    m.triangles.push_back({0, k + 1, (k + 1) % static_cast<std::uint32_t>(d.segments) + 1});
  return m;
}

Mesh make_box(const BoxShape& b, const std::string& what) {
  for (int i = 0; i < 3; ++i) require_positive(b.size_m[i], "size", what);
  const Vec3 h = b.size_m * 0.5;
  return convex_from_planes({{{1, 0, 0}, h.x}, {{-1, 0, 0}, h.x}, {{0, 1, 0}, h.y}, {{0, -1, 0}, h.y},
                             {{0, 0, 1}, h.z}, {{0, 0, -1}, h.z}},
                            std::max({h.x, h.y, h.z}));
}

Mesh make_sphere(const SphereShape& s, const std::string& what) {
  require_positive(s.radius_m, "radius", what);
  require_segments(s.segments, what);
  Profile p;
  const int rings = std::max(2, s.segments / 2);
  for (int i = 0; i <= rings; ++i) {
    const double phi = kPi * i / rings;  // from the south pole up
    p.push_back({i == 0 || i == rings ? 0.0 : s.radius_m * std::sin(phi), -s.radius_m * std::cos(phi)});
  }
  return revolve(p, s.segments, 90.0);  // 90°: the poles' segments are smooth, never a crease
}

Mesh make_cylinder(const CylinderShape& c, const std::string& what) {
  require_positive(c.radius_m, "radius", what);
  require_positive(c.height_m, "height", what);
  require_segments(c.segments, what);
  return revolve({{0, 0}, {c.radius_m, 0}, {c.radius_m, c.height_m}, {0, c.height_m}}, c.segments, kDefaultCreaseAngleDeg);
}

Mesh make_truncated_cube(const TruncatedCubeShape& t, const std::string& what) {
  require_positive(t.size_m, "size", what);
  if (!(t.truncation > 0.0 && t.truncation < 0.5))
    fail("{}: 'truncation' must be between 0 and 0.5 (fraction of each edge cut at each end; got {})", what,
         t.truncation);
  const double h = t.size_m / 2;
  std::vector<Plane> planes = {{{1, 0, 0}, h}, {{-1, 0, 0}, h}, {{0, 1, 0}, h},
                               {{0, -1, 0}, h}, {{0, 0, 1}, h}, {{0, 0, -1}, h}};
  for (int sx : {-1, 1})
    for (int sy : {-1, 1})
      for (int sz : {-1, 1}) {
        const Vec3 corner{sx * h, sy * h, sz * h};
        planes.push_back(plane_through({double(sx), double(sy), double(sz)},
                                       corner - Vec3{sx * t.truncation * t.size_m, 0, 0}));
      }
  return convex_from_planes(planes, h);
}

// Facets of a round brilliant (Tolkowsky-style): table, 8 bezels, 8 stars, 16 upper girdle
// facets, a 32-sided girdle, 8 pavilion mains and 16 lower girdle facets.
Mesh make_brilliant(const BrilliantShape& b, const std::string& what) {
  require_positive(b.diameter_m, "diameter", what);
  if (!(b.table > 0.2 && b.table < 0.9)) fail("{}: 'table' must be between 0.2 and 0.9 of the diameter", what);
  if (!(b.crown_angle_deg > 10 && b.crown_angle_deg < 60)) fail("{}: 'crown_angle_deg' must be 10-60", what);
  if (!(b.pavilion_angle_deg > 30 && b.pavilion_angle_deg < 60)) fail("{}: 'pavilion_angle_deg' must be 30-60", what);
  if (!(b.girdle >= 0.0 && b.girdle < 0.2)) fail("{}: 'girdle' must be between 0 and 0.2 of the diameter", what);
  const double r = b.diameter_m / 2, g = b.girdle * b.diameter_m / 2;
  const double crown = radians(b.crown_angle_deg), pavilion = radians(b.pavilion_angle_deg);
  const double table_y = g + (r - b.table * r) * std::tan(crown);
  auto facet = [](double azimuth, double inclination, double sign_y) {
    return Vec3{std::sin(inclination) * std::cos(azimuth), sign_y * std::cos(inclination),
                std::sin(inclination) * std::sin(azimuth)};
  };
  auto rim = [&](double azimuth, double y, double radius) {
    return Vec3{radius * std::cos(azimuth), y, radius * std::sin(azimuth)};
  };
  std::vector<Plane> planes = {{{0, 1, 0}, table_y}};
  for (int k = 0; k < 32; ++k) {
    const double a = 2.0 * kPi * (k + 0.5) / 32;
    planes.push_back({{std::cos(a), 0, std::sin(a)}, r});
  }
  const double star = crown - radians(13.0), upper = crown + radians(7.0), lower = pavilion + radians(1.5);
  const double table_corner = b.table * r / std::cos(kPi / 8);
  for (int k = 0; k < 8; ++k) {
    const double main = 2.0 * kPi * k / 8, between = main + kPi / 8;
    planes.push_back(plane_through(facet(main, crown, 1), rim(main, g, r)));
    planes.push_back(plane_through(facet(between, star, 1), rim(between, table_y, table_corner)));
    planes.push_back(plane_through(facet(main, pavilion, -1), rim(main, -g, r)));
  }
  for (int k = 0; k < 16; ++k) {
    const double a = 2.0 * kPi * (k + 0.5) / 16;
    planes.push_back(plane_through(facet(a, upper, 1), rim(a, g, r)));
    planes.push_back(plane_through(facet(a, lower, -1), rim(a, -g, r)));
  }
  return convex_from_planes(planes, r * 2);
}

void require_crease_angle(double deg, const std::string& what) {
  if (!(deg >= 0.0 && deg <= 180.0)) fail("{}: 'crease_angle_deg' must be between 0 and 180 (got {})", what, deg);
}

void validate_profile(const Profile& p, const std::string& what) {
  if (p.size() < 2) fail("{}: 'profile' needs at least two [r, y] points", what);
  for (const auto& [r, y] : p)
    if (!(r >= 0.0) || !std::isfinite(r) || !std::isfinite(y))
      fail("{}: 'profile' radii must be finite and >= 0 (got [{}, {}])", what, r, y);
}

Mesh make_lathe(const LatheShape& l, const std::string& what) {
  validate_profile(l.profile_m, what);
  require_segments(l.segments, what);
  require_crease_angle(l.crease_angle_deg, what);
  Mesh m = welded(revolve(l.profile_m, l.segments, l.crease_angle_deg), 1e-9 * profile_scale(l.profile_m), true);
  return signed_volume(m) < 0.0 ? flipped(std::move(m)) : m;
}

// Intersection of the lines p + s·d and q + t·e in the (r, y) plane.
std::array<double, 2> line_intersection(std::array<double, 2> p, std::array<double, 2> d, std::array<double, 2> q,
                                        std::array<double, 2> e) {
  const double den = d[0] * e[1] - d[1] * e[0];
  if (std::abs(den) < 1e-12) return q;  // parallel: consecutive offsets meet at the shared offset point
  const double s = ((q[0] - p[0]) * e[1] - (q[1] - p[1]) * e[0]) / den;
  return {p[0] + s * d[0], p[1] + s * d[1]};
}

// The inner wall: each outer segment moved inward (to its left, walking up) by the wall thickness.
Profile inner_profile(const Profile& outer, double wall, const std::string& what) {
  const std::size_t n = outer.size();
  std::vector<std::array<double, 2>> dir(n - 1), start(n - 1);
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double dr = outer[i + 1][0] - outer[i][0], dy = outer[i + 1][1] - outer[i][1], len = std::hypot(dr, dy);
    if (len == 0.0) fail("{}: 'profile' repeats the point [{}, {}]", what, outer[i][0], outer[i][1]);
    dir[i] = {dr / len, dy / len};
    start[i] = {outer[i][0] - dir[i][1] * wall, outer[i][1] + dir[i][0] * wall};
  }
  Profile inner = {line_intersection(start[0], dir[0], {0.0, 0.0}, {0.0, 1.0})};
  for (std::size_t i = 1; i + 1 < n; ++i) inner.push_back(line_intersection(start[i - 1], dir[i - 1], start[i], dir[i]));
  inner.push_back(line_intersection(start[n - 2], dir[n - 2], {0.0, outer.back()[1]}, {1.0, 0.0}));
  for (std::size_t i = 0; i < inner.size(); ++i) {
    if (inner[i][0] < -1e-12 || (i > 0 && inner[i][1] < inner[i - 1][1] - 1e-12))
      fail("{}: the wall thickness does not fit the profile (the inner wall would cross itself near [{}, {}] m)", what,
           outer[std::min(i, n - 1)][0], outer[std::min(i, n - 1)][1]);
    inner[i][0] = std::max(inner[i][0], 0.0);
  }
  return inner;
}

std::vector<ShapePart> make_vessel(const VesselShape& v, const std::string& what) {
  validate_profile(v.profile_m, what);
  require_crease_angle(v.crease_angle_deg, what);
  require_positive(v.wall_m, "wall", what);
  require_segments(v.segments, what);
  const Profile& outer = v.profile_m;
  if (outer.front()[0] != 0.0) fail("{}: a vessel 'profile' starts at the bottom centre, r = 0", what);
  if (outer.back()[0] <= v.wall_m) fail("{}: the rim radius must exceed the wall thickness", what);
  if (!(v.fill >= 0.0 && v.fill <= 1.0)) fail("{}: 'fill' must be between 0 and 1 (got {})", what, v.fill);
  const Profile inner = inner_profile(outer, v.wall_m, what);
  const double y_bottom = inner.front()[1], y_top = inner.back()[1];
  const double scale = profile_scale(outer), tolerance = 1e-9 * scale;

  // Inner wall walked from the rim down, split at the fill level.
  Profile dry = {inner.back()}, wet;
  const double y_fill = y_bottom + v.fill * (y_top - y_bottom);
  std::array<double, 2> fill_point = inner.back();
  for (std::size_t i = inner.size() - 1; i-- > 0;) {
    const auto &hi = inner[i + 1], &lo = inner[i];
    if (v.fill > 0.0 && wet.empty() && lo[1] < y_fill && hi[1] >= y_fill) {
      const double t = (y_fill - lo[1]) / (hi[1] - lo[1]);
      fill_point = {lo[0] + t * (hi[0] - lo[0]), y_fill};
      if (hi[1] > y_fill) dry.push_back(fill_point);
      wet = {fill_point};
    }
    (wet.empty() ? dry : wet).push_back(lo);
  }
  Profile outside = outer;
  outside.push_back(inner.back());  // the rim
  std::vector<ShapePart> parts;
  const double crease = v.crease_angle_deg;
  parts.push_back({revolve(outside, v.segments, crease), Side::object, Side::surroundings});
  if (dry.size() > 1) parts.push_back({revolve(dry, v.segments, crease), Side::object, Side::surroundings});
  if (v.fill > 0.0) {
    parts.push_back({revolve(wet, v.segments, crease), Side::object, Side::contents});
    parts.push_back({revolve({fill_point, {0.0, y_fill}}, v.segments, crease), Side::contents, Side::surroundings});
  }
  for (auto& p : parts) p.mesh = welded(p.mesh, tolerance, true);
  return parts;
}

// tinyobjloader reads a number it cannot parse ("nan", "inf", "1.2.3", "x") as 0; so the numbers of
// every v, vt and vn line are checked here first, naming the line of the first that is not a
// finite number.
void check_numbers(std::string_view text, const std::string& where, std::initializer_list<std::string_view> keys) {
  std::size_t line_start = 0;
  for (int line = 1; line_start < text.size(); ++line) {
    std::size_t end = text.find('\n', line_start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view l = text.substr(line_start, end - line_start);
    line_start = end + 1;
    const auto first = l.find_first_not_of(" \t");
    if (first == std::string_view::npos) continue;
    l.remove_prefix(first);
    const auto key_end = std::min(l.find_first_of(" \t"), l.size());
    if (std::find(keys.begin(), keys.end(), l.substr(0, key_end)) == keys.end()) continue;
    l.remove_prefix(key_end);
    for (std::size_t i = 0; i < l.size();) {
      if (l[i] == ' ' || l[i] == '\t' || l[i] == '\r') {
        ++i;
        continue;
      }
      if (l[i] == '#') break;
      const std::size_t token_end = std::min(l.find_first_of(" \t\r", i), l.size());
      std::string_view token = l.substr(i, token_end - i);
      i = token_end;
      if (token.starts_with('+')) token.remove_prefix(1);
      double v = 0.0;
      const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), v);
      if (ec != std::errc{} || ptr != token.data() + token.size() || !std::isfinite(v))
        fail("{}, line {}: '{}' is not a finite number", where, line, excerpt(token));
    }
  }
}

// MTL files named by `mtllib`, read with the same checks as every other file (no folders,
// devices or FIFOs; at most kMaxTextFileBytes). A missing one is a warning in tinyobjloader, as
// before: Bouguer takes only geometry from OBJ files.
// With `materials` (load_obj_materials) a missing MTL is an Error, and the numbers of its Kd lines
// are checked as the OBJ's are (tinyobjloader reads "nan" as 0 there too).
class CheckedMaterialReader : public tinyobj::MaterialReader {
 public:
  CheckedMaterialReader(std::filesystem::path folder, std::string where, bool materials = false)
      : folder_(std::move(folder)), where_(std::move(where)), materials_(materials) {}
  bool operator()(const std::string& id, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* names, std::string* warn, std::string* err) override {
    const std::filesystem::path path = folder_ / id;
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      if (materials_) fail("{}: mtllib '{}' not found", where_, excerpt(id));
      if (warn) *warn += "material file not found: " + id + "\n";
      return false;
    }
    std::string text;
    try {
      text = read_text_file(path, kMaxTextFileBytes);
    } catch (const Error& e) {
      fail("{}: mtllib '{}': {}", where_, excerpt(id), e.what());
    }
    if (materials_) check_numbers(text, path.string(), {"Kd"});
    std::istringstream in(text);
    tinyobj::LoadMtl(names, materials, &in, warn, err);
    return true;
  }

 private:
  std::filesystem::path folder_;
  std::string where_;
  bool materials_;
};

// The OBJ's corners as mesh vertices: one per distinct (position, texture coordinate, normal)
// triple, so a seam in the UVs or a crease in the normals keeps both sides. UVs and normals are
// kept only when every corner has one.
struct ObjCorners {
  Mesh mesh;
  std::vector<Vec3> normals;
  std::vector<std::array<double, 2>> uvs;
};

ObjCorners obj_corners(const tinyobj::attrib_t& attrib, const std::vector<tinyobj::shape_t>& shapes,
                       const std::vector<Vec3>& positions, const std::string& where) {
  bool all_uv = !attrib.texcoords.empty(), all_normal = !attrib.normals.empty();
  for (const auto& shape : shapes)
    for (const auto& i : shape.mesh.indices) {
      all_uv = all_uv && i.texcoord_index >= 0 && static_cast<std::size_t>(i.texcoord_index) * 2 + 1 < attrib.texcoords.size();
      all_normal = all_normal && i.normal_index >= 0 && static_cast<std::size_t>(i.normal_index) * 3 + 2 < attrib.normals.size();
    }
  ObjCorners c;
  std::map<std::array<int, 3>, std::uint32_t> index;
  for (const auto& shape : shapes) {
    const auto& idx = shape.mesh.indices;
    if (c.mesh.triangles.size() + idx.size() / 3 > kMaxMeshTriangles)
      fail("{}: more than {} triangles (docs/limits.md)", where, kMaxMeshTriangles);
    for (std::size_t i = 0; i + 2 < idx.size(); i += 3) {
      std::array<std::uint32_t, 3> t;
      for (std::size_t k = 0; k < 3; ++k) {
        const tinyobj::index_t& corner = idx[i + k];
        if (corner.vertex_index < 0 || static_cast<std::size_t>(corner.vertex_index) >= positions.size())
          fail("{} has a face with a vertex index out of range", where);
        const std::array<int, 3> key{corner.vertex_index, all_uv ? corner.texcoord_index : -1,
                                     all_normal ? corner.normal_index : -1};
        const auto [at, added] = index.try_emplace(key, static_cast<std::uint32_t>(c.mesh.positions.size()));
        if (added) {
          c.mesh.positions.push_back(positions[static_cast<std::size_t>(key[0])]);
          const auto ti = static_cast<std::size_t>(key[1]) * 2, ni = static_cast<std::size_t>(key[2]) * 3;
          if (all_uv) c.uvs.push_back({attrib.texcoords[ti], attrib.texcoords[ti + 1]});
          if (all_normal) c.normals.push_back({attrib.normals[ni], attrib.normals[ni + 1], attrib.normals[ni + 2]});
        }
        t[k] = at->second;
      }
      c.mesh.triangles.push_back(t);
    }
  }
  return c;
}

Mesh checked_triangles(const TriangleMeshShape& s, const std::string& what);

// An OBJ parsed by tinyobjloader after the checks above, its positions checked and bounded.
struct ParsedObj {
  std::string where;  // "object 'x': 'file.obj'"
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::vector<Vec3> positions;
};

ParsedObj parse_obj(const std::filesystem::path& path, const std::string& what, bool materials) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) fail("{}: mesh file '{}' not found", what, path.string());
  ParsedObj obj;
  obj.where = fmt::format("{}: '{}'", what, path.string());
  const std::string& where = obj.where;
  std::string text;
  try {
    text = read_text_file(path, kMaxMeshFileBytes);
  } catch (const Error& e) {
    fail("{}: {}", what, e.what());
  }
  check_numbers(text, where, {"v", "vt", "vn"});
  std::istringstream in(text);
  std::string warn, err;
  CheckedMaterialReader mtl(path.parent_path(), where, materials);
  if (!tinyobj::LoadObj(&obj.attrib, &obj.shapes, &obj.materials, &warn, &err, &in, &mtl, /*triangulate=*/true))
    fail("{}: cannot read it: {}", where, excerpt(err, 200));
  const auto& vertices = obj.attrib.vertices;
  if (vertices.size() / 3 > kMaxMeshVertices) fail("{}: more than {} vertices (docs/limits.md)", where, kMaxMeshVertices);
  obj.positions.reserve(vertices.size() / 3);
  for (std::size_t i = 0; i + 2 < vertices.size(); i += 3) {
    const Vec3 p{vertices[i], vertices[i + 1], vertices[i + 2]};
    for (int axis = 0; axis < 3; ++axis) {
      const double v = p[static_cast<std::size_t>(axis)];
      if (!std::isfinite(v))
        fail("{}: vertex {}: {} is {}, not a finite number", where, i / 3 + 1, "xyz"[axis], v);
      if (std::abs(v) > kMaxMeshCoordinate)
        fail("{}: vertex {}: {} = {} is beyond ±{} (docs/limits.md)", where, i / 3 + 1, "xyz"[axis], v,
             kMaxMeshCoordinate);
    }
    obj.positions.push_back(p);
  }
  return obj;
}

Mesh corner_mesh(const ParsedObj& obj, const std::vector<tinyobj::shape_t>& shapes) {
  ObjCorners c = obj_corners(obj.attrib, shapes, obj.positions, obj.where);
  if (c.mesh.triangles.empty()) fail("{} has no faces", obj.where);
  return checked_triangles(TriangleMeshShape{std::move(c.mesh), std::move(c.normals), std::move(c.uvs), {}}, obj.where);
}

Mesh load_obj(const MeshShape& s, const std::string& what) {
  const ParsedObj obj = parse_obj(s.path, what, false);
  return corner_mesh(obj, obj.shapes);
}

Mesh load_mesh(const MeshShape& s, const std::string& what) {
  std::string ext = s.path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".obj") return load_obj(s, what);
  if (ext == ".ply") return load_ply(s.path, what);
  fail("{}: mesh files must be .obj or .ply (got '{}')", what, s.path.string());
}

Mesh checked_triangles(const TriangleMeshShape& s, const std::string& what) {
  const std::size_t n = s.mesh.positions.size();
  if (s.mesh.triangles.empty()) fail("{}: the triangle mesh has no triangles", what);
  if (!s.normals.empty() && s.normals.size() != n) fail("{}: {} normals for {} positions", what, s.normals.size(), n);
  if (!s.uvs.empty() && s.uvs.size() != n) fail("{}: {} UVs for {} positions", what, s.uvs.size(), n);
  if (!s.tangents.empty() && s.tangents.size() != n)
    fail("{}: {} tangents for {} positions", what, s.tangents.size(), n);
  if (!s.tangents.empty() && s.normals.empty()) fail("{}: tangents need normals", what);
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& p = s.mesh.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      fail("{}: position {} is not finite", what, i);
  }
  for (std::size_t t = 0; t < s.mesh.triangles.size(); ++t)
    for (const std::uint32_t v : s.mesh.triangles[t])
      if (v >= n) fail("{}: triangle {} names vertex {}, but there are {}", what, t, v, n);
  Mesh m = s.mesh;
  m.normals.clear();
  m.uvs.clear();
  m.tangents.clear();
  if (!s.normals.empty()) {
    m.normals.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3& v = s.normals[i];
      const double l = length(v);
      if (!std::isfinite(l) || l == 0.0) fail("{}: normal {} is not a finite, non-zero vector", what, i);
      m.normals.push_back(v / l);
    }
  }
  for (std::size_t i = 0; i < s.uvs.size(); ++i)
    if (!std::isfinite(s.uvs[i][0]) || !std::isfinite(s.uvs[i][1])) fail("{}: UV {} is not finite", what, i);
  m.uvs = s.uvs;
  for (std::size_t i = 0; i < s.tangents.size(); ++i) {
    const Tangent& t = s.tangents[i];
    const double l = length(t.direction);
    if (!std::isfinite(l) || l == 0.0 || (t.sign != 1.0 && t.sign != -1.0))
      fail("{}: tangent {} is not a finite, non-zero vector with a sign of ±1", what, i);
    m.tangents.push_back({t.direction / l, t.sign});
  }
  return m;
}

}  // namespace

std::vector<ShapePart> make_shape(const Shape& shape, const std::string& what) {
  struct Visitor {
    const std::string& what;
    std::vector<ShapePart> one(Mesh m) const { return {ShapePart{std::move(m), Side::object, Side::surroundings}}; }
    std::vector<ShapePart> operator()(const QuadShape& s) const { return one(make_quad(s, what)); }
    std::vector<ShapePart> operator()(const DiskShape& s) const { return one(make_disk(s, what)); }
    std::vector<ShapePart> operator()(const BoxShape& s) const { return one(make_box(s, what)); }
    std::vector<ShapePart> operator()(const SphereShape& s) const { return one(make_sphere(s, what)); }
    std::vector<ShapePart> operator()(const CylinderShape& s) const { return one(make_cylinder(s, what)); }
    std::vector<ShapePart> operator()(const PrismShape& s) const {
      require_positive(s.radius_m, "radius", what);
      require_positive(s.height_m, "height", what);
      return one(regular_polygon_planes_shape(s.sides, s.radius_m, s.height_m, false, what));
    }
    std::vector<ShapePart> operator()(const PyramidShape& s) const {
      require_positive(s.radius_m, "radius", what);
      require_positive(s.height_m, "height", what);
      return one(regular_polygon_planes_shape(s.sides, s.radius_m, s.height_m, true, what));
    }
    std::vector<ShapePart> operator()(const TruncatedCubeShape& s) const { return one(make_truncated_cube(s, what)); }
    std::vector<ShapePart> operator()(const BrilliantShape& s) const { return one(make_brilliant(s, what)); }
    std::vector<ShapePart> operator()(const LatheShape& s) const { return one(make_lathe(s, what)); }
    std::vector<ShapePart> operator()(const VesselShape& s) const { return make_vessel(s, what); }
    std::vector<ShapePart> operator()(const MeshShape& s) const { return one(load_mesh(s, what)); }
    std::vector<ShapePart> operator()(const TriangleMeshShape& s) const { return one(checked_triangles(s, what)); }
  };
  return std::visit(Visitor{what}, shape);
}

std::optional<AnalyticSurface> analytic_surface(const Shape& shape, const std::string& what) {
  if (const auto* s = std::get_if<SphereShape>(&shape); s && !s->tessellate) {
    require_positive(s->radius_m, "radius", what);
    return SphereSurface{s->radius_m};
  }
  if (const auto* c = std::get_if<CylinderShape>(&shape); c && !c->tessellate) {
    require_positive(c->radius_m, "radius", what);
    require_positive(c->height_m, "height", what);
    return CylinderSurface{c->radius_m, c->height_m};
  }
  if (const auto* d = std::get_if<DiskShape>(&shape); d && !d->tessellate) {
    require_positive(d->radius_m, "radius", what);
    return DiskSurface{d->radius_m};
  }
  return std::nullopt;
}

bool shape_is_closed(const Shape& shape) {
  return !std::holds_alternative<QuadShape>(shape) && !std::holds_alternative<DiskShape>(shape);
}

}  // namespace bouguer

namespace bouguer {

std::uint64_t triangle_bound(const Shape& shape) {
  // Revolved profiles make two triangles per segment and profile step (see revolve).
  auto revolved = [](std::size_t profile_points, int segments) {
    return 2 * static_cast<std::uint64_t>(profile_points + 1) * static_cast<std::uint64_t>(std::max(segments, 0));
  };
  auto sided = [](int sides) { return 4 * static_cast<std::uint64_t>(std::max(sides, 0)) + 4; };
  struct Visitor {
    decltype(revolved) rev;
    decltype(sided) side;
    std::uint64_t operator()(const QuadShape&) const { return 2; }
    std::uint64_t operator()(const DiskShape& s) const { return rev(0, s.segments); }
    std::uint64_t operator()(const BoxShape&) const { return 12; }
    std::uint64_t operator()(const SphereShape& s) const { return rev(static_cast<std::size_t>(std::max(2, s.segments / 2)) + 1, s.segments); }
    std::uint64_t operator()(const CylinderShape& s) const { return rev(4, s.segments); }
    std::uint64_t operator()(const PrismShape& s) const { return side(s.sides); }
    std::uint64_t operator()(const PyramidShape& s) const { return side(s.sides); }
    std::uint64_t operator()(const TruncatedCubeShape&) const { return 128; }
    std::uint64_t operator()(const BrilliantShape&) const { return 1024; }
    std::uint64_t operator()(const LatheShape& s) const { return rev(s.profile_m.size(), s.segments); }
    // Outside, dry inside, wet inside and the liquid's surface: each at most the profile plus two points.
    std::uint64_t operator()(const VesselShape& s) const { return 4 * rev(s.profile_m.size() + 2, s.segments); }
    std::uint64_t operator()(const MeshShape&) const { return 0; }
    std::uint64_t operator()(const TriangleMeshShape& s) const { return s.mesh.triangles.size(); }
  };
  return std::visit(Visitor{revolved, sided}, shape);
}

ObjWithMaterials load_obj_materials(const std::filesystem::path& path, const std::string& what) {
  const ParsedObj obj = parse_obj(path, what, true);
  const std::string mtl_where = fmt::format("{}: its MTL", obj.where);
  ObjWithMaterials out;
  for (const tinyobj::material_t& m : obj.materials) {
    ObjMaterial material{m.name, {m.diffuse[0], m.diffuse[1], m.diffuse[2]}, {}};
    for (std::size_t c = 0; c < 3; ++c)
      if (!(material.kd[c] >= 0.0 && material.kd[c] <= 1.0))
        fail("{}: material '{}': Kd {} must lie between 0 and 1", mtl_where, excerpt(m.name), material.kd[c]);
    if (!m.diffuse_texname.empty()) material.map_kd = std::filesystem::absolute(path.parent_path() / m.diffuse_texname);
    out.materials.push_back(std::move(material));
  }
  // One part per material (-1: faces without one), in the order of the materials.
  std::map<int, tinyobj::shape_t> by_material;
  for (const tinyobj::shape_t& shape : obj.shapes)
    for (std::size_t f = 0; f < shape.mesh.material_ids.size() && 3 * f + 2 < shape.mesh.indices.size(); ++f) {
      const int id = shape.mesh.material_ids[f];
      auto& indices = by_material[id >= 0 && static_cast<std::size_t>(id) < out.materials.size() ? id : -1].mesh.indices;
      indices.insert(indices.end(), shape.mesh.indices.begin() + static_cast<std::ptrdiff_t>(3 * f),
                     shape.mesh.indices.begin() + static_cast<std::ptrdiff_t>(3 * f + 3));
    }
  for (const auto& [id, shape] : by_material) out.parts.push_back({corner_mesh(obj, {shape}), id});
  if (out.parts.empty()) fail("{} has no faces", obj.where);
  return out;
}

}  // namespace bouguer
