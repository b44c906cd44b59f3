#pragma once
// What a path does at a surface it meets, one function each: the surface as the nested objects
// the path is inside see it (surface_seen, inside_towards), the medium it arrived through, the
// crossing of an index-matched boundary (no vertex), the choice of one wavelength at a dispersive
// interface, and the continuation from a surface event (BSDF sampling and Russian roulette).
// Contract: each function reads the scene and changes only the path state it is handed.
#include "bouguer/integrators/media_travel.h"
#include "bouguer/integrators/surface_assembly.h"
#include "bouguer/render/path_guide.h"

namespace bouguer {

// The surface a path inside the nested objects `inside` meets at `hit` (surface_assembly.h:
// SurfaceSeen): the scene's, or for a surface of a nested object the media on its two sides that
// the set gives (scene/nested.h), index-matched where they match (a false intersection: the same
// medium on both sides), so that it is crossed without a vertex, shadow rays included.
inline SurfaceSeen surface_seen(const RenderScene& scene, const Hit& hit, InsideSet inside) {
  const Surface& s = scene.surfaces[hit.geometry];
  if (s.nested < 0) return s;
  const NestedSides sides = nested_sides(scene.nested, s.nested, inside);
  return {s, sides.front, sides.behind, indices_match(scene, sides.front, sides.behind)};
}

// The set of a path that leaves the surface at `hit` along d: changed only at a nested object's.
inline InsideSet inside_towards(const RenderScene& scene, const Hit& hit, InsideSet inside, const Vec3& d) {
  const int k = scene.surfaces[hit.geometry].nested;
  return k < 0 ? inside : inside_after(inside, k, dot(d, hit.normal));
}

// The medium a ray that hits `surface` has travelled through: crossing an interface, the one on
// the side it arrives from; else the path's current one.
inline int medium_arrived_through(const SurfaceSeen& seen, const Ray& ray, const Hit& hit, int medium) {
  if (seen.surface.kind != SurfaceKind::interface) return medium;
  return dot(ray.direction, hit.normal) < 0.0 ? seen.medium_front : seen.medium_behind;
}

// A path at an index-matched interface (Surface::index_matched) crosses it unchanged: the medium
// beyond, a new segment from the hit point, the ray from its offset origin. It is no vertex
// (connections cross it too). False once a path has crossed kMaxCrossings.
inline bool cross_index_matched(const SurfaceSeen& seen, const Hit& hit, int& crossings, int& medium, Vec3& start,
                                Ray& ray) {
  if (++crossings > kMaxCrossings) return false;
  medium = dot(ray.direction, hit.normal) > 0.0 ? seen.medium_front : seen.medium_behind;
  start = hit.point;
  ray.origin = offset_ray_origin(hit, ray.direction);
  return true;
}

// What advance_to_surface stopped at: the first surface that is not index-matched (its hit and
// how the ray's nested set sees it), the ray leaving the scene, one crossing more than
// kMaxCrossings, or a stop its caller asked for.
struct RayStop {
  enum class At : std::uint8_t { surface, escape, crossings_exhausted, halted };
  At at = At::halted;
  std::optional<Hit> hit;
  std::optional<SurfaceSeen> seen;
};

// The one loop that carries a ray through index-matched boundaries, for the walk, for connections
// (transmission) and for the exit guide (carry_to_environment): intersect, the surface as the
// ray's nested set sees it, the segment just travelled, and where the surface is index-matched
// its crossing without a vertex (cross_index_matched), then again. before_ray() -> bool is asked
// before each ray is cast (false: halt, no ray); segment(hit, seen) -> bool is handed each segment
// once its end is known, before any crossing there (hit and seen null: the ray left the scene;
// seg.start, seg.medium: where it began and the medium it travelled in), and false halts there.
// `seg` is left at the last segment's start; a caller that changes seg.ray.t_max in segment()
// bounds the next ray.
template <typename BeforeRay, typename Segment>
RayStop advance_to_surface(const RenderScene& scene, RaySegment& seg, std::uint64_t& rays, BeforeRay before_ray,
                           Segment segment) {
  for (;;) {
    if (!before_ray()) return {};
    ++rays;
    const auto hit = scene.rays.intersect(seg.ray);
    if (!hit) return segment(nullptr, nullptr) ? RayStop{RayStop::At::escape, {}, {}} : RayStop{};
    const SurfaceSeen seen = surface_seen(scene, *hit, seg.inside);
    if (!segment(&*hit, &seen)) return {};
    if (!seen.index_matched) return {RayStop::At::surface, hit, seen};
    seg.inside = inside_towards(scene, *hit, seg.inside, seg.ray.direction);
    if (!cross_index_matched(seen, *hit, seg.crossings, seg.medium, seg.start, seg.ray))
      return {RayStop::At::crossings_exhausted, hit, seen};
  }
}
// The same with no question before each ray.
template <typename Segment>
RayStop advance_to_surface(const RenderScene& scene, RaySegment& seg, std::uint64_t& rays, Segment segment) {
  return advance_to_surface(scene, seg, rays, [] { return true; }, segment);
}

// Whether a path crossing `surface` splits the wavelengths: an interface with a medium whose index
// varies with wavelength on either side.
inline bool is_dispersive(const RenderScene& scene, const SurfaceSeen& seen) {
  if (seen.surface.kind != SurfaceKind::interface) return false;
  return scene.media[static_cast<std::size_t>(seen.medium_front)].dispersive ||
         scene.media[static_cast<std::size_t>(seen.medium_behind)].dispersive;
}

// At the first dispersive interface a path meets, keep carried wavelength j = ⌊u·N⌋ with weight
// N and terminate the others (their throughput becomes 0): each wavelength's expected
// contribution is unchanged. Returns whether it happened.
template <std::size_t N>
bool keep_one_wavelength(const SceneView<N>& v, const SurfaceSeen& seen, SampledWavelengths<N>& w,
                         SampledSpectrum<N>& beta, double u, Rng& rng);

// Terminates all carried wavelengths but j = ⌊u·N⌋ (its value within its bin drawn in full mode)
// and returns j; the caller weighs what it carries by N.
template <std::size_t N>
int keep_wavelength(const SceneView<N>& v, SampledWavelengths<N>& w, double u, Rng& rng);

// A path's next step from a surface event: wi drawn from the BSDF in the path's transport mode
// (with a guide, from the mixture of the guide and the BSDF, render/path_guide.h, and weighted by
// the mixture's density), path.beta multiplied by its weight, path.medium the one wi travels in,
// path.ray the next ray from the hit, Russian roulette (`depth`: the path's events so far).
// Returns the BSDF's own density of wi (0: specular; the MIS weights read it, guided or not:
// integrators/guiding.h), or nullopt when the path ends. A guided vertex draws one number more.
template <std::size_t N>
std::optional<double> continue_path(const RenderScene& scene, const Hit& hit, const SurfaceEvent<N>& e,
                                    const Vec3& wo, TransportMode mode, int depth, PathHead<N>& path, Rng& rng,
                                    RouletteReading roulette = {}, const DirectionGuide& guide = {}) {
  const bool from_guide = guide && rng.next_double() < guide.alpha;
  const double uc = rng.next_double(), u1 = rng.next_double(), u2 = rng.next_double();
  std::optional<BsdfSampleN<N>> s;
  if (from_guide) {
    const Vec3 wi = guide.tree->sample(uc, u1, u2);
    const double pdf = e.pdf(wo, wi);
    const double mixture = guide.mixture_pdf(pdf, wi);
    const SampledSpectrum<N> f = e.eval(wo, wi, mode);
    if (!(pdf > 0.0) || f.is_zero()) return std::nullopt;
    s = BsdfSampleN<N>{wi, f * static_cast<float>(1.0 / mixture), pdf, dot(wi, e.ng) * dot(wo, e.ng) < 0.0};
  } else {
    s = e.sample(wo, uc, u1, u2, mode);
    if (!s) return std::nullopt;
    if (guide && s->pdf > 0.0) s->weight *= static_cast<float>(s->pdf / guide.mixture_pdf(s->pdf, s->wi));
  }
  const Vec3 wi = s->wi;
  path.beta *= s->weight;
  path.medium = e.medium_towards(wi);
  if (!survives_roulette(scene, depth, path.medium, path.beta, rng, roulette.divisor,
                         roulette_scale(scene, path.medium, mode), roulette.single) ||
      path.beta.is_zero())
    return std::nullopt;
  path.ray = {offset_ray_origin(hit, wi), wi};
  return s->pdf;
}

}  // namespace bouguer
