#pragma once
// Connections and next-event estimation: the transmission along a connection (across
// index-matched boundaries, stopped by any other surface, ratio-tracked through scattering media),
// direct light at a surface or a medium vertex weighted against the vertex's own sampling, and the
// MIS arithmetic they share with the estimators (the power heuristic over the spectral mixtures'
// densities). Contract: a connection's value is its contribution divided by its own density; its
// weights with the strategies it is combined with sum to 1.
#include "bouguer/integrators/exit_guide.h"
#include "bouguer/integrators/surface_events.h"

namespace bouguer {

double power_heuristic(double pdf_a, double pdf_b);

// The mean of a path's ratios, which its contributions are divided by (1 without scattering media,
// where the ratios are not read); with `connection`, of the path's ratios times a connection's.
template <std::size_t N>
float mean_ratio(const RenderScene& scene, const SampledSpectrum<N>& r) {
  return scene.scatters ? r.average() : 1.0f;
}
template <std::size_t N>
float mean_ratio(const RenderScene& scene, const SampledSpectrum<N>& r, const SampledSpectrum<N>& connection) {
  return scene.scatters ? (r * connection).average() : 1.0f;
}

// The MIS weight (power heuristic) of a strategy with density pdf_a and ratios r_a against one
// with pdf_b and r_b: the densities of the two one-sample mixtures over the carried wavelengths.
template <std::size_t N>
double spectral_power_heuristic(const RenderScene& scene, double pdf_a, const SampledSpectrum<N>& r_a, double pdf_b,
                                const SampledSpectrum<N>& r_b) {
  return power_heuristic(pdf_a * mean_ratio(scene, r_a), pdf_b * mean_ratio(scene, r_b));
}

// Solid-angle density with which next-event estimation at `from` reaches this emitter hit (for
// MIS), and the one for a direction that escapes to the environment map.
double area_light_pdf(const RenderScene& scene, const Hit& hit, const Vec3& from, const Vec3& wi);
// `lobe`: the map's lobe next-event estimation drew from there (environment_lobe), −1 the map's own.
double environment_pdf(const RenderScene& scene, const Vec3& d, int lobe = -1);

// Where a connection (to a light or the camera) starts: a surface hit, whose rays leave from its
// offset origin while lengths are measured from the hit point itself, or a point inside a medium.
struct PathVertex {
  Vec3 point;
  const Hit* hit = nullptr;  // null: a point inside a medium
  InsideSet inside = 0;      // the nested objects the path was inside there (at a surface: as it arrived)
  Vec3 origin_towards(const Vec3& d) const { return hit ? offset_ray_origin(*hit, d) : point; }
};

// What gets through along a connection: the transmittance (ratio-tracked in scattering media,
// exact elsewhere) and the connection's factors of the spectral MIS ratios (media/scattering.h).
template <std::size_t N>
struct Transmission {
  SampledSpectrum<N> tr = SampledSpectrum<N>::constant(1.0f);
  SpectralMis<N> ratios;
  double tau = 0.0;  // with sigma_mean given: Σ σ̄_s·∫ρ over the scattering media crossed (integrators/walk.h)
};

// The connection from `from` along wi to a point distance_m away (infinite: a distant light or
// the environment), starting in `medium`: nullopt when a surface blocks it. It crosses
// index-matched interfaces (Surface::index_matched: medium boundaries that neither reflect nor
// refract) into the medium beyond and stops at any other surface, glass included; so a medium
// inside glass or behind a water surface gets no direct light (docs/rendering.md). Surfaces of
// nested objects are seen as the path would see them (surface_seen), from the set `from.inside`.
// With `sigma_mean` (σ̄_s by medium), it also sums the segment's mean scattering optical depth for
// the MIS weights of the bidirectional estimators (Tungsten's generalised shadow ray with pdfs).
// With `by_smooth_interface`, it also says whether what blocked it was a smooth interface (glass,
// a liquid's surface: smooth_glass_seen): what next-event estimation through the interfaces may go
// on through; with `blocker`, where it was blocked.
template <std::size_t N>
std::optional<Transmission<N>> transmission(const SceneView<N>& v, const PathVertex& from, const Vec3& wi,
                                            double distance_m, int medium, const SampledWavelengths<N>& w, Rng& rng,
                                            std::uint64_t& rays, std::span<const double> sigma_mean = {},
                                            bool* by_smooth_interface = nullptr, Hit* blocker = nullptr);

// Whether a surface seen so is a smooth interface between media of different indices: what stops a
// shadow ray that next-event estimation through glass (and the light tracer's connections) may go
// on through.
inline bool smooth_glass_seen(const SurfaceSeen& seen) {
  return !seen.index_matched && seen.surface.kind == SurfaceKind::interface && seen.surface.roughness == 0.0;
}

// Which strategies next-event estimation combines at a vertex.
enum class NextEvent : std::uint8_t {
  // Whitted's: one area light drawn by power and every delta light, unweighted (no other strategy
  // of its reaches a light), and no environment map.
  lights,
  // The path tracer's: those and one direction of the environment map, each MIS-weighted against
  // the vertex's own sampling of its direction by the power heuristic.
  lights_and_map_weighted,
  // The same, and a point, spot or distant light that smooth interfaces hide (a flat face, a chain
  // of mesh faces, an exact sphere), reached through them (manifold.h), for
  // the path tracer alone: no other strategy of its
  // reaches those paths, where the bidirectional estimators' light subpaths do (their tails keep
  // lights_and_map_weighted; bdpt's one exception, where its light subpaths reach the vertex but
  // no connection can join them to the camera subpath, is Bdpt::through_glass). Area and spherical lights too, through exact spheres and (small ones:
  // SceneView::lamp_through_chains) through chains of mesh faces and exact cylinders' sides,
  // weighted against the walk.
  lights_map_and_interfaces,
};

// The map's lobe (lights/environment.h) for next-event estimation at a surface event seen from
// wo: at a surface that only reflects (diffuse, a rough conductor, glTF's metallic-roughness),
// about the shading normal on wo's side, since f·cos θ carries the cosine whatever the lobe's
// shape; at a rough interface, about its outward normal from either side (the map lies outside the
// closed object, and a direction into it meets the object's far side). The path tracer draws from
// it (radiance.h); a bidirectional tail keeps the map's own.
template <std::size_t N>
int environment_lobe(const RenderScene& scene, const SurfaceEvent<N>& e, const Vec3& wo) {
  if (!scene.environment) return -1;
  if (std::holds_alternative<RoughDielectric>(e.bsdf)) return scene.environment->lobe(e.frame.n);
  const auto* metal = std::get_if<ConductorReflection<N>>(&e.bsdf);
  const bool reflects_only = std::holds_alternative<DiffuseReflection<N>>(e.bsdf) ||
                             std::holds_alternative<MetallicRoughness<N>>(e.bsdf) || (metal && metal->alpha > 0.0);
  if (!reflects_only) return -1;
  return scene.environment->lobe(dot(e.frame.n, wo) >= 0.0 ? e.frame.n : -e.frame.n);
}

// Direct light at a non-specular surface event, towards wo, by the strategies `next_event`
// names; the map drawn from its `lobe` (environment_lobe; −1: the map's own density). Shadow rays
// go as transmission() says; with `through`, the environment's goes on through the smooth
// interfaces that block it (exit_guide.h: surface_exit_guide). path_r_u: the path's
// unidirectional ratios so far (all 1 outside scattering media).
template <std::size_t N>
SampledSpectrum<N> direct_light(const SceneView<N>& v, const Hit& hit, const SurfaceEvent<N>& e, const Vec3& wo,
                                const SampledWavelengths<N>& w, const SampledSpectrum<N>& path_r_u, Rng& rng,
                                std::uint64_t& rays, NextEvent next_event,
                                const ThroughInterfaces* through = nullptr, int lobe = -1);

// The same at a scattering event of a camera walk: the phase function in place of the BSDF, by the
// path tracer's strategies (NextEvent::lights_and_map_weighted; with through_interfaces,
// lights_map_and_interfaces).
// through_share: the probability with which the lamps' connections through the interfaces are
// made (divided by it): a split walk's in a dense medium (dense_media.h: split_walk_nee_share).
template <std::size_t N>
SampledSpectrum<N> direct_light_in_medium(const SceneView<N>& v, const MediumPoint& at, const SampledWavelengths<N>& w,
                                          const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays,
                                          bool through_interfaces = false, double through_share = 1.0);

// Only the point, spot and distant lamps of direct_light_in_medium, reached as it reaches them
// (through the interfaces with through_interfaces): the connections shell transport keeps where
// it leaves a sphere's vertices out (shell_hops.h), whose other strategies the walk's own
// directions stand for; those through the interfaces with through_share as above.
template <std::size_t N>
SampledSpectrum<N> delta_lights_in_medium(const SceneView<N>& v, const MediumPoint& at, const SampledWavelengths<N>& w,
                                          const SampledSpectrum<N>& path_r_u, Rng& rng, std::uint64_t& rays,
                                          bool through_interfaces = false, double through_share = 1.0);

}  // namespace bouguer
