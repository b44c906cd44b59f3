#include "bouguer/integrators/manifold_chain.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "bouguer/core/frame.h"
#include "bouguer/integrators/surface_events.h"

namespace bouguer {
namespace {

constexpr int kMaxUnknowns = 2 * kMaxChain;
// Converged: every constraint below this (its units are the indices'; about the sine of the
// angle by which Snell's law is missed), or below the rounding of the constraints themselves:
// about 1e-16 of the largest coordinate over the shortest segment, which for a 2 mm wall 30 m from
// the origin is above 1e-12 (kRoundingAllowance of that, kChainTolerance at least).
constexpr double kChainTolerance = 1e-12, kRoundingAllowance = 1e-14;
using Column = std::array<double, kMaxUnknowns>;
using Matrix = std::array<Column, kMaxUnknowns>;  // [row][column]

// Solves a·x = b for the first n unknowns (Gaussian elimination with partial pivoting); false where
// a is singular to working precision.
bool solve_linear(Matrix a, Column b, int n, Column& x) {
  for (int k = 0; k < n; ++k) {
    int pivot = k;
    for (int r = k + 1; r < n; ++r)
      if (std::abs(a[r][k]) > std::abs(a[pivot][k])) pivot = r;
    if (!(std::abs(a[pivot][k]) > 1e-300)) return false;
    std::swap(a[k], a[pivot]);
    std::swap(b[k], b[pivot]);
    for (int r = k + 1; r < n; ++r) {
      const double f = a[r][k] / a[k][k];
      for (int col = k; col < n; ++col) a[r][col] -= f * a[k][col];
      b[r] -= f * b[k];
    }
  }
  for (int k = n - 1; k >= 0; --k) {
    double sum = b[k];
    for (int col = k + 1; col < n; ++col) sum -= a[k][col] * x[col];
    x[k] = sum / a[k][k];
    if (!std::isfinite(x[k])) return false;
  }
  return true;
}

// A crossing's triangle: its corners, unit geometric normal, an orthonormal basis (e1, e2) of its
// plane, the mesh (its vertex normals), and the gradients in its plane of the barycentrics of
// corners 1 and 2 (a point's barycentrics, which a solve asks for many times, are then two dot
// products; and they are what the shading normal's derivative is made of).
struct Triangle {
  const Mesh* mesh = nullptr;
  std::uint32_t geometry = 0, primitive = 0;
  std::array<std::uint32_t, 3> corner{};
  Vec3 p0, normal, e1, e2, grad1, grad2;
};

// A triangle's first corner and unit geometric normal (its plane).
std::pair<Vec3, Vec3> plane_of(const RenderScene& s, const Hit& h) {
  const Mesh& m = s.rays.mesh(h.geometry);
  const auto& corner = m.triangles[h.primitive];
  const Vec3 p0 = m.positions[corner[0]];
  return {p0, normalize(cross(m.positions[corner[1]] - p0, m.positions[corner[2]] - p0))};
}

Triangle triangle_of(const RenderScene& s, const Hit& h) {
  Triangle t;
  t.mesh = &s.rays.mesh(h.geometry);
  t.geometry = h.geometry;
  t.primitive = h.primitive;
  t.corner = t.mesh->triangles[h.primitive];
  t.p0 = t.mesh->positions[t.corner[0]];
  const Vec3 a = t.mesh->positions[t.corner[1]] - t.p0, b = t.mesh->positions[t.corner[2]] - t.p0;
  t.normal = normalize(cross(a, b));
  const Frame f(t.normal);
  t.e1 = f.s;
  t.e2 = f.t;
  const double aa = dot(a, a), ab = dot(a, b), bb = dot(b, b), det = aa * bb - ab * ab;
  t.grad1 = (a * bb - b * ab) / det;
  t.grad2 = (b * aa - a * ab) / det;
  return t;
}

// The interpolated shading normal at a point of the triangle's plane (inside it or, during a
// Newton step, just past an edge: the affine interpolation extends smoothly), and the length of
// the interpolated normal it is (0 where the geometric normal stands in, which does not turn).
Vec3 shading_normal(const Triangle& t, const Vec3& y, double* interpolated_length = nullptr) {
  const Mesh& m = *t.mesh;
  if (interpolated_length) *interpolated_length = 0.0;
  if (m.normals.empty()) return t.normal;
  const Vec3 c = y - t.p0;
  const double b1 = dot(c, t.grad1), b2 = dot(c, t.grad2), b0 = 1.0 - b1 - b2;
  const Vec3 n = m.normals[t.corner[0]] * b0 + m.normals[t.corner[1]] * b1 + m.normals[t.corner[2]] * b2;
  const double l = length(n);
  if (!(l > 1e-12 && dot(n, t.normal) > 0.0)) return t.normal;
  if (interpolated_length) *interpolated_length = l;
  return n / l;
}

// The surface a ray from `origin` along d meets first within max_m, seen from the nested set
// `inside`, crossing index-matched ones as every ray does (advance_to_surface; the set updated):
// nothing where none is that near (`gave_up`: nor after kMaxCrossings of them, which is no clear
// way either).
struct Met {
  Hit hit;
  SurfaceSeen seen;
};
std::optional<Met> next_surface(const RenderScene& s, const Vec3& origin, const Vec3& d, double max_m,
                                InsideSet& inside, std::uint64_t& rays, bool* gave_up = nullptr) {
  RaySegment seg{Ray{origin, d, max_m}, origin, -1, inside};
  const RayStop stop = advance_to_surface(s, seg, rays, [&](const Hit* hit, const SurfaceSeen*) {
    if (hit) seg.ray.t_max -= length(hit->point - seg.start);  // the next ray: what is left of max_m
    return true;
  });
  inside = seg.inside;
  if (gave_up) *gave_up = stop.at == RayStop::At::crossings_exhausted;
  if (stop.at != RayStop::At::surface) return std::nullopt;
  return Met{*stop.hit, *stop.seen};
}

// A surface the chain can refract at: a smooth, non-dispersive interface of a mesh without a
// normal map.
bool chain_surface(const RenderScene& s, const Met& m) {
  const Surface& f = m.seen.surface;
  return f.kind == SurfaceKind::interface && f.roughness == 0.0 && !m.seen.index_matched && f.normal_map < 0 &&
         !s.rays.analytic(m.hit.geometry) && !s.media[static_cast<std::size_t>(m.seen.medium_front)].dispersive &&
         !s.media[static_cast<std::size_t>(m.seen.medium_behind)].dispersive;
}

// The crossing where a ray from `from` along d met m (`inside`: the set it arrived with), its point
// recomputed in double precision on the triangle's plane (Embree's is float).
std::optional<ChainCrossing> crossing_of(const RenderScene& s, const Vec3& from, const Vec3& d, const Met& m,
                                         InsideSet inside) {
  ChainCrossing c;
  c.hit = m.hit;
  const auto [p0, normal] = plane_of(s, c.hit);
  const double along = dot(d, normal);
  if (std::abs(along) < 1e-12) return std::nullopt;
  c.hit.point = from + d * (dot(p0 - from, normal) / along);
  const bool front = along < 0.0;  // arriving on the side the normal points to
  c.medium_from = front ? m.seen.medium_front : m.seen.medium_behind;
  c.medium_to = front ? m.seen.medium_behind : m.seen.medium_front;
  c.eta_from = s.media[static_cast<std::size_t>(c.medium_from)].ior_reference;
  c.eta_to = s.media[static_cast<std::size_t>(c.medium_to)].ior_reference;
  c.inside_to = inside_towards(s, m.hit, inside, d);
  return c;
}

// The crossing a ray from `from` (on from_hit, or in a medium) along d meets first, if it is the
// chain's kind of surface and on `geometry`.
std::optional<ChainCrossing> cross_at(const RenderScene& s, const Vec3& from, const Hit* from_hit, const Vec3& d,
                                      double max_m, InsideSet inside, std::uint32_t geometry, std::uint64_t& rays) {
  const auto m = next_surface(s, from_hit ? offset_ray_origin(*from_hit, d) : from, d, max_m, inside, rays);
  if (!m || !chain_surface(s, *m) || m->hit.geometry != geometry) return std::nullopt;
  return crossing_of(s, from, d, *m, inside);
}

// What a crossing's constraints are made of at the chain's points: the unit directions back and
// ahead and their lengths, h = η_before·back + η_after·ahead, the shading normal and the length of
// the interpolated normal it was divided by (0 where the geometric normal stands in: no change).
struct CrossingLocal {
  Vec3 back, ahead, h, n;
  double back_m = 0.0, ahead_m = 0.0, normal_length = 0.0;
};

// (`ahead_fixed`: the last crossing of a chain towards a distant lamp, whose direction ahead is that
// unit vector whatever the crossing: as towards a point infinitely far, moving it turns nothing.)
CrossingLocal crossing_local(const Triangle& t, const ChainCrossing& k, const Vec3& before, const Vec3& y,
                             const Vec3& after, const Vec3* ahead_fixed = nullptr) {
  CrossingLocal o;
  o.back_m = length(before - y), o.ahead_m = ahead_fixed ? std::numeric_limits<double>::infinity() : length(after - y);
  o.back = (before - y) / o.back_m, o.ahead = ahead_fixed ? *ahead_fixed : (after - y) / o.ahead_m;
  o.h = o.back * k.eta_from + o.ahead * k.eta_to;
  o.n = shading_normal(t, y, &o.normal_length);
  return o;
}

double largest(const Column& v, int n) {
  double m = 0.0;
  for (int i = 0; i < n; ++i) m = std::max(m, std::abs(v[static_cast<std::size_t>(i)]));
  return m;
}

// Where a chain ends: at a point q, or (`direction`) towards a distant lamp along the unit q.
struct ChainEnd {
  Vec3 q;
  bool direction = false;
};

// The chain at its points y (y[0] = x, y[count + 1] = q, or a metre past the last crossing towards
// a distant lamp): each crossing's triangle and local
// quantities, the constraints (two a crossing, along e1 and e2 of its triangle: the part of h
// across the shading normal) and, once differentiated, their Jacobian.
struct Linearised {
  std::array<Triangle, kMaxChain> tri;
  std::array<Vec3, kMaxChain + 2> y;
  std::array<CrossingLocal, kMaxChain> local;
  Column value{};
  Matrix jacobian{};  // ∂C/∂(the crossings' coordinates along e1, e2 of their triangles)
};

// The chain's points and constraints, the Jacobian not yet (a Newton step's trial point is
// mostly judged by its constraints alone). A crossing on the same triangle as in `before` takes
// its triangle from there.
Linearised evaluate(const RenderScene& s, const Vec3& x, const ChainEnd& end, const Chain& c,
                    const Linearised* before = nullptr) {
  Linearised l;
  l.y[0] = x;
  for (int i = 0; i < c.count; ++i) {
    const Hit& h = c.crossing[static_cast<std::size_t>(i)].hit;
    const Triangle* known = before ? &before->tri[static_cast<std::size_t>(i)] : nullptr;
    l.tri[static_cast<std::size_t>(i)] =
        known && known->geometry == h.geometry && known->primitive == h.primitive ? *known : triangle_of(s, h);
    l.y[static_cast<std::size_t>(i + 1)] = h.point;
  }
  l.y[static_cast<std::size_t>(c.count + 1)] = end.direction ? l.y[static_cast<std::size_t>(c.count)] + end.q : end.q;
  for (int i = 1; i <= c.count; ++i) {
    const Triangle& t = l.tri[static_cast<std::size_t>(i - 1)];
    const CrossingLocal& o = l.local[static_cast<std::size_t>(i - 1)] =
        crossing_local(t, c.crossing[static_cast<std::size_t>(i - 1)], l.y[static_cast<std::size_t>(i - 1)],
                       l.y[static_cast<std::size_t>(i)], l.y[static_cast<std::size_t>(i + 1)],
                       end.direction && i == c.count ? &end.q : nullptr);
    const Vec3 across = o.h - o.n * dot(o.h, o.n);
    l.value[static_cast<std::size_t>(2 * i - 2)] = dot(across, t.e1);
    l.value[static_cast<std::size_t>(2 * i - 1)] = dot(across, t.e2);
  }
  return l;
}

// The change of a crossing's two constraints when its neighbours and itself move by d_before,
// d_after and d_y (d(across) with across = h − n(n·h), then along e1 and e2).
std::array<double, 2> constraint_change(const Triangle& t, const ChainCrossing& k, const CrossingLocal& o,
                                        const Vec3& d_before, const Vec3& d_y, const Vec3& d_after) {
  const Vec3 v_back = d_before - d_y, v_ahead = d_after - d_y;
  const Vec3 d_back = (v_back - o.back * dot(o.back, v_back)) / o.back_m;
  const Vec3 d_ahead = (v_ahead - o.ahead * dot(o.ahead, v_ahead)) / o.ahead_m;
  const Vec3 dh = d_back * k.eta_from + d_ahead * k.eta_to;
  Vec3 dn{};
  if (o.normal_length > 0.0) {
    const Mesh& m = *t.mesh;
    const Vec3 n0 = m.normals[t.corner[0]];
    const Vec3 dN = (m.normals[t.corner[1]] - n0) * dot(t.grad1, d_y) + (m.normals[t.corner[2]] - n0) * dot(t.grad2, d_y);
    dn = (dN - o.n * dot(o.n, dN)) / o.normal_length;
  }
  const Vec3 d_across = dh - dn * dot(o.n, o.h) - o.n * (dot(dn, o.h) + dot(o.n, dh));
  return {dot(d_across, t.e1), dot(d_across, t.e2)};
}

// The Jacobian of the constraints at l's points, in closed form: moving crossing k in its
// triangle's plane changes only its own constraints and its two neighbours'.
void differentiate(Linearised& l, const Chain& c) {
  for (auto& row : l.jacobian) row.fill(0.0);
  for (int j = 0; j < 2 * c.count; ++j) {
    const int k = j / 2 + 1;
    const Triangle& t = l.tri[static_cast<std::size_t>(k - 1)];
    const Vec3 u = j % 2 == 0 ? t.e1 : t.e2;
    for (int i = std::max(1, k - 1); i <= std::min(c.count, k + 1); ++i) {
      const Vec3 d_before = i == k + 1 ? u : Vec3{}, d_y = i == k ? u : Vec3{}, d_after = i == k - 1 ? u : Vec3{};
      const auto dc = constraint_change(l.tri[static_cast<std::size_t>(i - 1)], c.crossing[static_cast<std::size_t>(i - 1)],
                                        l.local[static_cast<std::size_t>(i - 1)], d_before, d_y, d_after);
      l.jacobian[static_cast<std::size_t>(2 * i - 2)][static_cast<std::size_t>(j)] = dc[0];
      l.jacobian[static_cast<std::size_t>(2 * i - 1)][static_cast<std::size_t>(j)] = dc[1];
    }
  }
}

Linearised linearise(const RenderScene& s, const Vec3& x, const ChainEnd& end, const Chain& c) {
  Linearised l = evaluate(s, x, end, c);
  differentiate(l, c);
  return l;
}

// The chain traced again from x through `targets` (a point in each crossing's plane): each ray
// from the crossing before towards the next target, meeting the same surface first.
std::optional<Chain> retraced(const RenderScene& s, const Vec3& x, const Hit* x_hit, const Chain& c,
                              const std::array<Vec3, kMaxChain>& targets, std::uint64_t& rays) {
  Chain out = c;
  Vec3 from = x;
  const Hit* from_hit = x_hit;
  InsideSet inside = c.inside_x;
  for (int i = 0; i < c.count; ++i) {
    const Vec3 to = targets[static_cast<std::size_t>(i)] - from;
    const double d = length(to);
    if (!(d > 0.0)) return std::nullopt;
    const auto k = cross_at(s, from, from_hit, to / d, 2.0 * d, inside,
                            c.crossing[static_cast<std::size_t>(i)].hit.geometry, rays);
    if (!k) return std::nullopt;
    ChainCrossing& o = out.crossing[static_cast<std::size_t>(i)];
    // The sides it is crossed from stay the seed's (the indices are the chain's).
    if (k->eta_from != o.eta_from || k->eta_to != o.eta_to) return std::nullopt;
    o = *k;
    from = o.hit.point;
    from_hit = &o.hit;
    inside = o.inside_to;
  }
  return out;
}

}  // namespace

Vec3 chain_shading_normal(const RenderScene& s, const Hit& on, const Vec3& point) {
  return shading_normal(triangle_of(s, on), point);
}

namespace {

// How far a ray towards q goes, `left_m` from it: short of q as a shadow ray stops short of its
// target (q may lie on an area light's surface).
double short_of(const Vec3& q, double left_m) { return std::max(0.0, left_m * (1.0 - 1e-4) - 2.0 * ray_offset_m(q)); }

}  // namespace

std::optional<FirstSurface> first_surface(const RenderScene& s, const Vec3& x, const Hit* x_hit, InsideSet inside,
                                          const Vec3& q, std::uint64_t& rays) {
  const double d = length(q - x);
  if (!(d > 0.0)) return std::nullopt;
  const Vec3 dir = (q - x) / d;
  const auto m = next_surface(s, x_hit ? offset_ray_origin(*x_hit, dir) : x, dir, short_of(q, d), inside, rays);
  if (!m) return std::nullopt;
  return FirstSurface{m->hit, m->seen};
}

namespace {

// The crossings of the straight line from x along dir, short of q (a point `far_m` away: the
// shadow ray's end), or to infinity (far_m infinite: a distant lamp's direction): seed_chain's.
std::optional<Chain> seed_along(const RenderScene& s, const Vec3& x, const Hit* x_hit, InsideSet inside,
                                const Vec3& dir, const Vec3& q, double far_m, std::uint64_t& rays) {
  Chain c;
  c.inside_x = inside;
  Vec3 from = x;
  const Hit* from_hit = x_hit;
  for (;;) {
    bool gave_up = false;
    const double left_m = std::isinf(far_m) ? far_m : short_of(q, length(q - from));
    const auto m =
        next_surface(s, from_hit ? offset_ray_origin(*from_hit, dir) : from, dir, left_m, inside, rays, &gave_up);
    if (gave_up) return std::nullopt;
    if (!m) break;  // clear to the lamp
    if (c.count == kMaxChain || !chain_surface(s, *m)) return std::nullopt;
    const auto k = crossing_of(s, from, dir, *m, inside);
    if (!k) return std::nullopt;
    ChainCrossing& o = c.crossing[static_cast<std::size_t>(c.count++)];
    o = *k;
    from = o.hit.point;
    from_hit = &o.hit;
    inside = o.inside_to;
  }
  if (c.count == 0) return std::nullopt;
  return c;
}

}  // namespace

std::optional<Chain> seed_chain(const RenderScene& s, const Vec3& x, const Hit* x_hit, InsideSet inside, const Vec3& q,
                                std::uint64_t& rays) {
  const double d = length(q - x);
  if (!(d > 0.0)) return std::nullopt;
  return seed_along(s, x, x_hit, inside, (q - x) / d, q, d, rays);
}

std::optional<Chain> seed_chain_towards(const RenderScene& s, const Vec3& x, const Hit* x_hit, InsideSet inside,
                                        const Vec3& to_lamp, std::uint64_t& rays) {
  return seed_along(s, x, x_hit, inside, to_lamp, x, std::numeric_limits<double>::infinity(), rays);
}

namespace {

// Whether each crossing of a solved chain refracts: the directions back and ahead on opposite
// sides of its surface, by its geometric and its shading normal (the constraints also hold for
// some paths that turn back where a crossing moved onto a curved neighbour).
bool refracts_everywhere(const Linearised& l, int count) {
  for (int i = 1; i <= count; ++i) {
    const Vec3& y = l.y[static_cast<std::size_t>(i)];
    const Vec3 back = l.y[static_cast<std::size_t>(i - 1)] - y, ahead = l.y[static_cast<std::size_t>(i + 1)] - y;
    const Triangle& t = l.tri[static_cast<std::size_t>(i - 1)];
    const Vec3 ns = shading_normal(t, y);
    if (dot(back, t.normal) * dot(ahead, t.normal) >= 0.0 || dot(back, ns) * dot(ahead, ns) >= 0.0) return false;
  }
  return true;
}

// The constraints' own rounding for the chain's points (kRoundingAllowance).
double rounding_floor(const Linearised& l, int count) {
  double coordinate = 0.0, shortest = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= count + 1; ++i) {
    const Vec3& y = l.y[static_cast<std::size_t>(i)];
    coordinate = std::max({coordinate, std::abs(y.x), std::abs(y.y), std::abs(y.z)});
    if (i > 0) shortest = std::min(shortest, length(y - l.y[static_cast<std::size_t>(i - 1)]));
  }
  return std::max(kChainTolerance, kRoundingAllowance * coordinate / shortest);
}

}  // namespace

