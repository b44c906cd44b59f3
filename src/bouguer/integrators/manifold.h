#pragma once
// Next-event estimation through smooth glass (#37's manifold next-event estimation: Hanika,
// Droske, Fascione 2015, with each interface's refraction solved exactly rather than by Newton
// steps on a mesh): one crossing of a plane (a face of a mesh or a cylinder's cap), or one or two
// crossings of an exact sphere or a cylinder's side. A lamp behind a refracting surface (under water, behind a pane,
// inside a glass globe; a fog inside a glass ball lit from outside; the caustic under a glass ball)
// sends light to a vertex on the other side only along the paths where Snell's law holds at every
// crossing. No BSDF or phase direction meets a point light, so the path tracer reached those paths
// not at all; an area light it reached only where a sampled direction happened to refract onto it.
//
// Contract, for every such path: the vertex's f·|cos θ| (or phase value) towards the first
// crossing, times the light's intensity (a point or spot light) or its radiance times |cos θ| at
// a point y drawn by area on it, divided by that point's density (an area or spherical light),
// times the Fresnel transmittance at each crossing, the transmittance of every segment (exact
// Bouguer–Lambert, fields and priorities as any shadow ray; ratio-tracked in scattering media,
// with all segments' spectral-MIS ratios), and the ray tube's dω_light / dA⊥ at the vertex (the
// irradiance a point source gives through the refractions: flux is conserved, so no n² appears);
// for a sun, its irradiance across the beam times the beam tube dA⊥_lamp/dA⊥_x (beam_tube,
// chain_beam_tube: distant_light_through_interface).
// Zero where no such path exists: a crossing off the face the straight shadow ray met (a plane)
// or hidden, an interface that disperses, is rough or shades with normals other than its own,
// something else in the way.
//
// Which strategy owns which path. Point, spot and distant lights: these connections are the path tracer's
// only strategy, so nothing is weighted (and bdpt's, at a non-specular vertex the camera sees
// through specular ones: Bdpt::through_glass). Area and spherical lights through a caster
// (RenderScene::casters: exact smooth spheres of objects without a priority): the walk also
// reaches a path from a non-specular vertex through one or two refractions of one caster to the
// light (a BSDF or phase direction refracted onto it), and the two are weighted by the power
// heuristic: here with the connection's density (connection_density) against the vertex's
// density times the refraction probabilities, in the walk by caster_path_densities
// (radiance.h: CasterTrail). A path the solve misses (two solutions closer than the scan's
// interval, near a caustic's fold) is the walk's alone: caster_path_densities runs the same solve.
// Area and spherical lights hidden by smooth faces of meshes (small ones by default: SceneView::
// lamp_through_chains) likewise through their chain from the point next-event estimation drew
// (area_light_through_chain), weighed in the walk by chain_path_densities (radiance.h: ChainTrail);
// and (the same lamps) hidden by an exact cylinder's side, the first surface the straight segment
// meets (area_light_through_cylinder), weighed by cylinder_path_densities (radiance.h:
// CylinderTrail).
#include <array>
#include <algorithm>
#include <limits>
#include <numbers>
#include <span>

#include "bouguer/core/frame.h"
#include "bouguer/integrators/direct_light.h"
#include "bouguer/integrators/manifold_chain.h"

