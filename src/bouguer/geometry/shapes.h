#pragma once
// Shape generators: plain parameter structs (lengths in metres, angles in degrees) and
// make_shape, which turns one into triangles in its local frame (documented per shape in
// docs/scene-format.md). Convex cut shapes are built as intersections of half-spaces.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "bouguer/geometry/analytic.h"
#include "bouguer/geometry/mesh.h"

namespace bouguer {

struct QuadShape { double width_m = 1, height_m = 1; };                 // xy-plane, normal +z
// Spheres, cylinders and disks are analytic (exact, no facets: analytic_surface) unless
// `tessellate`; `segments` applies to the triangles only.
struct DiskShape { double radius_m = 1; int segments = 128; bool tessellate = false; };  // xy-plane, normal +z
struct BoxShape { Vec3 size_m{1, 1, 1}; };                               // centred
struct SphereShape { double radius_m = 1; int segments = 96; bool tessellate = false; };  // centred
struct CylinderShape {  // base y = 0, axis +y, capped
  double radius_m = 1, height_m = 1;
  int segments = 128;
  bool tessellate = false;
};
struct PrismShape { int sides = 6; double radius_m = 1, height_m = 1; };          // n-gon base on y = 0
struct PyramidShape { int sides = 6; double radius_m = 1, height_m = 1; };        // n-gon base, apex on +y
struct TruncatedCubeShape { double size_m = 1; double truncation = 0.29289321881345254; };  // centred
// Round brilliant: girdle diameter, table as a fraction of it, crown and pavilion main-facet
// angles, girdle thickness as a fraction of the diameter. Girdle centred on y = 0, table up.
struct BrilliantShape {
  double diameter_m = 0.01;
  double table = 0.57;
  double crown_angle_deg = 34.5;
  double pavilion_angle_deg = 40.75;
  double girdle = 0.03;
};
// Where the profile of a surface of revolution turns by more than this, its normal has a crease
// (shapes.cpp, revolve); below it the shading normal is smooth along the profile.
inline constexpr double kDefaultCreaseAngleDeg = 30.0;
// Surface of revolution about +y of a profile of (r, y) points.
struct LatheShape {
  std::vector<std::array<double, 2>> profile_m;
  int segments = 128;
  double crease_angle_deg = kDefaultCreaseAngleDeg;
};
// A bottle or glass: outer profile (r, y) from the bottom centre (r = 0) to the rim, wall
// thickness, and the fill level as a fraction of the inner height (0 = empty).
struct VesselShape {
  std::vector<std::array<double, 2>> profile_m;
  double wall_m = 0.002;
  double fill = 0.0;
  int segments = 128;
  double crease_angle_deg = kDefaultCreaseAngleDeg;
};
struct MeshShape { std::filesystem::path path; };
// Triangles already in memory (a front end's own mesh: glTF, Python): positions in metres, and
// per-vertex normals, UVs and tangents when the source has them (carried to the hit as Mesh
// attributes). Empty normals/uvs/tangents, or one per position; tangents only with normals.
struct TriangleMeshShape {
  Mesh mesh;
  std::vector<Vec3> normals;
  std::vector<std::array<double, 2>> uvs;
  std::vector<Tangent> tangents;
};

using Shape = std::variant<QuadShape, DiskShape, BoxShape, SphereShape, CylinderShape, PrismShape, PyramidShape,
                           TruncatedCubeShape, BrilliantShape, LatheShape, VesselShape, MeshShape, TriangleMeshShape>;

// The media on the two sides of each part, relative to the object: the object's own medium
// (`inside`), the medium around it (`outside`), or the vessel's contents.
enum class Side { object, surroundings, contents };

struct ShapePart {
  Mesh mesh;
  Side behind = Side::object;        // medium on the side opposite the normal
  Side in_front = Side::surroundings;  // medium the normal points into
};

// A shape's parts, in its local frame. Errors name `what` (the object) and the problem.
std::vector<ShapePart> make_shape(const Shape& shape, const std::string& what);

// The exact surface of a sphere, cylinder or disk not asked to be tessellated; nullopt for the
// other shapes, which are triangles. Errors name `what` (a radius or height that is not positive).
std::optional<AnalyticSurface> analytic_surface(const Shape& shape, const std::string& what);

// An OBJ's faces by their `usemtl` material, with each material's diffuse colour (Kd, linear, in
// [0, 1]) and diffuse texture (map_Kd, resolved against the OBJ's folder; empty: none). The MTL must
// exist and its Kd numbers be finite (an Error naming the file otherwise). Parts hold UVs and
// normals as load_obj's mesh does; a part's material is an index into `materials`, −1 for faces
// without one.
struct ObjMaterial {
  std::string name;
  Vec3 kd{0.5, 0.5, 0.5};
  std::filesystem::path map_kd;
};
struct ObjPart {
  Mesh mesh;
  int material = -1;
};
struct ObjWithMaterials {
  std::vector<ObjPart> parts;
  std::vector<ObjMaterial> materials;
};
ObjWithMaterials load_obj_materials(const std::filesystem::path& path, const std::string& what);

// Whether a shape can bound a medium (closed): quads and disks cannot.
bool shape_is_closed(const Shape& shape);

// At most how many triangles make_shape makes of `shape`, known before it makes them (so that a
// scene is refused before it tessellates more than fits in memory); 0 for a mesh file, whose
// reader bounds it by the file's size.
std::uint64_t triangle_bound(const Shape& shape);

}  // namespace bouguer
