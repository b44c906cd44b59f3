#pragma once
// A light path's specular prefix: from a point, spot or distant lamp to its first vertex that is
// not specular, and whether next-event estimation at that vertex makes the path (manifold.h:
// next_event_makes). Two strategies that splat light through glass to the camera ask it, each to
// count only what its estimator's other strategies do not make: the path tracer's light paths
// (light.cpp, render.light_paths) and bdpt's light through glass to the camera
// (bidirectional.h: Bdpt::through_glass_to_camera).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <variant>

#include "bouguer/integrators/manifold.h"
#include "bouguer/integrators/walk.h"

namespace bouguer {

// What the prefix says of a light path, vertex by vertex.
enum class PrefixVerdict {
  specular,        // a specular vertex: the prefix goes on
  made,            // next-event estimation at the first non-specular vertex makes the path (or it
                   // is left out: below)
  beyond,          // it does not: the path is the light path's own
};

// The prefix of a light path from lamp `lamp`: feed it the path's vertices in order (not the
// lamp's own) until it says made or beyond. At the first vertex that is not specular: no crossing
// before it, made (the straight shadow ray's); a reflection anywhere before it, beyond (next-event
// estimation solves refractions only); otherwise as next_event_makes answers, with f read with the
// light's own direction for the camera's, which zeroes it on the same side for a surface that only
// reflects, its shading normal's or its own. A vertex on a rough interface counts as made: its f,
// zero where the half vector of a refraction is not valid, next-event estimation reads with the
// camera's side, which a light path does not know there (such light stays missing, said in
// rendering.md).
// A distant lamp's (`sun`) path is measured from its first vertex; how far that lies from where
// its light subpath started (`previous`, on the disk across the scene it draws its rays from) is
// `start_m`, whose float rounding next_event_makes allows for (made_within_m).
template <std::size_t N>
struct LightPrefix {
  manifold_detail::DeltaLamp lamp;
  const DistantLight* sun = nullptr;
  Vec3 previous = lamp.p;
  bool after_specular = false, reflected = false;
  int crossings = 0;
  double path_m = 0.0, start_m = -1.0;
  Vec3 nearest_lamp = {}, specular_normal = {}, specular_wo = {};

  PrefixVerdict add(const SceneView<N>& v, const Vertex<N>& x, const SampledWavelengths<N>& w, std::uint64_t& rays) {
    if (sun && start_m < 0.0)
      start_m = length(x.point - previous);
    else
      path_m += length(x.point - previous);
    previous = x.point;
    if (after_specular) {
      const bool same_side = (dot(specular_wo, specular_normal) > 0.0) == (dot(-x.wo, specular_normal) > 0.0);
      reflected = reflected || same_side;
      crossings += !same_side;
    }
    if (x.kind == VertexKind::surface && x.delta) {
      if (!after_specular) nearest_lamp = x.point;
      after_specular = true;
      specular_normal = x.normal;
      specular_wo = x.wo;
      return PrefixVerdict::specular;
    }
    if (reflected) return PrefixVerdict::beyond;
    if (x.kind == VertexKind::surface && std::holds_alternative<RoughDielectric>(x.event.bsdf))
      return PrefixVerdict::made;
    auto towards = [&](const Vec3& wi, double& pdf) {
      pdf = vertex_pdf(v.scene, x, x.wo, wi);
      return vertex_f(v.scene, x, x.wo, wi, TransportMode::radiance);
    };
    auto medium_towards = [&](const Vec3& wi) { return vertex_medium_towards(x, wi); };
    return next_event_makes(v, vertex_at(x), lamp, sun, nearest_lamp, path_m, std::max(start_m, 0.0), crossings,
                            towards, medium_towards, w, rays)
               ? PrefixVerdict::made
               : PrefixVerdict::beyond;
  }
};

// The prefix of a light path from `light` (its light subpath's first vertex `start`): a point, spot
// or distant lamp; nothing for others.
template <std::size_t N>
std::optional<LightPrefix<N>> light_prefix(const Light& light, const Vec3& start) {
  if (const auto* sun = std::get_if<DistantLight>(&light)) return LightPrefix<N>{.lamp = {}, .sun = sun, .previous = start};
  if (const auto lamp = manifold_detail::delta_lamp(light)) return LightPrefix<N>{.lamp = *lamp};
  return std::nullopt;
}

}  // namespace bouguer