namespace bouguer {

// The stream of the random numbers connections through casters draw (each vertex seeds one from
// the walk's generator: however many they take, the walk's own numbers stay where they were).
inline constexpr std::uint64_t kManifoldStream = 0x6d6e6565;  // "mnee"

// The point of the plane through `on_plane` with unit normal `n` where a ray from x refracts
// towards p (x and p on opposite sides; eta_x, eta_p the indices on their sides): the root of
// η_x·sin θ_x = η_p·sin θ_p on the segment between their feet, which is unique (the difference of
// the two sides grows monotonically along it); solved to 1e-12 of its length. Nothing where they
// are on one side.
std::optional<Vec3> refraction_point(const Vec3& x, const Vec3& p, const Vec3& on_plane, const Vec3& n, double eta_x,
                                     double eta_p);

// A solution's neighbourhood: where it crossed for a neighbouring vertex, and how far around it a
// solve looks (in the angle about the centre or the axis: the ray tube's neighbours move the
// crossing by their step over the radius, up to a few times that).
struct NearSolution {
  Vec3 point;
  double window_rad = 1e-4;
};

// The points of the sphere (centre, radius) where a ray from `inner` (inside it) refracts towards
// `outer` (outside; eta_inner, eta_outer the indices on their sides), which `outer` sees: the
// stationary points of the optical length η_i·|inner − y| + η_o·|y − outer| on the arc of the great
// circle through both points (Snell's law keeps the normal, which passes through the centre, in
// the plane of incidence) that `outer` sees. Usually one; near a caustic, three. Found by the sign
// changes of its derivative over 48 intervals of the arc, refined to 1e-14 of a radian within
// them (the Illinois method), and two roots either side of an extremum of it that comes near 0
// between scan points (a close pair at a caustic's fold, as for the cylinder below). With `near`,
// only the solution near that point (the ray tube's neighbours of a solution).
struct SphereRefraction {
  std::array<Vec3, 4> points{};
  int count = 0;
};
SphereRefraction sphere_refraction_points(const Vec3& inner, const Vec3& outer, const Vec3& centre, double radius_m,
                                          double eta_inner, double eta_outer, const NearSolution* near = nullptr);

// The same towards a distant lamp: the points where a ray from `inner` refracts into the unit
// direction to_lamp (the outer point infinitely far along it), on the half of the sphere whose
// outward normal has a part along to_lamp; the plane of the paths is the centre's, inner's and
// to_lamp's.
SphereRefraction sphere_refraction_towards(const Vec3& inner, const Vec3& to_lamp, const Vec3& centre, double radius_m,
                                           double eta_inner, double eta_outer, const NearSolution* near = nullptr);

// The points of the side of a cylinder (its axis through `on_axis` along the unit `axis`, of
// infinite length: whether a point lies on the finite side is for the caller to trace) where a ray
// from `inner` (nearer the axis than the radius) refracts towards `outer` (farther): the stationary
// points of the optical length η_i·|inner − y| + η_o·|y − outer| over the side. For each angle φ
// around the axis the length is convex along it, so its height there is the unique root of
// Snell's law along the axis (a plane's refraction, over the two horizontal distances); over φ,
// the sign changes of the length's derivative (the envelope's: the partial at that height) over
// 48 intervals of the arc `outer` sees, and two roots either side of an extremum of it that comes
// near 0 between them (a close pair at a caustic's fold, which sign changes alone step over),
// refined by the Illinois method to 1e-14 of a radian. With `near`, only the solution near that
// point.
SphereRefraction cylinder_refraction_points(const Vec3& inner, const Vec3& outer, const Vec3& on_axis,
                                            const Vec3& axis, double radius_m, double eta_inner, double eta_outer,
                                            const NearSolution* near = nullptr);

// The paths from `from` to `to` (both outside the sphere) through it: refracted in at entry[k],
// straight across, refracted out at exit[k]. In the plane of the centre and both points, as above;
// each entry point on the arc `from` sees traces one ray, and the paths are the sign changes of
// the side of it `to` lies on, over 16 intervals, refined to 1e-14 of a radian. An interval whose
// ends differ in whether their rays pass (at an edge of total internal reflection, or of `to`
// being ahead) is split in four, three times over, so a narrow window of paths near `to` is not
// stepped over. The deviation through a sphere grows with the impact parameter on each side of
// the centre's line, so one path a side is the rule, more only near `to`'s caustic; two paths
// closer than an interval are missed as above. None where the turn from `from` to `to` exceeds
// the most a passage deviates. A ray totally reflected inside carries nothing here (its paths are
// the walks'). `near`: as above, an entry point.
struct SpherePassages {
  std::array<Vec3, 4> entry{}, exit{};
  int count = 0;
};
SpherePassages sphere_passage_points(const Vec3& from, const Vec3& to, const Vec3& centre, double radius_m,
                                     double eta_inside, double eta_outside, const NearSolution* near = nullptr);

// The same towards a distant lamp: the passages from `from` that leave the sphere along the unit
// direction to_lamp (`to` infinitely far along it).
SpherePassages sphere_passage_towards(const Vec3& from, const Vec3& to_lamp, const Vec3& centre, double radius_m,
                                      double eta_inside, double eta_outside, const NearSolution* near = nullptr);

// The paths from `from` to `to` (both outside the cylinder's side: farther from its axis than
// the radius; the axis of infinite length, as above) through it: refracted in at entry[k], straight
// across, refracted out at exit[k]. Each crossing's normal lies across the axis, so η times the
// direction's part along the axis is one invariant α for the whole path, and across the axis the
// path refracts as through a circle with Bravais' effective indices √(η² − α²), each segment rising
// α/√(η² − α²) per unit of its length across. Over the entry angle φ and α = η_min·sin β, the paths
// are where the ray traced across the axis passes `to`'s foot and its rise meets `to`'s height:
// found by marching squares on a grid of 16 angles by 12 values of β over the window its paths can
// have (close pairs along the grid's rows as scan_roots finds them; in a cell, Newton's method on
// both conditions, or the curve of the first followed between two crossings), each accepted where
// the rise misses by less than 1e-9 of the radius (Snell's law then holds to about 1e-13). Paths within
// about 3° of grazing, and two paths closer than a cell where neither search sees them, may be
// missed. `near`: as above, an entry point: Newton's method from the angle and α of the straight
// line to it, and a 2×2 grid around them where that finds no path within the window.
SpherePassages cylinder_passage_points(const Vec3& from, const Vec3& to, const Vec3& on_axis, const Vec3& axis,
                                       double radius_m, double eta_inside, double eta_outside,
                                       const NearSolution* near = nullptr);

// Which side a solved chain's forward tube dω_q/dA⊥_x is taken from. `vertex`: by étendue from the
// reverse tube, (η_x/η_q)²·dω_x/dA⊥_q, what the walk's own directions at x would gather from a lamp
// of vanishing size at q (the path tracer's and bdpt's lamps). `point`: traced from q through the
// chain reversed, what the camera's own rays from a pinhole at q would reach (the light tracer's
// camera connections). The same where the normals are the faces' own; with shading normals each
// is the one the walk that also makes the path would see.
enum class TubeFrom { vertex, point };

namespace manifold_detail {

// One smooth interface, as next-event estimation crosses it: a plane through `point` with
// `normal` (a face of a mesh, a cylinder's cap), a sphere (centre `point`, radius), or a
// cylinder's side (crossed once, or twice: through a rod); its media (front: the side the normal points to, outside a
// sphere or a cylinder).
struct Interface {
  enum class Shape { plane, sphere, cylinder };
  std::uint32_t geometry = 0;
  Shape shape = Shape::plane;
  // A plane: a point of it and its normal; a sphere: its centre; a cylinder's side: a point of its
  // axis and the axis (unit).
  Vec3 point, normal;
  double radius_m = 0.0;
  int medium_front = -1, medium_behind = -1;
  bool twice = true;  // crossed twice too (a sphere: ManifoldCaster::twice)
  // The part of x − point across a cylinder's axis.
  Vec3 across_axis(const Vec3& x) const { return (x - point) - normal * dot(x - point, normal); }
  bool front(const Vec3& x) const {
    switch (shape) {
      case Shape::sphere: return length(x - point) > radius_m;
      case Shape::cylinder: return length(across_axis(x)) > radius_m;
      case Shape::plane: break;
    }
    return dot(x - point, normal) > 0.0;
  }
  Vec3 normal_at(const Vec3& y) const {
    switch (shape) {
      case Shape::sphere: return (y - point) / radius_m;
      case Shape::cylinder: return normalize(across_axis(y));
      case Shape::plane: break;
    }
    return normal;
  }
};

// The paths through an interface from x to the light point q: their crossings in order, one or two.
struct Paths {
  std::array<std::array<Vec3, 2>, 4> crossing{};
  int count = 0, crossings = 1;
};

inline Paths solve(const Interface& f, const Vec3& x, const Vec3& q, double eta_front, double eta_behind,
                   const NearSolution* near = nullptr) {
  Paths out;
  auto once = [&](const SphereRefraction& r) {
    for (int k = 0; k < r.count; ++k) out.crossing[static_cast<std::size_t>(k)][0] = r.points[static_cast<std::size_t>(k)];
    out.count = r.count;
    return out;
  };
  auto twice = [&](const SpherePassages& p) {
    out.crossings = 2;
    for (int k = 0; k < p.count; ++k)
      out.crossing[static_cast<std::size_t>(k)] = {p.entry[static_cast<std::size_t>(k)],
                                                   p.exit[static_cast<std::size_t>(k)]};
    out.count = p.count;
    return out;
  };
  const bool fx = f.front(x), fq = f.front(q);
  switch (f.shape) {
    case Interface::Shape::plane:
      if (fx == fq) return out;
      if (const auto y = refraction_point(x, q, f.point, f.normal, fx ? eta_front : eta_behind,
                                          fx ? eta_behind : eta_front))
        out.crossing[static_cast<std::size_t>(out.count++)][0] = *y;
      return out;
    case Interface::Shape::cylinder:  // its side, once, or in and out (a rod)
      if (fx && fq)
        return f.twice ? twice(cylinder_passage_points(x, q, f.point, f.normal, f.radius_m, eta_behind, eta_front, near))
                       : out;
      if (fx == fq) return out;
      return once(fx ? cylinder_refraction_points(q, x, f.point, f.normal, f.radius_m, eta_behind, eta_front, near)
                     : cylinder_refraction_points(x, q, f.point, f.normal, f.radius_m, eta_behind, eta_front, near));
    case Interface::Shape::sphere:
      if (fx && fq)
        return f.twice ? twice(sphere_passage_points(x, q, f.point, f.radius_m, eta_behind, eta_front, near)) : out;
      if (fx == fq) return out;  // both inside: no crossing
      return once(fx ? sphere_refraction_points(q, x, f.point, f.radius_m, eta_behind, eta_front, near)
                     : sphere_refraction_points(x, q, f.point, f.radius_m, eta_behind, eta_front, near));
  }
  return out;
}

// The paths through an interface from x that leave it along the unit to_lamp, towards a distant
// lamp: a plane's one (Snell's law there fixes the direction on x's side, and the crossing is where
// the line back along it meets the plane), a sphere's from inside it (once) or through it (twice,
// f.twice). None through a cylinder's side (not yet: docs/rendering.md).
inline Paths solve_towards(const Interface& f, const Vec3& x, const Vec3& to_lamp, double eta_front,
                           double eta_behind, const NearSolution* near = nullptr) {
  Paths out;
  const bool fx = f.front(x);
  switch (f.shape) {
    case Interface::Shape::plane: {
      const bool lamp_front = dot(to_lamp, f.normal) > 0.0;
      if (fx == lamp_front) return out;
      const double eta_lamp = lamp_front ? eta_front : eta_behind, eta_x = lamp_front ? eta_behind : eta_front;
      const Vec3 n_lamp = lamp_front ? f.normal : -f.normal;
      const double cos_l = dot(to_lamp, n_lamp), cos_x = cos_theta_transmitted(cos_l, eta_lamp, eta_x);
      if (!(cos_l > 0.0) || !(cos_x > 0.0)) return out;
      const Vec3 wi = -refract(to_lamp, n_lamp, cos_l, cos_x, eta_lamp / eta_x);  // on x's side, towards the plane
      const double along = dot(f.point - x, f.normal) / dot(wi, f.normal);
      if (!(along > 0.0) || !std::isfinite(along)) return out;
      out.crossing[0][0] = x + wi * along;
      out.count = 1;
      return out;
    }
    case Interface::Shape::sphere: {
      if (!fx) {
        const SphereRefraction r = sphere_refraction_towards(x, to_lamp, f.point, f.radius_m, eta_behind, eta_front, near);
        for (int k = 0; k < r.count; ++k) out.crossing[static_cast<std::size_t>(k)][0] = r.points[static_cast<std::size_t>(k)];
        out.count = r.count;
        return out;
      }
      if (!f.twice) return out;
      const SpherePassages p = sphere_passage_towards(x, to_lamp, f.point, f.radius_m, eta_behind, eta_front, near);
      out.crossings = 2;
      for (int k = 0; k < p.count; ++k)
        out.crossing[static_cast<std::size_t>(k)] = {p.entry[static_cast<std::size_t>(k)], p.exit[static_cast<std::size_t>(k)]};
      out.count = p.count;
      return out;
    }
    case Interface::Shape::cylinder: break;
  }
  return out;
}

// What a path gets from its vertex to its last crossing, and where it then goes on to the light.
template <std::size_t N>
struct Reach {
  SampledSpectrum<N> tr = SampledSpectrum<N>::constant(1.0f);
  SampledSpectrum<N> r_l = SampledSpectrum<N>::constant(1.0f);  // the segments' spectral-MIS ratios:
  SampledSpectrum<N> r_u = SampledSpectrum<N>::constant(1.0f);  // the connection's and the walk's
  double fresnel = 1.0;  // the product of the crossings' Fresnel transmittances
  Vec3 wi;               // the first direction, from the vertex
  Hit last;              // the last crossing, as a hit (the final segment's start)
  InsideSet inside = 0;  // the nested set beyond it
  int medium = -1;       // the medium beyond it
  Vec3 to_light;
  double light_m = 0.0;  // from the last crossing to the light point
};

// Follows a path's crossings `ys` from the vertex, the first segment through the vertex's own
// medium that way (medium_towards(direction): a medium vertex's, or the side of its surface; not
// the interface's, which an index-matched boundary may part from it): each
// segment clear (transmission); at each crossing, the surface met there accepted by
// `normal_there(c, face)`, which gives the normal it refracts by (nothing: not the path's surface);
// Fresnel from the indices of the media on each side.
template <std::size_t N, typename MediumTowards, typename NormalThere>
std::optional<Reach<N>> follow_crossings(const SceneView<N>& v, const PathVertex& at, InsideSet inside,
                                         MediumTowards medium_towards, std::span<const Vec3> ys, const Vec3& q,
                                         NormalThere normal_there, const SampledWavelengths<N>& w, Rng& rng,
                                         std::uint64_t& rays) {
  const RenderScene& s = v.scene;
  Reach<N> r;
  int medium = -1;
  PathVertex from = at;
  r.inside = inside;
  for (std::size_t c = 0; c < ys.size(); ++c) {
    const Vec3 y = ys[c];
    const double d = length(y - from.point);
    if (!(d > 0.0)) return std::nullopt;
    const Vec3 dir = (y - from.point) / d;
    if (c == 0) {
      r.wi = dir;
      medium = medium_towards(dir);
    }
    const auto t = transmission(v, from, dir, d, medium, w, rng, rays);
    if (!t) return std::nullopt;
    r.tr *= t->tr;
    r.r_l *= t->ratios.r_l;
    r.r_u *= t->ratios.r_u;
    // The crossing itself, in a window from where transmission stopped (1e-4 of the way and twice
    // a ray's offset short) to as far past: float rounding far from the origin is wider than
    // 1e-4 of a 2 mm segment. (Within half the segment, so it never reaches the crossing before.)
    const double window = std::min(d * 1e-4 + 4.0 * ray_offset_m(y), 0.5 * d);
    const auto face = s.rays.intersect(Ray{y - dir * window, dir, 2.0 * window});
    ++rays;
    if (!face) return std::nullopt;
    const std::optional<Vec3> n = normal_there(c, *face);
    if (!n) return std::nullopt;
    const SurfaceSeen seen = surface_seen(s, *face, r.inside);
    const bool front = dot(dir, face->normal) < 0.0;  // arriving on the side the normal points to
    const int m_from = front ? seen.medium_front : seen.medium_behind, m_to = front ? seen.medium_behind : seen.medium_front;
    const double eta_from = s.media[static_cast<std::size_t>(m_from)].ior_reference;
    const double eta_to = s.media[static_cast<std::size_t>(m_to)].ior_reference;
    const double cos_i = std::abs(dot(dir, *n)), cos_t = cos_theta_transmitted(cos_i, eta_from, eta_to);
    if (!(cos_t > 0.0)) return std::nullopt;
    r.fresnel *= 1.0 - fresnel_dielectric(cos_i, cos_t, eta_from, eta_to);
    r.inside = inside_towards(s, *face, r.inside, dir);
    r.last = *face;
    r.medium = medium = m_to;
    from = PathVertex{face->point, &r.last, r.inside};
  }
  r.light_m = length(q - ys.back());
  if (!(r.light_m > 0.0)) return std::nullopt;
  r.to_light = (q - ys.back()) / r.light_m;
  return r;
}

// One solved path through an interface: each crossing on the same surface where the solve put it
// (a plane: on a face of that plane; a sphere: the normal there), refracting by its own normal.
template <std::size_t N, typename MediumTowards>
std::optional<Reach<N>> follow(const SceneView<N>& v, const PathVertex& at, InsideSet inside, const Interface& f,
                               const std::array<Vec3, 2>& ys, int crossings, const Vec3& q,
                               MediumTowards medium_towards, const SampledWavelengths<N>& w, Rng& rng,
                               std::uint64_t& rays) {
  const std::span<const Vec3> points(ys.data(), static_cast<std::size_t>(crossings));
  auto normal_there = [&](std::size_t c, const Hit& face) -> std::optional<Vec3> {
    const Vec3 n = f.normal_at(points[c]);
    const double d = length(points[c] - (c == 0 ? at.point : points[c - 1]));
    if (face.geometry != f.geometry || dot(face.normal, n) < 1.0 - 1e-9 ||
        dot(face.shading_normal, face.normal) < 1.0 - 1e-9 ||
        (f.shape == Interface::Shape::plane && std::abs(dot(face.point - f.point, n)) > 1e-6 * d))
      return std::nullopt;
    return n;
  };
  return follow_crossings(v, at, inside, medium_towards, points, q, normal_there, w, rng, rays);
}

// The ray tube at the vertex: the directions leaving the light point q that reach a patch
// perpendicular to wi at x, per unit area of it. Across the plane of a sphere's paths, from their
// symmetry: turning x about the axis through the centre and q by δ moves it ρ_x·δ and turns the
// path's last direction o by |o × axis|·δ. In the plane (and both ways on a plane's face), by the
// solve at a neighbour 1e-6 of the path away (the mapping is smooth there: central enough, and
// the differences keep 10 digits), solved for near this path's first crossing: within 10 steps
// over the radius of it (and at least 1e-4 rad), since a step moves the crossing by about a step
// (more where the path leaves near grazing). A fixed 1e-4 rad lost the path, and the tube was 0,
// once the path was 75 radii long (a lamp 3 m from a vertex in a 40 mm cylinder).
inline double tube(const Interface& f, const Vec3& x, const Vec3& wi, const std::array<Vec3, 2>& ys, int crossings,
                   const Vec3& q, double path_m, double eta_front, double eta_behind) {
  const double step = 1e-6 * path_m;
  const Vec3& last = ys[static_cast<std::size_t>(crossings - 1)];
  const Vec3 o0 = normalize(last - q);
  const NearSolution near{ys[0], f.radius_m > 0.0 ? std::max(1e-4, 10.0 * step / f.radius_m) : 1e-4};
  // o at the vertex moved by `by`, the path the one whose last crossing is nearest this one's.
  auto moved = [&](const Vec3& by) -> std::optional<Vec3> {
    const Paths p = solve(f, x + by * step, q, eta_front, eta_behind, &near);
    std::optional<Vec3> o;
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < p.count; ++i) {
      const Vec3 y = p.crossing[static_cast<std::size_t>(i)][static_cast<std::size_t>(p.crossings - 1)];
      if (length(y - last) < best) best = length(y - last), o = normalize(y - q);
    }
    return o;
  };
  if (f.shape == Interface::Shape::sphere) {
    const Vec3 axis = normalize(q - f.point);
    const double rho_x = length(cross(x - f.point, axis));
    if (rho_x > 1e-6 * length(x - f.point)) {
      const Vec3 across = normalize(cross(x - f.point, axis));  // the plane's normal
      const auto o1 = moved(normalize(cross(across, wi)));
      if (!o1) return 0.0;
      return length(*o1 - o0) / step * length(cross(o0, axis)) / rho_x;
    }
  }
  const Frame frame(wi);
  const auto o1 = moved(frame.s), o2 = moved(frame.t);
  if (!o1 || !o2) return 0.0;
  return length(cross(*o1 - o0, *o2 - o0)) / (step * step);
}

// The beam tube at the vertex for a path leaving towards a distant lamp: the cross-section of the
// lamp's parallel beam (across to_lamp) whose rays pass through a patch perpendicular to wi at x,
// per unit area of it, dA⊥_lamp/dA⊥_x. Through a plane cos θ_l/cos θ_x in closed form (the beam
// meets A⊥/cos θ_l of the plane and leaves it A⊥·cos θ_x/cos θ_l across). Through a sphere from its
// symmetry about the axis through the centre along to_lamp: turning x about it by δ moves x ρ_x·δ
// and the last crossing ρ_y·δ, both across the plane of the path; in the plane, by the solve at a
// neighbour 1e-6 of the scale away (as `tube`), the last crossing's move across the beam.
inline double beam_tube(const Interface& f, const Vec3& x, const Vec3& wi, const std::array<Vec3, 2>& ys,
                        int crossings, const Vec3& to_lamp, double eta_front, double eta_behind) {
  const Vec3& last = ys[static_cast<std::size_t>(crossings - 1)];
  if (f.shape == Interface::Shape::plane) {
    const double cos_x = std::abs(dot(wi, f.normal));
    return cos_x > 0.0 ? std::abs(dot(to_lamp, f.normal)) / cos_x : 0.0;
  }
  const double step = 1e-6 * (length(ys[0] - x) + f.radius_m);
  const NearSolution near{ys[0], std::max(1e-4, 10.0 * step / f.radius_m)};
  // The last crossing's move across the beam with the vertex moved by `by`, the path the one whose
  // last crossing is nearest this one's.
  auto moved = [&](const Vec3& by) -> std::optional<Vec3> {
    const Paths p = solve_towards(f, x + by * step, to_lamp, eta_front, eta_behind, &near);
    std::optional<Vec3> d;
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < p.count; ++i) {
      const Vec3 y = p.crossing[static_cast<std::size_t>(i)][static_cast<std::size_t>(p.crossings - 1)];
      if (length(y - last) < best) best = length(y - last), d = (y - last) - to_lamp * dot(y - last, to_lamp);
    }
    return d;
  };
  const double rho_x = length(cross(x - f.point, to_lamp));
  if (f.shape == Interface::Shape::sphere && rho_x > 1e-6 * length(x - f.point)) {
    const Vec3 across = cross(x - f.point, to_lamp) / rho_x;  // the plane's normal
    const auto d = moved(normalize(cross(across, wi)));
    if (!d) return 0.0;
    return length(*d) / step * length(cross(last - f.point, to_lamp)) / rho_x;
  }
  const Frame frame(wi);
  const auto d1 = moved(frame.s), d2 = moved(frame.t);
  if (!d1 || !d2) return 0.0;
  return length(cross(*d1, *d2)) / (step * step);
}

