#pragma once
// What a path does at a surface it meets, one function each: the surface as the nested objects
// the path is inside see it (surface_seen, inside_towards), the medium it arrived through, the
// crossing of an index-matched boundary (no vertex), the choice of one wavelength at a dispersive
// interface, and the continuation from a surface event (BSDF sampling and Russian roulette).
// Contract: each function reads the scene and changes only the path state it is handed.
#include "bouguer/integrators/media_travel.h"
#include "bouguer/integrators/surface_assembly.h"

namespace bouguer {

// The surface a path inside the nested objects `inside` meets at `hit`: the scene's, or for a
// surface of a nested object a copy in `scratch` with the media on its two sides that the set
// gives (scene/nested.h), index-matched where they match (a false intersection: the same medium on
// both sides), so that it is crossed without a vertex, shadow rays included.
inline const Surface& surface_seen(const RenderScene& scene, const Hit& hit, InsideSet inside, Surface& scratch) {
  const Surface& s = scene.surfaces[hit.geometry];
  if (s.nested < 0) return s;
  const NestedSides sides = nested_sides(scene.nested, s.nested, inside);
  scratch = s;
  scratch.medium_front = sides.front;
  scratch.medium_behind = sides.behind;
  scratch.index_matched = indices_match(scene, sides.front, sides.behind);
  return scratch;
}

// The set of a path that leaves the surface at `hit` along d: changed only at a nested object's.
inline InsideSet inside_towards(const RenderScene& scene, const Hit& hit, InsideSet inside, const Vec3& d) {
  const int k = scene.surfaces[hit.geometry].nested;
  return k < 0 ? inside : inside_after(inside, k, dot(d, hit.normal));
}

// The medium a ray that hits `surface` has travelled through: crossing an interface, the one on
// the side it arrives from; else the path's current one.
inline int medium_arrived_through(const Surface& surface, const Ray& ray, const Hit& hit, int medium) {
  if (surface.kind != SurfaceKind::interface) return medium;
  return dot(ray.direction, hit.normal) < 0.0 ? surface.medium_front : surface.medium_behind;
}

// A path at an index-matched interface (Surface::index_matched) crosses it unchanged: the medium
// beyond, a new segment from the hit point, the ray from its offset origin. It is no vertex
// (connections cross it too). False once a path has crossed kMaxCrossings.
inline bool cross_index_matched(const Surface& surface, const Hit& hit, int& crossings, int& medium, Vec3& start,
                                Ray& ray) {
  if (++crossings > kMaxCrossings) return false;
  medium = dot(ray.direction, hit.normal) > 0.0 ? surface.medium_front : surface.medium_behind;
  start = hit.point;
  ray.origin = offset_ray_origin(hit, ray.direction);
  return true;
}

// Whether a path crossing `surface` splits the wavelengths: an interface with a medium whose index
// varies with wavelength on either side.
inline bool is_dispersive(const RenderScene& scene, const Surface& surface) {
  if (surface.kind != SurfaceKind::interface) return false;
  return scene.media[static_cast<std::size_t>(surface.medium_front)].dispersive ||
         scene.media[static_cast<std::size_t>(surface.medium_behind)].dispersive;
}

// At the first dispersive interface a path meets, keep carried wavelength j = ⌊u·N⌋ with weight
// N and terminate the others (their throughput becomes 0): each wavelength's expected
// contribution is unchanged. Returns whether it happened.
template <std::size_t N>
bool keep_one_wavelength(const SceneView<N>& v, const Surface& surface, SampledWavelengths<N>& w,
                         SampledSpectrum<N>& beta, double u, Rng& rng);

// Terminates all carried wavelengths but j = ⌊u·N⌋ (its value within its bin drawn in full mode)
// and returns j; the caller weighs what it carries by N.
template <std::size_t N>
int keep_wavelength(const SceneView<N>& v, SampledWavelengths<N>& w, double u, Rng& rng);

// A path's next step from a surface event: wi drawn from the BSDF in the path's transport mode,
// beta multiplied by its weight, the medium wi travels in, the next ray from the hit, Russian
// roulette (`single` as survives_roulette's). Returns the sample's pdf (0: specular), or nullopt
// when the path ends.
template <std::size_t N>
std::optional<double> continue_path(const RenderScene& scene, const Hit& hit, const SurfaceEvent<N>& e,
                                    const Vec3& wo, TransportMode mode, int depth, SampledSpectrum<N>& beta,
                                    int& medium, Ray& ray, Rng& rng, float mean_ratio = 1.0f, int single = -1) {
  const double uc = rng.next_double(), u1 = rng.next_double(), u2 = rng.next_double();
  const auto s = e.sample(wo, uc, u1, u2, mode);
  if (!s) return std::nullopt;
  const Vec3 wi = s->wi;
  beta *= s->weight;
  medium = e.medium_towards(wi);
  if (!survives_roulette(scene, depth, medium, beta, rng, mean_ratio, roulette_scale(scene, medium, mode), single) ||
      beta.is_zero())
    return std::nullopt;
  ray = {offset_ray_origin(hit, wi), wi};
  return s->pdf;
}

}  // namespace bouguer
