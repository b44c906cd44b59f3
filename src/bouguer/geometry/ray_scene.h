#pragma once
// Ray queries against all triangles of a scene (Embree 3 behind this one interface; no other
// file includes Embree). Geometry ids are given out in the order meshes are added.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>

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
  std::uint32_t primitive = 0;
  Vec3 point;                 // recomputed from the triangle's barycentrics (more exact than o + t·d)
  Vec3 normal;                // unit geometric normal; outward for closed, consistently wound meshes
  std::array<double, 2> barycentric{0.0, 0.0};  // (b1, b2) of the triangle's vertices 1 and 2
  // Unit shading normal, on the side of `normal`: interpolated from the mesh's normals, or `normal`
  // where the mesh has none.
  Vec3 shading_normal;
  // Texture coordinates: interpolated from the mesh's UVs, or the barycentrics where it has none.
  std::array<double, 2> uv{0.0, 0.0};
};

class RayScene {
 public:
  RayScene();
  ~RayScene();
  RayScene(RayScene&&) noexcept;
  RayScene& operator=(RayScene&&) noexcept;

  std::uint32_t add(const Mesh& mesh);
  void commit();

  std::optional<Hit> intersect(const Ray& ray) const;
  const Mesh& mesh(std::uint32_t geometry) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Start point for a ray leaving `hit` in `direction`: moved off the surface, to the side the
// direction points to, by a distance that scales with the coordinates' magnitude (a few dozen
// float ulps), so secondary rays neither re-hit their own surface nor skip thin slivers.
// Inline: it runs at every vertex of every path.
inline Vec3 offset_ray_origin(const Hit& hit, bool towards_normal) {
  const Vec3& p = hit.point;
  const double magnitude = std::max(std::max(std::abs(p.x), std::abs(p.y)), std::max(std::abs(p.z), 1e-3));
  const double offset = 4e-6 * magnitude;  // ≈ 32 float ulps of the largest coordinate
  return p + hit.normal * (towards_normal ? offset : -offset);
}
inline Vec3 offset_ray_origin(const Hit& hit, const Vec3& direction) {
  return offset_ray_origin(hit, dot(direction, hit.normal) > 0.0);
}

}  // namespace bouguer