// What the light sends along a path's final segment: its intensity, or its radiance × |cos θ_y|
// divided by the density of the point drawn (area_pdf: the light's choice times the point's
// density per m², 0 for a delta light); the final segment's transmittance and ratios.
template <std::size_t N>
struct LightEnd {
  SampledSpectrum<N> value;
  double area_pdf = 0.0, cos_light = 1.0;
  SampledSpectrum<N> tr = SampledSpectrum<N>::constant(1.0f);
  SampledSpectrum<N> r_l = SampledSpectrum<N>::constant(1.0f), r_u = r_l;
};

// The solid-angle density at the vertex with which the connection draws a path that reaches an
// area or spherical light at y: the point's density (area_pdf) over dω_x/dA_y = |cos θ_y| times
// the reverse ray tube, which étendue (n²·dA⊥·dω conserved) gives from the forward one as
// (η_y/η_x)²·dω_y/dA⊥_x.
inline double connection_density(double area_pdf, double cos_light, double tube, double eta_x, double eta_light) {
  const double reverse = (eta_light / eta_x) * (eta_light / eta_x) * tube;
  return cos_light > 0.0 && reverse > 0.0 ? area_pdf / (cos_light * reverse) : 0.0;
}

// What a light sends from point q (a point light's position, or a point drawn on an area or
// spherical light) along each path to the vertex: intensity (or radiance × |cos θ| / density)
// towards the path's last direction, or zero; `end` traces the final segment. add(l, reach) takes
// each path's light and how it went (the light tracer's camera connections splat each where its
// last direction lands on the film).
template <std::size_t N, typename Towards, typename MediumTowards, typename End, typename Add>
void through_each(const SceneView<N>& v, const PathVertex& at, InsideSet inside, const Interface& f, const Vec3& q,
                  Towards towards, MediumTowards medium_towards, const SampledWavelengths<N>& w,
                  const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays, End end, Add add) {
  const RenderScene& s = v.scene;
  const double eta_front = s.media[static_cast<std::size_t>(f.medium_front)].ior_reference;
  const double eta_behind = s.media[static_cast<std::size_t>(f.medium_behind)].ior_reference;
  const Paths paths = solve(f, at.point, q, eta_front, eta_behind);
  for (int k = 0; k < paths.count; ++k) {
    const auto& ys = paths.crossing[static_cast<std::size_t>(k)];
    const auto r = follow(v, at, inside, f, ys, paths.crossings, q, medium_towards, w, rng, rays);
    if (!r) continue;
    double vertex_pdf = 0.0;
    const SampledSpectrum<N> fv = towards(r->wi, vertex_pdf);
    if (fv.is_zero()) continue;
    // The final segment and what the light sends along it.
    const LightEnd<N> e = end(*r);
    if (e.value.is_zero()) continue;
    double path_m = length(ys[0] - at.point) + r->light_m;
    if (paths.crossings == 2) path_m += length(ys[1] - ys[0]);
    const double t = tube(f, at.point, r->wi, ys, paths.crossings, q, path_m, eta_front, eta_behind);
    if (!(t > 0.0) || !std::isfinite(t)) continue;
    const SampledSpectrum<N> r_l = r->r_l * e.r_l;
    // An area or spherical light: weighted against the walk's own paths through the same
    // crossings (its direction's density times the probability of refracting at each), by the
    // power heuristic with the spectral-MIS means (radiance.h: CasterTrail weighs those).
    double weight = 1.0;
    if (e.area_pdf > 0.0) {
      const double eta_x = f.front(at.point) ? eta_front : eta_behind;
      const double p_connection = connection_density(e.area_pdf, e.cos_light, t, eta_x,
                                                     s.media[static_cast<std::size_t>(r->medium)].ior_reference);
      weight = power_heuristic(p_connection * mean_ratio(s, path_r_u, r_l),
                               vertex_pdf * r->fresnel * mean_ratio(s, path_r_u, r->r_u * e.r_u));
    }
    add(fv * e.value * r->tr * e.tr * static_cast<float>(weight * r->fresnel * t / mean_ratio(s, path_r_u, r_l)), *r);
  }
}

