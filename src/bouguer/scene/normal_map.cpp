#include "bouguer/scene/normal_map.h"

#include <array>
#include <cmath>
#include <optional>

namespace bouguer {

Vec3 tangent_space_normal(const Vec3& rgb, double scale) {
  return normalize(Vec3{(2.0 * rgb.x - 1.0) * scale, (2.0 * rgb.y - 1.0) * scale, 2.0 * rgb.z - 1.0});
}

namespace {

// The tangent frame (T, B) around unit n from the mesh's vertex tangents (glTF's TANGENT),
// interpolated at the hit: T by Gram–Schmidt against n, B = sign · n × T. The sign is the
// interpolated one's (a triangle whose corners disagree, at a mirrored seam, takes the majority's).
// nullopt where the interpolated tangent lies along n.
std::optional<std::array<Vec3, 2>> vertex_frame(const Mesh& mesh, const Hit& hit, const Vec3& n) {
  const auto& tri = mesh.triangles[hit.primitive];
  const double b1 = hit.barycentric[0], b2 = hit.barycentric[1], b0 = 1.0 - b1 - b2;
  const Tangent &t0 = mesh.tangents[tri[0]], &t1 = mesh.tangents[tri[1]], &t2 = mesh.tangents[tri[2]];
  const Vec3 t = t0.direction * b0 + t1.direction * b1 + t2.direction * b2;
  const Vec3 t_raw = t - n * dot(n, t);
  if (!(length(t_raw) > 1e-12)) return std::nullopt;
  const Vec3 tangent = normalize(t_raw);
  const double sign = t0.sign * b0 + t1.sign * b1 + t2.sign * b2 < 0.0 ? -1.0 : 1.0;
  return std::array<Vec3, 2>{tangent, cross(n, tangent) * sign};
}

// The tangent frame (T, B) around unit n from the triangle's positions and texture coordinates (as
// texture `texture` reads them: its transform applied): T = ∂p/∂u and B = ∂p/∂v, Gram–Schmidt
// against n; B keeps the side the UVs give it. nullopt where the UVs are degenerate.
std::optional<std::array<Vec3, 2>> uv_frame(const TextureTable& table, int texture, const Mesh& mesh, const Hit& hit,
                                            const Vec3& n) {
  const auto& tri = mesh.triangles[hit.primitive];
  const auto a = texture_coordinates(table, texture, mesh.uvs[tri[0]]);
  const auto b = texture_coordinates(table, texture, mesh.uvs[tri[1]]);
  const auto c = texture_coordinates(table, texture, mesh.uvs[tri[2]]);
  const Vec3 dp1 = mesh.positions[tri[1]] - mesh.positions[tri[0]], dp2 = mesh.positions[tri[2]] - mesh.positions[tri[0]];
  const double du1 = b[0] - a[0], dv1 = b[1] - a[1], du2 = c[0] - a[0], dv2 = c[1] - a[1];
  const double det = du1 * dv2 - du2 * dv1;
  if (!(std::abs(det) > 1e-20)) return std::nullopt;
  const Vec3 dpdu = (dp1 * dv2 - dp2 * dv1) / det, dpdv = (dp2 * du1 - dp1 * du2) / det;
  const Vec3 t_raw = dpdu - n * dot(n, dpdu);
  if (!(length(t_raw) > 0.0)) return std::nullopt;
  const Vec3 t = normalize(t_raw);
  const Vec3 b_raw = dpdv - n * dot(n, dpdv) - t * dot(t, dpdv);
  const Vec3 bt = length(b_raw) > 0.0 ? normalize(b_raw) : cross(n, t) * (dot(cross(n, t), dpdv) < 0.0 ? -1.0 : 1.0);
  return std::array<Vec3, 2>{t, bt};
}

}  // namespace

Vec3 mapped_normal(const TextureTable& table, int texture, double scale, const Mesh& mesh, const Hit& hit) {
  const Vec3 n = hit.shading_normal;
  if (mesh.uvs.empty() || hit.primitive >= mesh.triangles.size()) return n;
  const auto frame = mesh.tangents.empty() ? uv_frame(table, texture, mesh, hit, n) : vertex_frame(mesh, hit, n);
  if (!frame) return n;
  const auto& [t, bt] = *frame;
  const Vec3 local = tangent_space_normal(texture_rgb(table, texel_blend(table, texture, hit.uv, 0.0)), scale);
  const Vec3 mapped = normalize(t * local.x + bt * local.y + n * local.z);
  if (!(dot(mapped, hit.normal) > 0.0)) return n;
  return mapped;
}

}  // namespace bouguer
