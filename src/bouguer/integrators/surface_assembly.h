#pragma once
// The surface assembly: a hit on a surface as a BSDF in its shading frame, with the media on its
// two sides (SurfaceEvent, surface_event): the material's textures read at the hit's UV at the
// ray cone's level, the normal map applied, the interface's indices for the path's wavelengths.
// Contract: the same hit, wavelengths and cone give the same SurfaceEvent; nothing else is read.
#include "bouguer/integrators/scene_view.h"
#include "bouguer/scene/normal_map.h"

namespace bouguer {

// A surface hit as a BSDF in its shading frame. Opaque surfaces are two-sided: both normals face
// wo. Interfaces keep the geometric normal's side, so z > 0 is the medium_front side.
//
// Shading normals (docs/rendering.md "Shading normals"), treated as pbrt-v3 does. The BSDF is
// evaluated and sampled in the frame of the hit's shading normal; the geometric normal `ng` alone
// says which side a direction is on, so it decides the medium a direction travels in and whether
// wo → wi is a reflection or a transmission. A pair on which the two frames disagree (a reflection
// through the geometric surface, a refraction that stays on its side, a wo behind the shading
// normal) carries nothing, and a sample that draws one ends the path: no light leaks through a
// surface without changing media. In importance mode the verbs include Veach's adjoint correction
// |wo·ns||wi·ng| / (|wo·ng||wi·ns|), which makes the light paths' BSDF the adjoint of the camera
// paths' (Veach's thesis, §5.3), so every estimator sums the same integral.
template <std::size_t N>
struct SurfaceEvent {
  Frame frame;  // z: the shading normal
  Bsdf<N> bsdf;
  int medium_front = -1, medium_behind = -1;
  InsideSet inside = 0;  // the nested objects the path was inside as it arrived (scene/nested.h)
  Vec3 ng = frame.n;     // the geometric normal, on the side of frame.n

  // The medium a direction leaving the surface travels in.
  int medium_towards(const Vec3& wi) const { return dot(wi, ng) > 0.0 ? medium_front : medium_behind; }
  bool shaded() const { return !(frame.n == ng); }

  // f(wo, wi)·|cos θi| (with the adjoint correction in importance mode), world directions.
  SampledSpectrum<N> eval(const Vec3& wo, const Vec3& wi, TransportMode mode) const {
    const Vec3 lo = frame.to_local(wo), li = frame.to_local(wi);
    if (!shaded()) return bouguer::eval(bsdf, lo, li, mode);
    if (!sides_agree(wo, wi, lo, li)) return {};
    return bouguer::eval(bsdf, lo, li, mode) * correction(wo, wi, lo, li, mode);
  }
  // The solid-angle density of drawing wi from wo (the shading frame's).
  double pdf(const Vec3& wo, const Vec3& wi) const { return bouguer::pdf(bsdf, frame.to_local(wo), frame.to_local(wi)); }
  // A direction drawn from wo, in world coordinates; nullopt where the two frames disagree on it.
  std::optional<BsdfSampleN<N>> sample(const Vec3& wo, double uc, double u1, double u2, TransportMode mode) const {
    const Vec3 lo = frame.to_local(wo);
    auto s = bouguer::sample(bsdf, lo, uc, u1, u2, mode);
    if (!s) return s;
    const Vec3 li = s->wi;
    s->wi = frame.to_world(li);
    if (shaded()) {
      if (!sides_agree(wo, s->wi, lo, li)) return std::nullopt;
      s->weight *= correction(wo, s->wi, lo, li, mode);
    }
    return s;
  }

 private:
  bool sides_agree(const Vec3& wo, const Vec3& wi, const Vec3& lo, const Vec3& li) const {
    return (dot(wo, ng) * dot(wi, ng) > 0.0) == (lo.z * li.z > 0.0);
  }
  float correction(const Vec3& wo, const Vec3& wi, const Vec3& lo, const Vec3& li, TransportMode mode) const {
    if (mode == TransportMode::radiance) return 1.0f;
    const double den = std::abs(dot(wo, ng)) * std::abs(li.z);
    return den > 0.0 ? static_cast<float>(std::abs(lo.z) * std::abs(dot(wi, ng)) / den) : 0.0f;
  }
};

// A surface as a path sees it: the scene's surface (its kind, material, roughness, lights) and
// what the path learns where it meets it, the media on its two sides and whether they match
// (index-matched: crossed without a vertex). For a nested object's surface they depend on the
// objects the path is inside (surface_events.h: surface_seen); for any other they are its own,
// so a Surface is seen as itself. A view: no copy of the Surface.
struct SurfaceSeen {
  const Surface& surface;
  int medium_front = -1, medium_behind = -1;
  bool index_matched = false;