// The paths' light summed (through_each).
template <std::size_t N, typename Towards, typename MediumTowards, typename End>
SampledSpectrum<N> through(const SceneView<N>& v, const PathVertex& at, InsideSet inside, const Interface& f,
                           const Vec3& q, Towards towards, MediumTowards medium_towards, const SampledWavelengths<N>& w,
                           const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays, End end) {
  SampledSpectrum<N> sum;
  through_each(v, at, inside, f, q, towards, medium_towards, w, path_r_u, rng, rays, end,
               [&](const SampledSpectrum<N>& l, const Reach<N>&) { sum += l; });
  return sum;
}

// A delta light's position, intensity spectrum and spot profile; nothing for other lights.
struct DeltaLamp {
  Vec3 p;
  int intensity = -1;
  const SpotProfile* spot = nullptr;
};
inline std::optional<DeltaLamp> delta_lamp(const Light& light) {
  if (const auto* pt = std::get_if<PointLight>(&light)) return DeltaLamp{pt->position_m, pt->intensity, nullptr};
  if (const auto* sp = std::get_if<SpotLight>(&light)) return DeltaLamp{sp->position_m, sp->intensity, &sp->profile};
  return std::nullopt;
}

// A path's final segment to a point that sends `value` along it (a delta lamp; the camera's
// pinhole, 1, the light tracer's connections weighing its importance in): the segment's
// transmittance and ratios, nothing where it is blocked.
template <std::size_t N>
LightEnd<N> point_end(const SceneView<N>& v, const SampledSpectrum<N>& value, const Reach<N>& r,
                      const SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays) {
  const auto t = transmission(v, PathVertex{r.last.point, &r.last, r.inside}, r.to_light, r.light_m, r.medium, w,
                              rng, rays);
  if (!t) return {};
  return {value, 0.0, 1.0, t->tr, t->ratios.r_l, t->ratios.r_u};
}

// What delta lamp `lamp` sends along a path's final segment: its intensity and spot profile
// towards the path's last direction, and the segment's transmittance.
template <std::size_t N>
LightEnd<N> delta_lamp_end(const SceneView<N>& v, const DeltaLamp& lamp, const Reach<N>& r,
                           const SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays) {
  const double emitted = lamp.spot ? spot_falloff(*lamp.spot, -r.to_light) : 1.0;
  if (emitted == 0.0) return {};
  return point_end(v, v.tables.at(lamp.intensity, w) * static_cast<float>(emitted), r, w, rng, rays);
}

// What a distant lamp sends along a path's final segment, from its last crossing towards the lamp
// (to_lamp) to infinity: its irradiance across the beam, and the segment's transmittance.
template <std::size_t N>
LightEnd<N> distant_lamp_end(const SceneView<N>& v, const DistantLight& sun, const Vec3& to_lamp, const Reach<N>& r,
                             const SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays) {
  const auto t = transmission(v, PathVertex{r.last.point, &r.last, r.inside}, to_lamp,
                              std::numeric_limits<double>::infinity(), r.medium, w, rng, rays);
  if (!t) return {};
  return {v.tables.at(sun.irradiance, w), 0.0, 1.0, t->tr, t->ratios.r_l, t->ratios.r_u};
}

// The light of a distant lamp at vertex `at` along each path through interface f that leaves it
// towards the lamp (solve_towards), add(l, last) taking each with its last crossing (nearest the
// lamp): f·|cos θ| towards the first crossing, the irradiance
// across the beam E times the beam tube (dA⊥_lamp/dA⊥_x), Fresnel at each crossing, every segment's
// transmittance. Unweighted: no other strategy reaches a delta lamp.
template <std::size_t N, typename Towards, typename MediumTowards, typename Add>
void distant_through(const SceneView<N>& v, const PathVertex& at, InsideSet inside, const Interface& f,
                     const DistantLight& sun, Towards towards, MediumTowards medium_towards,
                     const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays,
                     Add add) {
  const RenderScene& s = v.scene;
  const Vec3 to_lamp = -normalize(sun.direction);
  const double eta_front = s.media[static_cast<std::size_t>(f.medium_front)].ior_reference;
  const double eta_behind = s.media[static_cast<std::size_t>(f.medium_behind)].ior_reference;
  const Paths paths = solve_towards(f, at.point, to_lamp, eta_front, eta_behind);
  for (int k = 0; k < paths.count; ++k) {
    const auto& ys = paths.crossing[static_cast<std::size_t>(k)];
    // (A path leaving a surface vertex on the other side of it than the lamp's: the nested set
    // `inside` is the lamp's side's.)
    if (at.hit && dot(ys[0] - at.point, at.hit->normal) * dot(to_lamp, at.hit->normal) <= 0.0) continue;
    const Vec3 beyond = ys[static_cast<std::size_t>(paths.crossings - 1)] + to_lamp;
    const auto r = follow(v, at, inside, f, ys, paths.crossings, beyond, medium_towards, w, rng, rays);
    if (!r) continue;
    double vertex_pdf = 0.0;
    const SampledSpectrum<N> fv = towards(r->wi, vertex_pdf);
    if (fv.is_zero()) continue;
    const LightEnd<N> e = distant_lamp_end(v, sun, to_lamp, *r, w, rng, rays);
    if (e.value.is_zero()) continue;
    const double t = beam_tube(f, at.point, r->wi, ys, paths.crossings, to_lamp, eta_front, eta_behind);
    if (!(t > 0.0) || !std::isfinite(t)) continue;
    add(fv * e.value * r->tr * e.tr * static_cast<float>(r->fresnel * t / mean_ratio(s, path_r_u, r->r_l * e.r_l)),
        ys[static_cast<std::size_t>(paths.crossings - 1)]);
  }
}

// What an area or spherical light sends from its point y along a path's final segment: clear up
// to it, then its own surface there, seen from the path's side: its radiance × |cos θ_y| divided by
// the point's density area_pdf (the lamp's choice included), and the segment's transmittance.
template <std::size_t N>
LightEnd<N> area_lamp_end(const SceneView<N>& v, const Light& light, const Vec3& y, double area_pdf,
                          const Reach<N>& r, const SampledWavelengths<N>& w, Rng& rng, std::uint64_t& rays) {
  const RenderScene& s = v.scene;
  const auto t = transmission(v, PathVertex{r.last.point, &r.last, r.inside}, r.to_light, r.light_m, r.medium, w,
                              rng, rays);
  if (!t) return {};
  const auto hit = s.rays.intersect(Ray{y - r.to_light * (r.light_m * 1e-4), r.to_light, r.light_m * 2e-4});
  ++rays;
  if (!hit || s.surfaces[hit->geometry].kind != SurfaceKind::emitter || &surface_light_at(s, *hit) != &light)
    return {};
  const double cos_light = std::abs(dot(hit->normal, r.to_light));
  return {emitted(v, *hit, -r.to_light, w) * static_cast<float>(cos_light / area_pdf), area_pdf, cos_light, t->tr,
          t->ratios.r_l, t->ratios.r_u};
}

template <std::size_t N, typename Towards, typename MediumTowards>
SampledSpectrum<N> delta_through(const SceneView<N>& v, const PathVertex& at, InsideSet inside, const Interface& f,
                                 const DeltaLamp& lamp, Towards towards, MediumTowards medium_towards,
                                 const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng,
                                 std::uint64_t& rays) {
  auto end = [&](const Reach<N>& r) { return delta_lamp_end(v, lamp, r, w, rng, rays); };
  return through(v, at, inside, f, lamp.p, towards, medium_towards, w, path_r_u, rng, rays, end);
}

// Follows a solved chain from the vertex (follow_crossings): the walk meets each crossing where the
// solve put it (Embree's float hit within a hundred times its rounding), on the same surface, and
// refracts there by its shading normal.
template <std::size_t N, typename MediumTowards>
std::optional<Reach<N>> follow_chain(const SceneView<N>& v, const PathVertex& at, const Chain& c, const Vec3& q,
                                     MediumTowards medium_towards, const SampledWavelengths<N>& w, Rng& rng,
                                     std::uint64_t& rays) {
  const RenderScene& s = v.scene;
  std::array<Vec3, kMaxChain> ys{};
  for (int i = 0; i < c.count; ++i) ys[static_cast<std::size_t>(i)] = c.crossing[static_cast<std::size_t>(i)].hit.point;
  const std::span<const Vec3> points(ys.data(), static_cast<std::size_t>(c.count));
  auto normal_there = [&](std::size_t i, const Hit& face) -> std::optional<Vec3> {
    const Hit& k = c.crossing[i].hit;
    if (face.geometry != k.geometry || length(face.point - points[i]) > 1e-5 * s.rays.rounding_scale_m(points[i]))
      return std::nullopt;
    return chain_shading_normal(s, k, points[i]);
  };
  return follow_crossings(v, at, c.inside_x, medium_towards, points, q, normal_there, w, rng, rays);
}