namespace {

bool solve(const RenderScene& s, const Vec3& x, const Hit* x_hit, const ChainEnd& q, Chain& c, std::uint64_t& rays) {
  const int n = 2 * c.count;
  Linearised l = linearise(s, x, q, c);
  for (int iteration = 0; iteration < 40; ++iteration) {
    const double error = largest(l.value, n);
    if (error < rounding_floor(l, c.count)) return refracts_everywhere(l, c.count);
    Column minus_value{}, step{};
    for (int i = 0; i < n; ++i) minus_value[static_cast<std::size_t>(i)] = -l.value[static_cast<std::size_t>(i)];
    if (!solve_linear(l.jacobian, minus_value, n, step)) return false;
    // A full Newton step, halved until the constraints shrink (and the path still meets its
    // surfaces in order).
    bool moved = false;
    for (double lambda = 1.0; lambda > 1e-3 && !moved; lambda *= 0.5) {
      std::array<Vec3, kMaxChain> targets{};
      for (int i = 0; i < c.count; ++i) {
        const Triangle& t = l.tri[static_cast<std::size_t>(i)];
        targets[static_cast<std::size_t>(i)] =
            l.y[static_cast<std::size_t>(i + 1)] +
            (t.e1 * step[static_cast<std::size_t>(2 * i)] + t.e2 * step[static_cast<std::size_t>(2 * i + 1)]) * lambda;
      }
      const auto next = retraced(s, x, x_hit, c, targets, rays);
      if (!next) continue;
      Linearised m = evaluate(s, x, q, *next, &l);
      if (largest(m.value, n) < error) {
        differentiate(m, *next);
        c = *next;
        l = std::move(m);
        moved = true;
      }
    }
    if (!moved) return false;
  }
  return false;
}

}  // namespace

