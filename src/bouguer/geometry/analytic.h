#pragma once
// Quadrics intersected exactly, without facets: a sphere, a capped cylinder and a disk, each in
// its local frame (the same frames as the tessellated shapes of shapes.h) and placed by an
// affine transform. Pure functions, so they are tested without Embree; geometry/ray_scene.cpp
// hands them to Embree as user geometry.
#include <array>
#include <cstdint>
#include <optional>
#include <variant>

#include "bouguer/core/math.h"
#include "bouguer/geometry/transform.h"

namespace bouguer {

struct SphereSurface { double radius_m = 1; };                       // centred at the origin
struct CylinderSurface { double radius_m = 1, height_m = 1; };       // base y = 0, axis +y, both caps
struct DiskSurface { double radius_m = 1; };                         // xy-plane, normal +z
using AnalyticSurface = std::variant<SphereSurface, CylinderSurface, DiskSurface>;

// A surface and where it stands in the world.
struct AnalyticShape {
  AnalyticSurface surface;
  Transform to_world;
};

// Which part of a surface a hit is on (the hit's primitive): the cylinder's side and caps.
enum class AnalyticPart : std::uint32_t { side = 0, bottom = 1, top = 2 };

// A hit in the local frame: exact point (projected onto the surface), outward unit normal and
// texture coordinates in [0, 1]² (sphere: longitude atan2(−z, x)/2π and colatitude/π from +y;
// cylinder side: the same longitude and y/height; disk and caps: the plane's two coordinates
// mapped from [−r, r]).
struct LocalHit {
  double t = 0.0;  // along the local ray o + t·d (d unnormalised: t is the world ray's t)
  Vec3 point;
  Vec3 normal;
  std::array<double, 2> uv{0.0, 0.0};
  AnalyticPart part = AnalyticPart::side;
};

// The nearest hit of the local ray o + t·d with t in (t_min, t_max), or nullopt.
std::optional<LocalHit> intersect_local(const AnalyticSurface& s, const Vec3& o, const Vec3& d, double t_min,
                                        double t_max);

// The distance from the local point p to the nearest point of the surface (the cylinder's side
// and both caps).
double distance_local(const AnalyticSurface& s, const Vec3& p);
// That nearest point (local); a point of the sphere or the cylinder's side where p is on its axis.
Vec3 nearest_local(const AnalyticSurface& s, const Vec3& p);

// The surface's local bounding box (lo, hi).
std::array<Vec3, 2> local_bounds(const AnalyticSurface& s);

// A cylinder's side placed in the world, where it stays circular (the transform a similarity
// across its axis, the axis perpendicular to that, any stretch along it): a point of its axis (the
// base's centre), the axis (unit, from the base to the top) and its radius. Nothing for an
// elliptic one.
struct CircularSide {
  Vec3 on_axis, axis;
  double radius_m = 0.0;
};
std::optional<CircularSide> circular_side(const CylinderSurface& c, const Transform& to_world);

}  // namespace bouguer