// (η_x/η_q)²: the chain's first index over its last, squared (the ray tube's étendue factor).
inline double chain_eta_ratio2(const Chain& c) {
  const double r = c.crossing[0].eta_from / c.crossing[static_cast<std::size_t>(c.count - 1)].eta_to;
  return r * r;
}

// The light sent from point q to vertex `at` through a chain of mesh faces (manifold_chain.h,
// seeded from the straight segment): the path on which each crossing refracts by its shading
// normal, then as `through_each`: f·|cos θ| towards its first crossing, what `end` says q sends
// along the last segment, Fresnel at each crossing (by the shading normal, as the walk), every
// segment's transmittance, and the forward ray tube dω_q/dA⊥_x (TubeFrom): with a lamp at q,
// "Radiance across a refraction": no n² in the radiance, flux conserved.
template <std::size_t N, typename Towards, typename MediumTowards, typename End, typename Add>
void through_chain_each(const SceneView<N>& v, const PathVertex& at, Chain c, const Vec3& q, Towards towards,
                        MediumTowards medium_towards, const SampledWavelengths<N>& w,
                        const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays, TubeFrom from, End end,
                        Add add) {
  const RenderScene& s = v.scene;
  if (!solve_chain(s, at.point, at.hit, q, c, rays)) return;
  const auto r = follow_chain(v, at, c, q, medium_towards, w, rng, rays);
  if (!r) return;
  double vertex_pdf = 0.0;
  const SampledSpectrum<N> fv = towards(r->wi, vertex_pdf);
  if (fv.is_zero()) return;
  const LightEnd<N> e = end(*r);
  if (e.value.is_zero()) return;
  const double tube = from == TubeFrom::vertex ? chain_eta_ratio2(c) * chain_reverse_tube(s, at.point, q, c)
                                               : chain_reverse_tube(s, q, at.point, reversed(c));
  if (!(tube > 0.0) || !std::isfinite(tube)) return;
  add(fv * e.value * r->tr * e.tr * static_cast<float>(r->fresnel * tube / mean_ratio(s, path_r_u, r->r_l * e.r_l)),
      *r);
}

// The smooth interface a connection refracts through at `hit` (seen there as `seen`): a face of
// a mesh or a cylinder's cap (its plane: a cap stays a plane under any affine transform), an exact
// sphere, or a cylinder's side that its transform keeps circular. Nothing where it is not smooth
// glass (rough, index-matched, dispersive) or is an ellipsoid or an elliptic cylinder (not yet).
// (A disk bounds no medium, so it is never an interface.)
inline std::optional<Interface> smooth_interface(const RenderScene& s, const Hit& hit, const SurfaceSeen& seen) {
  if (seen.surface.kind != SurfaceKind::interface || seen.surface.roughness != 0.0 || seen.index_matched)
    return std::nullopt;
  if (s.media[static_cast<std::size_t>(seen.medium_front)].dispersive ||
      s.media[static_cast<std::size_t>(seen.medium_behind)].dispersive)
    return std::nullopt;
  Interface f{hit.geometry, Interface::Shape::plane, hit.point, hit.normal, 0.0, seen.medium_front, seen.medium_behind};
  const AnalyticShape* shape = s.rays.analytic(hit.geometry);
  if (!shape) return f;
  if (const auto* sphere = std::get_if<SphereSurface>(&shape->surface)) {
    const double scale = shape->to_world.similarity_scale();
    if (scale == 0.0) return std::nullopt;
    f.shape = Interface::Shape::sphere, f.point = shape->to_world.apply(Vec3{}), f.radius_m = sphere->radius_m * scale;
  } else if (const auto* cylinder = std::get_if<CylinderSurface>(&shape->surface);
             cylinder && hit.primitive == static_cast<std::uint32_t>(AnalyticPart::side)) {
    const auto side = circular_side(*cylinder, shape->to_world);
    if (!side) return std::nullopt;
    f.shape = Interface::Shape::cylinder, f.point = side->on_axis, f.normal = side->axis, f.radius_m = side->radius_m;
  }
  return f;
}

// The exact cylinder's side a connection from x (on x_hit, or in a medium; `arrived`: the nested
// set there) to the point q goes on through: the first surface the straight segment meets, where
// that is one (and the nested set leaving x). The same question from both sides of the MIS:
// area_light_through_cylinder's and cylinder_path_densities'.
struct CylinderMet {
  Interface f;
  InsideSet inside = 0;
};
inline std::optional<CylinderMet> cylinder_met_first(const RenderScene& s, const Vec3& x, const Hit* x_hit,
                                                     InsideSet arrived, const Vec3& q, std::uint64_t& rays) {
  const InsideSet inside = x_hit ? inside_towards(s, *x_hit, arrived, normalize(q - x)) : arrived;
  const auto first = first_surface(s, x, x_hit, inside, q, rays);
  if (!first) return std::nullopt;
  const auto f = smooth_interface(s, first->hit, first->seen);
  if (!f || f->shape != Interface::Shape::cylinder) return std::nullopt;
  return CylinderMet{*f, inside};
}

inline Interface caster_interface(const RenderScene& s, const ManifoldCaster& c) {
  const Surface& surface = s.surfaces[c.geometry];
  return Interface{c.geometry, Interface::Shape::sphere, c.centre_m, Vec3{}, c.radius_m, surface.medium_front,
                   surface.medium_behind, c.twice};
}

// The part of a spherical lamp that sees some of the caster: outward normals n with n·axis > mu0,
// and the density per m² of a point drawn uniformly on it.
struct FacingCap {
  Vec3 axis;
  double mu0 = -1.0, pdf_area = 0.0;
};
inline std::optional<FacingCap> facing_cap(const SphereLight& sphere, const ManifoldCaster& c) {
  const Vec3 to = c.centre_m - sphere.centre_m;
  const double d = length(to);
  const double mu0 = d > 0.0 ? std::max(-1.0, (sphere.radius_m - c.radius_m) / d) : -1.0;
  if (!(mu0 < 1.0) || !(sphere.radius_m > 0.0)) return std::nullopt;
  return FacingCap{d > 0.0 ? to / d : Vec3{0.0, 0.0, 1.0}, mu0,
                   1.0 / (2.0 * std::numbers::pi * sphere.radius_m * sphere.radius_m * (1.0 - mu0))};
}

// A point drawn by area on an area light, or on the part of a spherical one that sees some of
// the caster: the cap of outward normals n with n·d > (r_lamp − r_caster)/D, d the unit direction
// and D the distance from the lamp's centre to the caster's (the rest sends it nothing). About
// half the sphere for a small lamp, where drawing on all of it wasted half the solves.
inline std::optional<LightAreaSample> facing_point(const Light& light, const ManifoldCaster& c, double u1, double u2) {
  const auto* sphere = std::get_if<SphereLight>(&light);
  if (!sphere) return sample_area(light, u1, u2);
  const auto cap = facing_cap(*sphere, c);
  if (!cap) return std::nullopt;
  const double mu = 1.0 - u1 * (1.0 - cap->mu0), r = std::sqrt(std::max(0.0, 1.0 - mu * mu));
  const double phi = 2.0 * std::numbers::pi * u2;
  const Vec3 n = Frame(cap->axis).to_world(Vec3{r * std::cos(phi), r * std::sin(phi), mu});
  return LightAreaSample{sphere->centre_m + n * sphere->radius_m, cap->pdf_area};
}

}  // namespace manifold_detail

// Whether next-event estimation goes on to this area or spherical light through chains of mesh
// faces (SceneView::lamp_through_chains: RenderSettings::area_lamp_chains, or the lamp's size seen
// from the glass).
template <std::size_t N>
bool lamp_through_chains(const SceneView<N>& v, const Light& light) {
  if (const auto* a = std::get_if<AreaLight>(&light)) return v.lamp_through_chains(a->geometry);
  if (const auto* sphere = std::get_if<SphereLight>(&light)) return v.lamp_through_chains(sphere->geometry);
  return false;
}

// The light of an area or spherical lamp at vertex `at` through a chain of mesh faces, from the
// point y next-event estimation drew on it for the straight line (its density per m², the lamp's
// choice by power included: point_pdf), where the straight segment is hidden by smooth
// refracting faces. The path Newton reaches from the straight line (through_chain_each's), then:
// f·|cos θ| towards its first crossing, the lamp's radiance towards the path's last direction,
// Fresnel at each crossing, every segment's transmittance, and the change of variables from the
// point to the vertex's directions, |cos θ_y|·dω_x/dA⊥_y (the reverse tube), times (η_x/η_y)² as
// for a delta lamp. Weighted by the power heuristic against the walk's own paths through the same
// faces (its direction's density times the probability of refracting at each crossing: radiance.h,
// ChainTrail), with the connection's density point_pdf / (|cos θ_y|·dω_x/dA⊥_y).
template <std::size_t N, typename Towards, typename MediumTowards>
SampledSpectrum<N> area_light_through_chain(const SceneView<N>& v, const PathVertex& at, const Light& light,
                                            const Vec3& y, double point_pdf, Towards towards,
                                            MediumTowards medium_towards, const SampledWavelengths<N>& w,
                                            const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays) {
  const RenderScene& s = v.scene;
  if (!(point_pdf > 0.0)) return {};
  const InsideSet inside = at.hit ? inside_towards(s, *at.hit, at.inside, normalize(y - at.point)) : at.inside;
  auto c = seed_chain(s, at.point, at.hit, inside, y, rays);
  if (!c || !solve_chain(s, at.point, at.hit, y, *c, rays)) return {};
  const auto r = manifold_detail::follow_chain(v, at, *c, y, medium_towards, w, rng, rays);
  if (!r) return {};
  double vertex_pdf = 0.0;
  const SampledSpectrum<N> fv = towards(r->wi, vertex_pdf);
  if (fv.is_zero()) return {};
  const manifold_detail::LightEnd<N> e = manifold_detail::area_lamp_end(v, light, y, point_pdf, *r, w, rng, rays);
  if (e.value.is_zero()) return {};
  const double reverse = chain_reverse_tube(s, at.point, y, *c);
  if (!(e.cos_light > 0.0) || !(reverse > 0.0) || !std::isfinite(reverse)) return {};
  const SampledSpectrum<N> r_l = r->r_l * e.r_l, r_u = r->r_u * e.r_u;
  const double p_connection = point_pdf / (e.cos_light * reverse);
  const double weight = power_heuristic(p_connection * mean_ratio(s, path_r_u, r_l),
                                        vertex_pdf * r->fresnel * mean_ratio(s, path_r_u, r_u));
  return fv * e.value * r->tr * e.tr *
         static_cast<float>(weight * r->fresnel * manifold_detail::chain_eta_ratio2(*c) * reverse /
                            mean_ratio(s, path_r_u, r_l));
}

