#pragma once
// Normal maps: the shading normal a tangent-space normal texture gives at a hit. One function,
// applied in one place (where integrators/events.h enters surface_event, on a copy of the hit), so
// every estimator sees the same perturbed `Hit::shading_normal`; how the BSDF frame uses it is the
// events' business, not this file's.
//
// Convention (glTF's, and OpenGL's): a texel (r, g, b) in [0, 1] is the tangent-space normal
// (2r − 1, 2g − 1, 2b − 1), +x along increasing u (the image's right), +y along increasing v (the
// image's up: Bouguer's v runs up, scene/texture.h), +z the interpolated shading normal; `scale`
// multiplies x and y before normalising (glTF's normalTexture.scale).
//
// Tangents: a mesh's own vertex tangents where it has them (glTF's TANGENT, Mesh::tangents):
// interpolated with the hit's barycentrics, made orthogonal to the shading normal N by
// Gram–Schmidt, and B = w · N × T with the vertices' handedness w (glTF's definition). They are
// used as given: a KHR_texture_transform rotation does not turn them (glTF's asset is expected to
// carry tangents for its texture coordinates as the image reads them).
// Otherwise per triangle, from its positions and texture coordinates (after the texture's own
// transform): T = ∂p/∂u and B = ∂p/∂v, made orthonormal to the shading normal by Gram–Schmidt. B is
// taken from the UVs, not as N × T, so mirrored UV islands keep their handedness. glTF asks for
// MikkTSpace tangents when an asset brings none (per-vertex, averaged over the triangles that share
// a vertex); per-triangle gradients equal them wherever the UV mapping is affine across
// neighbouring triangles (a quad, a cylinder's unwrapped side) and differ by the averaging at
// vertices where it is not.
#include "bouguer/core/math.h"
#include "bouguer/geometry/mesh.h"
#include "bouguer/geometry/ray_scene.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/texture.h"

namespace bouguer {

// The unit tangent-space normal of texel value `rgb` with glTF's `scale` on x and y.
Vec3 tangent_space_normal(const Vec3& rgb, double scale);

// The shading normal that normal texture `texture` (scale `scale`) gives at `hit` on triangle
// hit.primitive of `mesh`: the tangent-space normal at hit.uv (finest level, bilinear) in the
// tangent frame around hit.shading_normal (the vertex tangents', or the triangle's UVs').
// hit.shading_normal itself where the frame is degenerate (UVs, or a tangent along the normal) or
// the mapped normal would not lie on the geometric normal's side.
Vec3 mapped_normal(const TextureTable& table, int texture, double scale, const Mesh& mesh, const Hit& hit);

// The hit with its shading normal from the surface's normal map (Surface::normal_map), or as it is.
inline Hit normal_mapped(const RenderScene& s, const Surface& surface, const Hit& hit) {
  if (surface.normal_map < 0) return hit;
  Hit mapped = hit;
  mapped.shading_normal = mapped_normal(s.textures, surface.normal_map, surface.normal_scale, s.rays.mesh(hit.geometry), hit);
  return mapped;
}

}  // namespace bouguer
