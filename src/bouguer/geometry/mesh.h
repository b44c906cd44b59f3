#pragma once
// Indexed triangle meshes. Winding convention: counter-clockwise seen from the side the
// geometric normal cross(p1 − p0, p2 − p0) points to; for closed shapes that side is outside.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bouguer/core/math.h"

namespace bouguer {

// A vertex tangent (glTF's TANGENT): a unit vector along increasing u, and the handedness of the
// tangent frame, ±1: bitangent = sign · cross(shading normal, tangent).
struct Tangent {
  Vec3 direction;
  double sign = 1.0;
  bool operator==(const Tangent&) const = default;
};

struct Mesh {
  std::vector<Vec3> positions;  // metres
  std::vector<std::array<std::uint32_t, 3>> triangles;
  // Optional per-vertex attributes, each empty or one per position: unit shading normals (on the
  // side of the geometric normal) and texture coordinates. A hit interpolates them.
  std::vector<Vec3> normals;
  std::vector<std::array<double, 2>> uvs;
  // Tangents, only where the source gives them (a glTF primitive's TANGENT) and then only with
  // normals; a normal map reads them instead of the frame of the triangle's UVs (scene/normal_map.h).
  std::vector<Tangent> tangents;
};

// Appends src's triangles; an attribute is kept only when both meshes have it (or dst is empty).
void append(Mesh& dst, const Mesh& src);
// The winding reversed, the normals negated (they stay on the geometric normal's side) and with
// them the tangents' signs (the bitangent stays where it was).
Mesh flipped(Mesh m);

// Merges vertices closer than tolerance_m and drops triangles that become degenerate. The result
// has positions only; with keep_attributes, it keeps the normals, UVs and tangents, and merges only
// vertices whose attributes are the same too (a crease or a UV seam stays two vertices).
Mesh welded(const Mesh& m, double tolerance_m, bool keep_attributes = false);

// Signed volume (m³): positive when the triangles face outward.
double signed_volume(const Mesh& m);

// Why a mesh cannot bound a medium: open boundary, inconsistent winding, non-manifold edges, or
// facing inward. nullopt when it is closed, consistently oriented and outward-facing.
std::optional<std::string> closed_surface_problem(const Mesh& m);

// The distance from p to the nearest point of triangle (a, b, c) (Ericson, "Real-Time Collision
// Detection", 5.1.5: the Voronoi region of p among the corners, edges and face), and p minus
// that nearest point.
double triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
Vec3 triangle_offset(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// Largest absolute coordinate (m), the scale for welding and ray offsets.
double max_extent(const Mesh& m);

}  // namespace bouguer