  SurfaceSeen(const Surface& s)  // (implicit: a surface without nesting is seen as it is)
      : surface(s), medium_front(s.medium_front), medium_behind(s.medium_behind), index_matched(s.index_matched) {}
  SurfaceSeen(const Surface& s, int front, int behind, bool matched)
      : surface(s), medium_front(front), medium_behind(behind), index_matched(matched) {}
};

// `medium` is the one the path arrived through (the medium around an opaque surface).
// `cone_width_m`: the width at the hit of the ray cone the path carries (scene/texture.h), which
// chooses the textures' MIP level; 0 reads their finest level.
template <std::size_t N>
SurfaceEvent<N> surface_event(const SceneView<N>& v, const Hit& hit, const SurfaceSeen& seen, const Vec3& wo,
                              int medium, const SampledWavelengths<N>& w, double cone_width_m = 0.0);

// The indices on the two sides of an interface, as the path sees them (reference or kept wavelength).
template <std::size_t N>
inline SmoothDielectric interface_indices(const SceneView<N>& v, const SurfaceSeen& seen, const SampledWavelengths<N>& w) {
  auto eta_of = [&](int m) { return eta(v.scene.media[static_cast<std::size_t>(m)], v.tables, w); };
  return {eta_of(seen.medium_front), eta_of(seen.medium_behind)};
}

// The texels of texture `id` at the hit's UV, at the level the ray cone chooses (the finest without one).
inline TexelBlend texels_at(const RenderScene& s, int id, const Hit& hit, const Vec3& wo, double cone_width_m) {
  const double cos_theta = dot(wo, hit.normal);
  const AnalyticShape* analytic = s.rays.analytic(hit.geometry);
  const double lod = analytic ? texture_level_of_detail(s.textures, id, *analytic, hit.primitive, hit.uv, cone_width_m,
                                                        cos_theta)
                              : texture_level_of_detail(s.textures, id, s.rays.mesh(hit.geometry), hit.primitive,
                                                        cone_width_m, cos_theta);
  return texel_blend(s.textures, id, hit.uv, lod);
}

// A reflectance at the hit: spectrum `spectrum`, or reflectance texture `texture` (≥ 0) at the hit's UV.
template <std::size_t N>
inline SampledSpectrum<N> reflectance_at(const SceneView<N>& v, int spectrum, int texture, const Hit& hit,
                                         const Vec3& wo, const SampledWavelengths<N>& w, double cone_width_m) {
  if (texture < 0) return v.tables.at(spectrum, w);
  return texture_reflectance(v.scene.textures, texels_at(v.scene, texture, hit, wo, cone_width_m), w);
}

// An opaque surface's material at the hit as a BSDF, its textures read at the hit's UV; `medium`
// is the one around it.
template <std::size_t N>
inline Bsdf<N> opaque_bsdf(const SceneView<N>& v, const SurfaceMaterial& m, const Hit& hit, const Vec3& wo, int medium,
                           const SampledWavelengths<N>& w, double cone_width_m) {
  const RenderScene& s = v.scene;
  if (const auto* d = std::get_if<DiffuseMaterial>(&m))
    return DiffuseReflection<N>{reflectance_at(v, d->reflectance, d->reflectance_texture, hit, wo, w, cone_width_m)};
  if (const auto* t = std::get_if<ThinDielectricMaterial>(&m))
    return ThinDielectric<N>{t->ior / eta(s.media[static_cast<std::size_t>(medium)], v.tables, w),
                             reflectance_at(v, t->tint, t->tint_texture, hit, wo, w, cone_width_m)};
  if (const auto* g = std::get_if<MetallicRoughnessMaterial>(&m)) {
    double metalness = g->metalness, roughness = g->roughness;
    if (g->metallic_roughness_texture >= 0) {
      const Vec3 t = texture_rgb(s.textures, texels_at(s, g->metallic_roughness_texture, hit, wo, cone_width_m));
      metalness = std::clamp(t.z, 0.0, 1.0);
      roughness = std::clamp(t.y, 0.0, 1.0);
    }
    return MetallicRoughness<N>{reflectance_at(v, g->base_colour, g->base_colour_texture, hit, wo, w, cone_width_m),
                                metalness, std::max(roughness * roughness, kMinMetallicRoughnessAlpha)};
  }
  const auto& c = std::get<ConductorMaterial>(m);
  double alpha = c.alpha;
  if (c.alpha_texture >= 0) {
    const Vec3 t = texture_rgb(s.textures, texels_at(s, c.alpha_texture, hit, wo, cone_width_m));
    alpha = std::clamp((t.x + t.y + t.z) / 3.0, 0.0, 1.0);
  }
  return ConductorReflection<N>{v.tables.at(c.n, w), v.tables.at(c.k, w),
                                eta(s.media[static_cast<std::size_t>(medium)], v.tables, w), alpha};
}

template <std::size_t N>
inline SurfaceEvent<N> surface_event(const SceneView<N>& v, const Hit& geometric_hit, const SurfaceSeen& seen,
                                     const Vec3& wo, int medium, const SampledWavelengths<N>& w, double cone_width_m) {
  const Surface& surface = seen.surface;
  const Hit hit = normal_mapped(v.scene, surface, geometric_hit);  // its shading normal from a normal map
  const RenderScene& s = v.scene;
  const Vec3& ns = hit.shading_normal;
  if (surface.kind == SurfaceKind::opaque) {
    const double side = dot(wo, hit.normal) > 0.0 ? 1.0 : -1.0;
    const Frame frame(ns * side);
    const Vec3 ng = hit.normal * side;
    const SurfaceMaterial& m = s.materials[static_cast<std::size_t>(surface.material)];
    return {frame, opaque_bsdf(v, m, hit, wo, medium, w, cone_width_m), medium, medium, 0, ng};
  }
  const SmoothDielectric indices = interface_indices(v, seen, w);
  const Frame frame(ns);
  if (surface.roughness == 0.0) return {frame, indices, seen.medium_front, seen.medium_behind, 0, hit.normal};
  const RoughDielectricBsdf lobe{{surface.roughness}, indices.eta_front, indices.eta_behind,
                                 &s.dielectric_albedo[static_cast<std::size_t>(surface.albedo)]};
  return {frame, RoughDielectric{lobe}, seen.medium_front, seen.medium_behind, 0, hit.normal};
}

}  // namespace bouguer
