#pragma once
// Ray queries against all triangles and analytic surfaces of a scene (Embree 3 behind this one
// interface; no other file includes Embree). Geometry ids are given out in the order meshes and
// analytic shapes are added.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>

#include "bouguer/geometry/analytic.h"
#include "bouguer/geometry/mesh.h"

namespace bouguer {

struct Ray {
  Vec3 origin;     // metres
  Vec3 direction;  // unit
  double t_max = std::numeric_limits<double>::infinity();
};

struct Hit {
  double t = 0.0;             // metres along the ray
  std::uint32_t geometry = 0;
  std::uint32_t primitive = 0;  // the triangle, or the analytic surface's part (AnalyticPart)
  // Recomputed from the triangle's barycentrics, or projected onto the analytic surface (more
  // exact than o + t·d).
  Vec3 point;
  // Unit geometric normal; outward for closed, consistently wound meshes and for closed analytic
  // surfaces, where it is the exact normal of the quadric.
  Vec3 normal;
  std::array<double, 2> barycentric{0.0, 0.0};  // (b1, b2) of the triangle's vertices 1 and 2; 0 on analytic
  // Unit shading normal, on the side of `normal`: interpolated from the mesh's normals, or `normal`
  // where the mesh has none.
  Vec3 shading_normal;
  // Texture coordinates: interpolated from the mesh's UVs, or the barycentrics where it has none;
  // on an analytic surface those of LocalHit (geometry/analytic.h).
  std::array<double, 2> uv{0.0, 0.0};
};

class RayScene {
 public:
  RayScene();
  ~RayScene();
  RayScene(RayScene&&) noexcept;
  RayScene& operator=(RayScene&&) noexcept;

  std::uint32_t add(const Mesh& mesh);
  // A surface intersected exactly, in double precision (Embree user geometry): no triangles.
  std::uint32_t add(const AnalyticShape& shape);
  void commit();

  std::optional<Hit> intersect(const Ray& ray) const;
  // The distance from p to the nearest surface (triangle or analytic), or radius_m where none is
  // nearer (Embree's point query over the same tree). Never more than the true distance, up to
  // rounding: an affinely placed analytic surface gives its local distance times the transform's
  // smallest stretch. With `nearest`, also the nearest surface's nearest point where one is
  // nearer than radius_m (left as it is otherwise): exact on a triangle; on an affinely placed
  // analytic surface, the local nearest point carried to the world (the nearest for a rigid one).
  // With `geometry`, the nearest surface's geometry id (Hit::geometry) there too.
  double distance_to_surfaces(const Vec3& p, double radius_m, Vec3* nearest = nullptr,
                              std::uint32_t* geometry = nullptr) const;
  // The scale of float rounding about p (m): its largest absolute coordinate or the committed
  // scene's box's, whichever is larger (at least 1 mm). Embree's float boxes and hits are off by
  // about 1e-7 of it.
  double rounding_scale_m(const Vec3& p) const;
  // The triangles of a mesh geometry (empty for an analytic one).
  const Mesh& mesh(std::uint32_t geometry) const;
  // The analytic shape of a geometry, or null for a mesh.
  const AnalyticShape* analytic(std::uint32_t geometry) const;
  // A world-space box (lo, hi) around a geometry.
  std::array<Vec3, 2> bounds(std::uint32_t geometry) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Start point for a ray leaving `hit` in `direction`: moved off the surface, to the side the
// direction points to, by a distance that scales with the coordinates' magnitude (a few dozen
// float ulps), so secondary rays neither re-hit their own surface nor skip thin slivers.
// Inline: it runs at every vertex of every path.
// The distance a ray's origin is moved off a surface at p: ≈ 32 float ulps of its largest
// coordinate (at least 1 mm's). Also how far short of a target on a surface a ray must stop
// (twice it) for that surface not to block it (transmission, manifold.h).
inline double ray_offset_m(const Vec3& p) {
  const double magnitude = std::max(std::max(std::abs(p.x), std::abs(p.y)), std::max(std::abs(p.z), 1e-3));
  return 4e-6 * magnitude;
}
inline Vec3 offset_ray_origin(const Hit& hit, bool towards_normal) {
  const double offset = ray_offset_m(hit.point);
  return hit.point + hit.normal * (towards_normal ? offset : -offset);
}
inline Vec3 offset_ray_origin(const Hit& hit, const Vec3& direction) {
  return offset_ray_origin(hit, dot(direction, hit.normal) > 0.0);
}

}  // namespace bouguer