bool solve_chain(const RenderScene& s, const Vec3& x, const Hit* x_hit, const Vec3& q, Chain& c, std::uint64_t& rays) {
  return solve(s, x, x_hit, ChainEnd{q}, c, rays);
}

bool solve_chain_towards(const RenderScene& s, const Vec3& x, const Hit* x_hit, const Vec3& to_lamp, Chain& c,
                         std::uint64_t& rays) {
  return solve(s, x, x_hit, ChainEnd{to_lamp, true}, c, rays);
}

double chain_reverse_tube(const RenderScene& s, const Vec3& x, const Vec3& q, const Chain& c) {
  const int n = 2 * c.count;
  const Linearised l = linearise(s, x, ChainEnd{q}, c);
  const Vec3 last = c.crossing[static_cast<std::size_t>(c.count - 1)].hit.point;
  const Frame across(normalize(q - last));  // the patch at q, perpendicular to the last segment
  const Vec3 first = c.crossing[0].hit.point;
  const double first_m = length(first - x);
  const Vec3 wi = (first - x) / first_m;
  const auto last_i = static_cast<std::size_t>(c.count - 1);
  std::array<Vec3, 2> turn{};  // how the first direction turns per metre q moves along s and t
  for (int a = 0; a < 2; ++a) {
    // (only the last crossing's constraints see q)
    const auto dc = constraint_change(l.tri[last_i], c.crossing[last_i], l.local[last_i], Vec3{}, Vec3{},
                                      a == 0 ? across.s : across.t);
    Column rhs{}, dy{};
    rhs[static_cast<std::size_t>(n - 2)] = -dc[0];
    rhs[static_cast<std::size_t>(n - 1)] = -dc[1];
    if (!solve_linear(l.jacobian, rhs, n, dy)) return 0.0;
    const Vec3 dfirst = l.tri[0].e1 * dy[0] + l.tri[0].e2 * dy[1];
    turn[static_cast<std::size_t>(a)] = (dfirst - wi * dot(dfirst, wi)) / first_m;
  }
  return length(cross(turn[0], turn[1]));
}