// Whether the segment from a to b certainly crosses a caster's sphere: then next-event estimation
// skips the straight shadow ray to an area lamp's point (direct_light.h), and with it the
// connections through a cylinder's side from that point (cylinder_path_densities asks the same).
bool caster_between(const RenderScene& s, const Vec3& a, const Vec3& b);

// A walk's path from the connecting vertex x through refractions of caster c (at crossings ys) to
// a lamp hit (an area or spherical light): the solid-angle density with which the connection at
// x draws that path (0 where it would not: its full solve does not find the path, or a spherical
// lamp's point lies outside the part it draws on), and the probability of the walk's own choices
// to refract at each crossing (the Fresnel transmittances' product). The walk's weight against
// the connection comes from these (radiance.h: CasterTrail).
struct CasterPathDensities {
  double connection = 0.0, refraction = 1.0;
};
CasterPathDensities caster_path_densities(const RenderScene& s, const ManifoldCaster& c, const Vec3& x,
                                          const std::array<Vec3, 2>& ys, int crossings, const Hit& light_hit);

// The same for a walk's path from the connecting vertex x (on the surface x_hit, or in a medium:
// null; `inside` the nested set there, a surface's as the walk arrived) through refractions at
// mesh faces (crossings `ys`, in order) to a lamp hit: the density with which next-event
// estimation draws the lamp point for the straight line (pdf_point, the lamp's choice by power)
// and area_light_through_chain then finds this path (0 where the straight segment does not cross
// the same surfaces, Newton from it reaches another path or none), over the change of variables;
// and the walk's probability of refracting at each crossing.
CasterPathDensities chain_path_densities(const RenderScene& s, const Vec3& x, const Hit* x_hit, InsideSet inside,
                                         std::span<const Vec3> ys, const Hit& light_hit, std::uint64_t& rays);

// The same for a walk's path through an exact cylinder's side (crossings `ys`, one or two, on it)
// to a lamp hit: the connection draws it where the straight segment from x to the lamp point meets
// that side first (area_light_through_cylinder) and its solve finds the walk's path.
CasterPathDensities cylinder_path_densities(const RenderScene& s, const Vec3& x, const Hit* x_hit, InsideSet inside,
                                            std::span<const Vec3> ys, const Hit& light_hit, std::uint64_t& rays);

// The paths from vertex `at` to a point q (a delta lamp's position, the camera's pinhole) through
// the smooth interface whose hit `blocker` stopped the straight segment between them: a face of a
// mesh without shading normals or a cylinder's cap, solved on its plane, a chain of mesh faces
// (manifold_chain.h), or an exact sphere that is not a caster (a nested one; casters are
// through_casters'); each path as through_each, q sending what `end` says, add(l, reach) taking
// it. `towards(wi, pdf)` gives the vertex's f·|cos θ| towards wi, medium_towards(wi) the medium wi
// leaves into. path_r_u: the path's unidirectional ratios so far, each path divided by the mean of
// their product with its own light ratios (direct_light.h).
template <std::size_t N, typename Towards, typename MediumTowards, typename End, typename Add>
void through_interface_each(const SceneView<N>& v, const PathVertex& at, const Vec3& q, const Hit& blocker,
                            Towards towards, MediumTowards medium_towards, const SampledWavelengths<N>& w,
                            const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays, TubeFrom from, End end,
                            Add add) {
  using namespace manifold_detail;
  const RenderScene& s = v.scene;
  if (find_caster(s, blocker.geometry)) return;
  const InsideSet inside = at.hit ? inside_towards(s, *at.hit, at.inside, normalize(q - at.point)) : at.inside;
  // Faces of meshes: one without shading normals has its exact solve below; smooth-shaded ones,
  // and two or more crossings, the chain's.
  // (A straight segment the chain cannot seed, something else behind the face, leaves a flat face
  // to its own solve: the refracted path may pass by what the straight one meets.)
  if (!s.rays.analytic(blocker.geometry)) {
    const bool smooth_shaded = dot(blocker.shading_normal, blocker.normal) < 1.0 - 1e-9;
    const auto chain = seed_chain(s, at.point, at.hit, inside, q, rays);
    if (chain && (chain->count > 1 || smooth_shaded))
      return through_chain_each(v, at, *chain, q, towards, medium_towards, w, path_r_u, rng, rays, from, end, add);
    if (smooth_shaded) return;
  }
  const auto f = smooth_interface(s, blocker, surface_seen(s, blocker, inside));
  if (!f) return;
  // (A sphere crossed twice is a caster's case: a nested sphere's media change with the path. A
  // cylinder's side crossed twice, a glass rod between the vertex and the lamp, is solved here.)
  if (f->shape == Interface::Shape::sphere && f->front(at.point) && f->front(q)) return;
  through_each(v, at, inside, *f, q, towards, medium_towards, w, path_r_u, rng, rays, end, add);
}

// The light of a distant lamp (a sun) at vertex `at` through the flat smooth interface whose hit
// `blocker` stopped the straight shadow ray (a cylinder's cap; a flat face of a mesh where no line
// seeds a chain): the one path that refracts there into the sun's direction beyond
// (solve_towards: no solve), its irradiance across the beam E·T·cos θ_l/cos θ_x (beam_tube: flux
// through a tube, no n², as for the point lamps' tubes). Unweighted, as every delta lamp's
// connection (no other strategy of the path tracer reaches a delta lamp; bdpt's through_glass
// says why its weight is 1 there too). The face the straight line meets, or one the refracted
// lines tried meet first (three tries); not one neither meets first, nor where the caller tries
// none (the straight line stopped by something opaque first, or a surface that faces the
// refracted direction but not the sun). add(l, last) as distant_through.
template <std::size_t N, typename Towards, typename MediumTowards, typename Add>
void distant_light_through_plane(const SceneView<N>& v, const PathVertex& at, const DistantLight& sun,
                                 const Hit& blocker, Towards towards, MediumTowards medium_towards,
                                 const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng,
                                 std::uint64_t& rays, Add add) {
  using namespace manifold_detail;
  const RenderScene& s = v.scene;
  const Vec3 travel_sun = normalize(sun.direction), to_sun = -travel_sun;
  const InsideSet inside = at.hit ? inside_towards(s, *at.hit, at.inside, to_sun) : at.inside;
  // The face the straight line meets first; where the refracted line meets another surface first
  // (near an edge of a box of water: the straight line leaves by a side, the refracted one by the
  // top), that one's plane next, up to three tries (a path accepted is valid whatever face it
  // crosses: follow checks it, and the sun's line beyond).
  SceneView<N> geometry = v;
  geometry.visibility_only = true;
  Rng unused(0, kManifoldStream);  // (nothing is drawn)
  Hit face = blocker;
  for (int tries = 0; tries < 3; ++tries) {
    if (find_caster(s, face.geometry)) return;
    if (!s.rays.analytic(face.geometry) && dot(face.shading_normal, face.normal) < 1.0 - 1e-9) return;
    const auto f = smooth_interface(s, face, surface_seen(s, face, inside));
    if (!f || f->shape != Interface::Shape::plane) return;
    const Paths p = solve_towards(*f, at.point, to_sun, s.media[static_cast<std::size_t>(f->medium_front)].ior_reference,
                                  s.media[static_cast<std::size_t>(f->medium_behind)].ior_reference);
    if (p.count == 0) return;
    const Vec3 wi = normalize(p.crossing[0][0] - at.point);
    if (at.hit && dot(wi, at.hit->normal) * dot(to_sun, at.hit->normal) <= 0.0) return;  // (its other side)
    // Whether the path is clear to its crossing is the geometry's (next_event_makes asks the same):
    // ratio tracking's estimate of 0 in a scattering medium must not send this on to another face.
    if (follow(geometry, at, inside, *f, p.crossing[0], 1, p.crossing[0][0] + to_sun, medium_towards, w, unused, rays)) {
      distant_through(v, at, inside, *f, sun, towards, medium_towards, w, path_r_u, rng, rays, add);
      return;
    }
    const auto next = s.rays.intersect(Ray{at.origin_towards(wi), wi});
    ++rays;
    if (!next || (next->geometry == face.geometry && dot(next->normal, face.normal) > 1.0 - 1e-9)) return;
    face = *next;
  }
}

// How many lines a distant lamp's connection through chains of mesh faces seeds chains from
// (distant_light_through_chains), and the probes it casts for the faces they may cross
// (measured on a sunlit tumbler of haze, bench/light_paths.py: docs/performance.md).
inline constexpr int kSunSeeds = 3, kSunProbes = 4;
inline constexpr double kSunProbeTilt_rad = 0.6;  // (34°)

