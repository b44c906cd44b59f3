#include "bouguer/scene/normal_map.h"

#include <cmath>

namespace bouguer {

Vec3 tangent_space_normal(const Vec3& rgb, double scale) {
  return normalize(Vec3{(2.0 * rgb.x - 1.0) * scale, (2.0 * rgb.y - 1.0) * scale, 2.0 * rgb.z - 1.0});
}

Vec3 mapped_normal(const TextureTable& table, int texture, double scale, const Mesh& mesh, const Hit& hit) {
  const Vec3 n = hit.shading_normal;
  if (mesh.uvs.empty() || hit.primitive >= mesh.triangles.size()) return n;
  const auto& tri = mesh.triangles[hit.primitive];
  // The triangle's texture coordinates as the image reads them (its transform applied).
  const auto a = texture_coordinates(table, texture, mesh.uvs[tri[0]]);
  const auto b = texture_coordinates(table, texture, mesh.uvs[tri[1]]);
  const auto c = texture_coordinates(table, texture, mesh.uvs[tri[2]]);
  const Vec3 dp1 = mesh.positions[tri[1]] - mesh.positions[tri[0]], dp2 = mesh.positions[tri[2]] - mesh.positions[tri[0]];
  const double du1 = b[0] - a[0], dv1 = b[1] - a[1], du2 = c[0] - a[0], dv2 = c[1] - a[1];
  const double det = du1 * dv2 - du2 * dv1;
  if (!(std::abs(det) > 1e-20)) return n;
  const Vec3 dpdu = (dp1 * dv2 - dp2 * dv1) / det, dpdv = (dp2 * du1 - dp1 * du2) / det;
  // Gram–Schmidt against the shading normal; B keeps the side the UVs give it.
  const Vec3 t_raw = dpdu - n * dot(n, dpdu);
  if (!(length(t_raw) > 0.0)) return n;
  const Vec3 t = normalize(t_raw);
  const Vec3 b_raw = dpdv - n * dot(n, dpdv) - t * dot(t, dpdv);
  const Vec3 bt = length(b_raw) > 0.0 ? normalize(b_raw) : cross(n, t) * (dot(cross(n, t), dpdv) < 0.0 ? -1.0 : 1.0);
  const Vec3 local = tangent_space_normal(texture_rgb(table, texel_blend(table, texture, hit.uv, 0.0)), scale);
  const Vec3 mapped = normalize(t * local.x + bt * local.y + n * local.z);
  if (!(dot(mapped, hit.normal) > 0.0)) return n;
  return mapped;
}

}  // namespace bouguer