double chain_beam_tube(const RenderScene& s, const Vec3& x, const Vec3& to_lamp, const Chain& c) {
  const int n = 2 * c.count;
  const Linearised l = linearise(s, x, ChainEnd{to_lamp, true}, c);
  const Frame across(normalize(c.crossing[0].hit.point - x));  // the patch at x, across the first segment
  const auto last_i = static_cast<std::size_t>(c.count - 1);
  std::array<Vec3, 2> shift{};  // how the last crossing moves across the beam per metre x moves along s and t
  for (int a = 0; a < 2; ++a) {
    // (only the first crossing's constraints see x)
    const auto dc = constraint_change(l.tri[0], c.crossing[0], l.local[0], a == 0 ? across.s : across.t, Vec3{}, Vec3{});
    Column rhs{}, dy{};
    rhs[0] = -dc[0];
    rhs[1] = -dc[1];
    if (!solve_linear(l.jacobian, rhs, n, dy)) return 0.0;
    const Vec3 dlast = l.tri[last_i].e1 * dy[static_cast<std::size_t>(n - 2)] +
                       l.tri[last_i].e2 * dy[static_cast<std::size_t>(n - 1)];
    shift[static_cast<std::size_t>(a)] = dlast - to_lamp * dot(dlast, to_lamp);
  }
  return length(cross(shift[0], shift[1]));
}

}  // namespace bouguer