// The light of a distant lamp at vertex `at` along one chain of mesh faces, solved towards it
// (solve_chain_towards): f·|cos θ| towards its first crossing, E times the beam tube
// (chain_beam_tube), Fresnel at each crossing (by the shading normal, as the walk), every
// segment's transmittance, the lamp's line beyond the last crossing clear to infinity.
template <std::size_t N, typename Towards, typename MediumTowards>
SampledSpectrum<N> distant_light_along_chain(const SceneView<N>& v, const PathVertex& at, const DistantLight& sun,
                                             const Chain& c, Towards towards, MediumTowards medium_towards,
                                             const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u,
                                             Rng& rng, std::uint64_t& rays) {
  using namespace manifold_detail;
  const RenderScene& s = v.scene;
  const Vec3 to_lamp = -normalize(sun.direction);
  const Vec3 beyond = c.crossing[static_cast<std::size_t>(c.count - 1)].hit.point + to_lamp;
  const auto r = follow_chain(v, at, c, beyond, medium_towards, w, rng, rays);
  if (!r) return {};
  double vertex_pdf = 0.0;
  const SampledSpectrum<N> fv = towards(r->wi, vertex_pdf);
  if (fv.is_zero()) return {};
  const LightEnd<N> e = distant_lamp_end(v, sun, to_lamp, *r, w, rng, rays);
  if (e.value.is_zero()) return {};
  const double tube = chain_beam_tube(s, at.point, to_lamp, c);
  if (!(tube > 0.0) || !std::isfinite(tube)) return {};
  return fv * e.value * r->tr * e.tr * static_cast<float>(r->fresnel * tube / mean_ratio(s, path_r_u, r->r_l * e.r_l));
}

// The light of a distant lamp at vertex `at` (`inside`: the nested set leaving it towards the
// lamp) through chains of smooth refracting mesh faces, summed over the distinct paths found. A
// point in a drink near its surface gets the sun both through the surface and through the glass's
// wall, and which the straight line meets says nothing of the other; so chains are seeded from
// several lines, each solved towards the lamp (Newton from that line's crossings), and a path
// found from two lines is counted once (the same crossings in order, to 1e-6 of its first
// segment). The lines: the straight one; then the lamp's direction of travel at the vertex
// refracted once by the plane of the face each of kSunProbes probes, kSunProbeTilt_rad off the
// straight line, meets first (from the index beyond the straight line's last crossing to the
// vertex's: through a thin wall, nearly its path; the surface, where the straight line leaves by
// the wall); kSunSeeds lines at most, none within about 2.6° of another, and none solved whose
// crossings lie on the same surfaces as an earlier line's, each facing much as there. (On a
// sunlit tumbler: also refracting by the faces the lines cross, six lines, found 0.5 % more light
// at twice the cost; two lines, 8 % less; the straight line alone, 11 % less.) Paths none of
// these lead Newton to are missing (docs/rendering.md: the path tracer's light paths bring them);
// `any`: some line crossed only such faces. add(l, last) as distant_through.
template <std::size_t N, typename Towards, typename MediumTowards, typename Add>
void distant_light_through_chains(const SceneView<N>& v, const PathVertex& at, const DistantLight& sun,
                                  InsideSet inside, Towards towards, MediumTowards medium_towards,
                                  const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng,
                                  std::uint64_t& rays, bool& any, Add add) {
  const RenderScene& s = v.scene;
  const Vec3 to_lamp = -normalize(sun.direction);
  std::array<Vec3, kSunSeeds> lines{};
  int line_count = 0;
  auto add_line = [&](const Vec3& d) {
    if (line_count == kSunSeeds) return;
    for (int i = 0; i < line_count; ++i)
      if (dot(d, lines[static_cast<std::size_t>(i)]) > 0.999) return;
    lines[static_cast<std::size_t>(line_count++)] = d;
  };
  // The lamp's direction of travel at the vertex refracted by a plane of normal n, from eta_lamp
  // to eta_x, reversed (towards the plane), where it gets through.
  double eta_x = 0.0, eta_lamp = 0.0;
  auto add_refracted = [&](Vec3 n) {
    if (dot(n, to_lamp) < 0.0) n = -n;
    const double cos_l = dot(to_lamp, n), cos_x = cos_theta_transmitted(cos_l, eta_lamp, eta_x);
    if (cos_l > 0.0 && cos_x > 0.0) add_line(-refract(to_lamp, n, cos_l, cos_x, eta_lamp / eta_x));
  };
  std::array<Chain, kSunSeeds> found{};
  int found_count = 0;
  auto same_path = [&](const Chain& a, const Chain& b) {
    if (a.count != b.count) return false;
    const double tolerance = 1e-6 * length(a.crossing[0].hit.point - at.point);
    for (int i = 0; i < a.count; ++i)
      if (length(a.crossing[static_cast<std::size_t>(i)].hit.point - b.crossing[static_cast<std::size_t>(i)].hit.point) >
          tolerance)
        return false;
    return true;
  };
  // (A line whose crossings are on the same surfaces as an earlier line's, in order, each facing
  // within about 18° of that one's, would most likely lead Newton where that one's did: it is not
  // solved. The facets of one curved wall are alike; a wall and a liquid's surface are not.)
  std::array<Chain, kSunSeeds> seeded{};
  int seeded_count = 0;
  auto same_faces = [](const Chain& a, const Chain& b) {
    if (a.count != b.count) return false;
    for (int i = 0; i < a.count; ++i) {
      const Hit &p = a.crossing[static_cast<std::size_t>(i)].hit, &q = b.crossing[static_cast<std::size_t>(i)].hit;
      if (p.geometry != q.geometry || dot(p.normal, q.normal) < 0.95) return false;
    }
    return true;
  };
  add_line(to_lamp);
  for (int i = 0; i < line_count; ++i) {
    auto c = seed_chain_towards(s, at.point, at.hit, inside, lines[static_cast<std::size_t>(i)], rays);
    if (!c) continue;
    any = true;
    bool again = false;
    for (int k = 0; k < seeded_count && !again; ++k) again = same_faces(seeded[static_cast<std::size_t>(k)], *c);
    if (again) continue;
    seeded[static_cast<std::size_t>(seeded_count++)] = *c;
    if (eta_x == 0.0) {  // (the straight line's indices, or the first line seeded)
      eta_x = c->crossing[0].eta_from, eta_lamp = c->crossing[static_cast<std::size_t>(c->count - 1)].eta_to;
      const Frame around(to_lamp);
      for (int k = 0; k < kSunProbes; ++k) {
        const double phi = 2.0 * std::numbers::pi * k / kSunProbes;
        const Vec3 d = normalize(to_lamp * std::cos(kSunProbeTilt_rad) +
                                 (around.s * std::cos(phi) + around.t * std::sin(phi)) * std::sin(kSunProbeTilt_rad));
        // (The surface a probe meets across index-matched ones, as a line would seed it: a
        // point 1000 km along it stands for infinity.)
        const auto probe = first_surface(s, at.point, at.hit, inside, at.point + d * 1e6, rays);
        if (probe && smooth_glass_seen(probe->seen)) add_refracted(probe->hit.shading_normal);
      }
    }
    if (!solve_chain_towards(s, at.point, at.hit, to_lamp, *c, rays)) continue;
    const Vec3 first = c->crossing[0].hit.point;
    if (at.hit && dot(first - at.point, at.hit->normal) * dot(to_lamp, at.hit->normal) <= 0.0) continue;
    bool seen = false;
    for (int k = 0; k < found_count && !seen; ++k) seen = same_path(found[static_cast<std::size_t>(k)], *c);
    if (seen) continue;
    found[static_cast<std::size_t>(found_count++)] = *c;
    const SampledSpectrum<N> l = distant_light_along_chain(v, at, sun, *c, towards, medium_towards, w, path_r_u, rng, rays);
    if (!l.is_zero()) add(l, c->crossing[static_cast<std::size_t>(c->count - 1)].hit.point);
  }
}

// The light of a distant lamp at vertex `at` through the smooth interface whose hit `blocker`
// stopped the straight shadow ray: faces of meshes through chains (distant_light_through_chains),
// or, where no line seeds one (something opaque behind the face), a flat face by its plane; a
// cylinder's cap by its plane; an exact sphere that is not a caster from inside it (a nested one;
// casters are through_casters'). Nothing through a cylinder's side (docs/rendering.md). add(l,
// last) as distant_through.
template <std::size_t N, typename Towards, typename MediumTowards, typename Add>
void distant_light_through_interface(const SceneView<N>& v, const PathVertex& at, const DistantLight& sun,
                                     const Hit& blocker, Towards towards, MediumTowards medium_towards,
                                     const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng,
                                     std::uint64_t& rays, Add add) {
  using namespace manifold_detail;
  const RenderScene& s = v.scene;
  if (find_caster(s, blocker.geometry)) return;
  const Vec3 to_lamp = -normalize(sun.direction);
  const InsideSet inside = at.hit ? inside_towards(s, *at.hit, at.inside, to_lamp) : at.inside;
  if (!s.rays.analytic(blocker.geometry)) {
    bool any = false;
    distant_light_through_chains(v, at, sun, inside, towards, medium_towards, w, path_r_u, rng, rays, any, add);
    if (any || dot(blocker.shading_normal, blocker.normal) < 1.0 - 1e-9) return;
  }
  const auto f = smooth_interface(s, blocker, surface_seen(s, blocker, inside));
  if (!f) return;
  switch (f->shape) {
    case Interface::Shape::plane:
      return distant_light_through_plane(v, at, sun, blocker, towards, medium_towards, w, path_r_u, rng, rays, add);
    case Interface::Shape::sphere:
      if (f->front(at.point)) return;  // (crossed twice: a caster's case, as for the point lamps)
      return distant_through(v, at, inside, *f, sun, towards, medium_towards, w, path_r_u, rng, rays, add);
    case Interface::Shape::cylinder: break;
  }
}

// The light of delta light `light` at vertex `at` through the smooth interface whose hit
// `blocker` stopped the straight shadow ray (through_interface_each; a distant lamp's,
// distant_light_through_interface), summed.
template <std::size_t N, typename Towards, typename MediumTowards>
SampledSpectrum<N> delta_light_through_interface(const SceneView<N>& v, const PathVertex& at, const Light& light,
                                                 const Hit& blocker, Towards towards, MediumTowards medium_towards,
                                                 const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u,
                                                 Rng& rng, std::uint64_t& rays) {
  SampledSpectrum<N> sum;
  if (const auto* sun = std::get_if<DistantLight>(&light)) {
    distant_light_through_interface(v, at, *sun, blocker, towards, medium_towards, w, path_r_u, rng, rays,
                                    [&](const SampledSpectrum<N>& l, const Vec3&) { sum += l; });
    return sum;
  }
  const auto lamp = manifold_detail::delta_lamp(light);
  if (!lamp) return {};
  auto end = [&](const manifold_detail::Reach<N>& r) { return manifold_detail::delta_lamp_end(v, *lamp, r, w, rng, rays); };
  through_interface_each(v, at, lamp->p, blocker, towards, medium_towards, w, path_r_u, rng, rays, TubeFrom::vertex,
                         end, [&](const SampledSpectrum<N>& l, const manifold_detail::Reach<N>&) { sum += l; });
  return sum;
}

// How near a solved path's last crossing must come to a light path's first (`nearest_lamp`) to be
// the same path (next_event_makes): 1e-5 of the path's length (at least of the float rounding's
// scale there); at least 4 ray offsets a crossing: the light path's rays leave each crossing
// from an origin offset off the surface (ray_offset_m, 4e-6 of the coordinates), which moves its
// path up to about that much off the exact one (a sun's paths through a glass's wall came out
// 2e-7 to 1.5e-6 m off, 2e-6 to 4e-5 of their length, and a tolerance of 1e-5 of it alone counted
// a fifth of them twice); and, for a sun, 1e-6 of how far its light subpath's first ray went
// (`start_m`, from the disk it starts on: a float hit there is good to about 6e-8 of it, which in
// a scene a kilometre across is more than the rest; measured from the disk, 1e-5 of the path
// would have been millimetres there, enough to take two paths near a caustic's fold for one).
inline double made_within_m(const RenderScene& s, const Vec3& nearest_lamp, double path_m, double start_m,
                            int crossings) {
  return std::max({1e-5 * std::max(path_m, s.rays.rounding_scale_m(nearest_lamp)),
                   4.0 * crossings * ray_offset_m(nearest_lamp), 1e-6 * start_m});
}

// Whether the path tracer's next-event estimation at vertex `at` to delta lamp `lamp` (or, given
// `sun`, to that distant lamp) makes the
// path along which the lamp's light reached `at` refracted at each of `crossings` smooth
// interfaces and reflected nowhere (a light path's first vertex that is not specular: from the
// lamp through its first crossing, `nearest_lamp`, those refractions make one path; `path_m` its
// length, a sun's from its first vertex, `start_m` how far that lay from the disk a sun's light
// subpath started on). With no crossing, always (the straight shadow ray). Otherwise as direct_light_at asks:
// through each caster, and where `towards` and a spot's profile are not zero along the straight
// segment and its shadow ray is stopped by a smooth refracting interface, through that interface
// (a sun's: distant_light_through_interface, every line it seeds);
// made where one of the paths solved there crosses last (nearest the lamp) as near `nearest_lamp`
// as made_within_m allows, as chain_path_densities finds the walk's path. The question is
// the geometry's: the segments are traced for whether they are clear only (visibility_only: a
// transmittance ratio tracking estimates as 0 in a density field would otherwise answer "not
// made" at random), so it draws no random numbers. (Where next-event estimation gets 0 from a
// path it solves, f or a segment's transmittance, so does the light path.) The path tracer's light
// paths (render.light_paths) keep only what this does not make.
template <std::size_t N, typename Towards, typename MediumTowards>
bool next_event_makes(const SceneView<N>& v, const PathVertex& at, const manifold_detail::DeltaLamp& lamp,
                      const DistantLight* sun, const Vec3& nearest_lamp, double path_m, double start_m, int crossings,
                      Towards towards, MediumTowards medium_towards, const SampledWavelengths<N>& w,
                      std::uint64_t& rays) {
  using namespace manifold_detail;
  const RenderScene& s = v.scene;
  if (crossings == 0) return true;
  if (!v.manifold) return false;
  SceneView<N> geometry = v;
  geometry.visibility_only = true;
  Rng unused(0, kManifoldStream);  // (nothing is drawn)
  bool made = false;
  const SampledSpectrum<N> one = SampledSpectrum<N>::constant(1.0f);
  auto end = [&](const Reach<N>& r) { return point_end(geometry, one, r, w, unused, rays); };
  auto made_at = [&](const Vec3& last) {
    made = made || length(last - nearest_lamp) < made_within_m(s, nearest_lamp, path_m, start_m, crossings);
  };
  auto add = [&](const SampledSpectrum<N>&, const Reach<N>& r) { made_at(r.last.point); };
  if (sun) {  // (every line distant_light_through_interface seeds, as direct_light_at asks)
    auto add_sun = [&](const SampledSpectrum<N>&, const Vec3& last) { made_at(last); };
    const Vec3 to_lamp = -normalize(sun->direction);
    const InsideSet inside = at.hit ? inside_towards(s, *at.hit, at.inside, to_lamp) : at.inside;
    for (const ManifoldCaster& c : s.casters)
      distant_through(geometry, at, inside, caster_interface(s, c), *sun, towards, medium_towards, w, one, unused, rays,
                      add_sun);
    double pdf = 0.0;
    if (made || towards(to_lamp, pdf).is_zero()) return made;
    bool glass = false;
    Hit blocker;
    if (!transmission(geometry, at, to_lamp, std::numeric_limits<double>::infinity(), medium_towards(to_lamp), w,
                      unused, rays, {}, &glass, &blocker) &&
        glass)
      distant_light_through_interface(geometry, at, *sun, blocker, towards, medium_towards, w, one, unused, rays,
                                      add_sun);
    return made;
  }
  const Vec3 to = lamp.p - at.point;
  const double d = length(to);
  const Vec3 straight = to / d;
  const InsideSet inside = at.hit ? inside_towards(s, *at.hit, at.inside, straight) : at.inside;
  for (const ManifoldCaster& c : s.casters)
    through_each(geometry, at, inside, caster_interface(s, c), lamp.p, towards, medium_towards, w, one, unused, rays,
                 end, add);
  double pdf = 0.0;
  // (A spot that does not send light along the straight segment: next-event estimation stops there.)
  if (made || towards(straight, pdf).is_zero() || (lamp.spot && spot_falloff(*lamp.spot, -straight) == 0.0))
    return made;
  bool glass = false;
  Hit blocker;
  if (!transmission(geometry, at, straight, d, medium_towards(straight), w, unused, rays, {}, &glass, &blocker) && glass)
    through_interface_each(geometry, at, lamp.p, blocker, towards, medium_towards, w, one, unused, rays,
                           TubeFrom::vertex, end, add);
  return made;
}

// The light of an area or spherical lamp at vertex `at` through an exact cylinder's side (once, or
// in and out: a rod), from the point y next-event estimation drew on it for the straight line
// (point_pdf: its density per m², the lamp's choice by power included), where the first surface
// that straight segment meets is that side (first_surface). Then as `through`: the solved paths,
// each weighted by the power heuristic against the walk's own paths through the same side (its
// direction's density times the probability of refracting at each crossing: radiance.h,
// CylinderTrail and cylinder_path_densities, which asks the same first surface).
template <std::size_t N, typename Towards, typename MediumTowards>
SampledSpectrum<N> area_light_through_cylinder(const SceneView<N>& v, const PathVertex& at, const Light& light,
                                               const Vec3& y, double point_pdf, Towards towards,
                                               MediumTowards medium_towards, const SampledWavelengths<N>& w,
                                               const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays) {
  using namespace manifold_detail;
  if (!(point_pdf > 0.0)) return {};
  const auto met = cylinder_met_first(v.scene, at.point, at.hit, at.inside, y, rays);
  if (!met) return {};
  auto end = [&](const Reach<N>& r) { return area_lamp_end(v, light, y, point_pdf, r, w, rng, rays); };
  return through(v, at, met->inside, met->f, y, towards, medium_towards, w, path_r_u, rng, rays, end);
}

// The light of the delta lights and of one area or spherical light (its index drawn by power with
// probability p_choice, its point by area from u1, u2: on a spherical lamp, on the part that faces
// each caster) at vertex `at` through each caster (RenderScene::casters), once or twice crossed.
template <std::size_t N, typename Towards, typename MediumTowards>
SampledSpectrum<N> through_casters(const SceneView<N>& v, const PathVertex& at, Towards towards,
                                   MediumTowards medium_towards, std::optional<std::pair<int, double>> area_light,
                                   double u1, double u2,
                                   const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng,
                                   std::uint64_t& rays) {
  using namespace manifold_detail;
  const RenderScene& s = v.scene;
  SampledSpectrum<N> sum;
  const Light* light = area_light ? &s.lights[static_cast<std::size_t>(area_light->first)] : nullptr;
  for (const ManifoldCaster& c : s.casters) {
    const Interface f = caster_interface(s, c);
    const std::optional<LightAreaSample> y = light ? facing_point(*light, c, u1, u2) : std::nullopt;
    // The nested set the connections leave with (a caster has no priority; the vertex's own
    // surface may).
    auto inside_along = [&](const Vec3& q) {
      return at.hit ? inside_towards(s, *at.hit, at.inside, normalize(q - at.point)) : at.inside;
    };
    for (const int index : s.delta_lights) {
      const Light& lamp_light = s.lights[static_cast<std::size_t>(index)];
      if (const auto lamp = delta_lamp(lamp_light))
        sum += delta_through(v, at, inside_along(lamp->p), f, *lamp, towards, medium_towards, w, path_r_u, rng, rays);
      else if (const auto* sun = std::get_if<DistantLight>(&lamp_light))
        distant_through(v, at, inside_along(at.point - normalize(sun->direction)), f, *sun, towards, medium_towards, w,
                        path_r_u, rng, rays, [&](const SampledSpectrum<N>& l, const Vec3&) { sum += l; });
    }
    if (!y) continue;
    auto end = [&](const Reach<N>& r) {
      return area_lamp_end(v, *light, y->p, area_light->second * y->pdf_area, r, w, rng, rays);
    };
    sum += through(v, at, inside_along(y->p), f, y->p, towards, medium_towards, w, path_r_u, rng, rays, end);
  }
  return sum;
}

}  // namespace bouguer
