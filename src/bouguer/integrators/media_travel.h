#pragma once
// A path between its vertices: the transmittance of a medium segment (travel, travel_to), delta
// tracking through a scattering one (through_medium), what a segment ends on besides a surface
// (escaped: the background or the map; emitted: an emitter), the continuation at a medium vertex
// (continue_from_medium) and Russian roulette, and the hero wavelength that draws a path's
// distances (draw_hero). Contract: each function reads the scene and changes only the path state
// it is handed (beta, ray, wavelengths).
#include "bouguer/integrators/scene_view.h"

namespace bouguer {

// Transmittance through scene medium `medium` (−1: none) along ray over [0, t_m]. Callers measure
// segments from the surface point a ray left (not its offset origin), so a slab's path length is
// exact and does not depend on where on the surface the ray starts.
template <std::size_t N>
inline SampledSpectrum<N> travel(const SceneView<N>& v, int medium, const Ray& ray, double t_m, const SampledWavelengths<N>& w) {
  if (medium < 0) return SampledSpectrum<N>::constant(1.0f);
  return transmittance(v.scene.media[static_cast<std::size_t>(medium)].medium, v.tables, ray, 0.0, t_m, w);
}

// The same from point `from` to point `to` along the unit direction d: the length is computed
// only where the medium absorbs.
template <std::size_t N>
inline SampledSpectrum<N> travel_to(const SceneView<N>& v, int medium, const Vec3& from, const Vec3& d, const Vec3& to,
                                    const SampledWavelengths<N>& w) {
  if (medium < 0 || !absorbs(v.scene.media[static_cast<std::size_t>(medium)].medium))
    return SampledSpectrum<N>::constant(1.0f);
  return transmittance(v.scene.media[static_cast<std::size_t>(medium)].medium, v.tables, Ray{from, d}, 0.0,
                       length(to - from), w);
}

// Radiance a ray leaving the scene in direction d brings back through `medium`: the background
// or the environment map, none through an absorber (an infinite path).
template <std::size_t N>
inline SampledSpectrum<N> escaped(const SceneView<N>& v, int medium, const Vec3& d, const SampledWavelengths<N>& w) {
  if (absorbs(v.scene, medium)) return {};
  if (v.scene.environment) return v.tables.environment(*v.scene.environment, v.scene.environment->texel(d), w);
  const auto& b = std::get<BackgroundLight>(v.scene.lights[static_cast<std::size_t>(v.scene.background_light)]);
  return v.tables.at(b.radiance, w);
}

// The light of an emitter hit: its triangle's area light, or the emitting sphere (one light, its
// hits' primitive 0: AnalyticPart::side).
inline const Light& surface_light_at(const RenderScene& scene, const Hit& hit) {
  const Surface& s = scene.surfaces[hit.geometry];
  return scene.lights[static_cast<std::size_t>(s.first_light) + hit.primitive];
}

// An area light's radiance spectrum at texture coordinates uv: its spectrum, times its emission
// texture's lifted texel there (the finest level: light sampling has no ray cone, and the same
// lookup serves every strategy, so they agree).
template <std::size_t N>
inline SampledSpectrum<N> area_radiance(const SceneView<N>& v, int spectrum, int texture, std::array<double, 2> uv,
                                        const SampledWavelengths<N>& w) {
  const SampledSpectrum<N> l = v.tables.at(spectrum, w);
  if (texture < 0) return l;
  return l * texture_reflectance(v.scene.textures, texel_blend(v.scene.textures, texture, uv, 0.0), w);
}

// The radiance spectrum a light sample (LightLiSample, LightLeSample) carries before its factor.
template <std::size_t N, typename LightSample>
inline SampledSpectrum<N> sample_radiance(const SceneView<N>& v, const LightSample& s, const SampledWavelengths<N>& w) {
  if (s.texel >= 0) return v.tables.environment(*v.scene.environment, s.texel, w);
  return area_radiance(v, s.spectrum, s.texture, s.uv, w);
}

// Radiance an emitter hit sends back along wo (zero behind a one-sided emitter).
template <std::size_t N>
inline SampledSpectrum<N> emitted(const SceneView<N>& v, const Hit& hit, const Vec3& wo, const SampledWavelengths<N>& w) {
  const Light& light = surface_light_at(v.scene, hit);
  const double factor = emitted_factor(light, wo, hit.normal);
  if (factor == 0.0) return {};
  const EmitterRadiance r = emitter_radiance(light);
  return area_radiance(v, r.spectrum, r.texture, hit.uv, w) * static_cast<float>(factor);
}

// What undoes, for Russian roulette, the scaling of radiance by (η_o/η_i)² at each refraction
// (pbrt-v4's etaScale): (n/n_world)² in `medium` for a path carrying radiance, 1 for importance.
// Inside water a camera path's beta is 1/1.33² of what it brings back once it leaves; without
// this a white furnace lost 43 % of its paths at their first roulette, which was all its noise.
inline float roulette_scale(const RenderScene& scene, int medium, TransportMode mode) {
  if (mode != TransportMode::radiance || medium < 0) return 1.0f;
  const double n = scene.media[static_cast<std::size_t>(medium)].ior_reference;
  const double n_world = scene.media[static_cast<std::size_t>(scene.world_medium)].ior_reference;
  return static_cast<float>((n * n) / (n_world * n_world));
}

// Russian roulette from depth 4, never where the medium forbids it (inside an absorber,
// media/medium.h); the survival probability is the largest throughput over wavelengths (beta over
// the mean of the path's ratios, which is what a contribution is divided by, times
// roulette_scale), at least 5 %. Whether the path goes on (beta rescaled if it does). `single`:
// the index of the only wavelength carried (every other's throughput is 0), or −1.
template <std::size_t N>
bool survives_roulette(const RenderScene& scene, int depth, int medium, SampledSpectrum<N>& beta, Rng& rng,
                       float mean_ratio = 1.0f, float scale = 1.0f, int single = -1) {
  constexpr int kRouletteDepth = 4;
  if (depth < kRouletteDepth || (medium >= 0 && !allows_roulette(scene.media[static_cast<std::size_t>(medium)].medium)))
    return true;
  const float largest = single >= 0 ? beta[static_cast<std::size_t>(single)] : beta.max_value();
  const float survive = std::max(0.05f, std::min(1.0f, largest * scale / mean_ratio));
  if (rng.next_double() >= survive) return false;
  if (single >= 0)
    beta[static_cast<std::size_t>(single)] /= survive;
  else
    beta /= survive;
  return true;
}

// The segment a path travelled from `start` to the surface it hit, through `medium`: beta times
// the exact transmittance, or in a scattering medium, delta tracking (media/scattering.h). The
// point of a real scattering event if there was one.
template <std::size_t N>
std::optional<Vec3> through_medium(const SceneView<N>& v, int medium, const Vec3& start, const Vec3& direction,
                                   const Hit& hit, const SampledWavelengths<N>& w, Rng& rng, SampledSpectrum<N>& beta,
                                   SpectralMis<N>& mis) {
  const ScatteringMedium* sm = scattering_medium(v.scene, medium);
  if (!sm) {
    beta *= travel_to(v, medium, start, direction, hit.point, w);
    return std::nullopt;
  }
  const MediumEvent e = sample_scattering(*sm, v.tables, Ray{start, direction}, length(hit.point - start), w, rng, beta, mis);
  if (!e.scattered) return std::nullopt;
  return start + direction * e.t;
}

// A ray between a path's vertices, on its way through index-matched boundaries
// (surface_events.h: advance_to_surface): the ray (from an offset origin at a surface), where its
// current segment began (lengths are measured from there, so they do not depend on the offset),
// the medium that segment travels in, the nested objects it is inside (scene/nested.h), and the
// index-matched boundaries its path has crossed so far (at most kMaxCrossings).
struct RaySegment {
  Ray ray;
  Vec3 start;
  int medium = -1;
  InsideSet inside = 0;
  int crossings = 0;
};

// A scattering event as the connections from it read it (direct_light.h, exit_guide.h, splats.h): where it is, the direction the walk
// arrived along (a camera walk's: light leaves the event along its reverse; a light walk's: light
// arrives along it), the phase function, the medium and the nested objects the walk was inside.
struct MediumPoint {
  Vec3 x;
  Vec3 direction;
  const PhaseFunction& phase;
  int medium = -1;
  InsideSet inside = 0;
};

// The head of a path, what its next step changes: its ray segment (the ray it goes on along, the
// medium that ray travels in) and the throughput (walk.h's WalkState is one).
template <std::size_t N>
struct PathHead : RaySegment {
  SampledSpectrum<N> beta = SampledSpectrum<N>::constant(1.0f);
};

// How Russian roulette reads a path (survives_roulette): what it divides the throughput by (the
// mean of the path's spectral-MIS ratios, times a split walk's bin weight) and the index of the
// only wavelength carried (−1: several).
struct RouletteReading {
  float divisor = 1.0f;
  int single = -1;
};

// A path's next step from a scattering event at x: a direction drawn from the phase function
// (weight 1) into path.ray, Russian roulette on path.beta in path.medium (`events`: the path's
// surface and scattering events so far). The phase pdf, or nullopt when the path ends.
template <std::size_t N>
std::optional<double> continue_from_medium(const RenderScene& scene, const ScatteringMedium& sm, const Vec3& x,
                                           int events, PathHead<N>& path, Rng& rng, TransportMode mode,
                                           RouletteReading roulette = {}) {
  const double u1 = rng.next_double(), u2 = rng.next_double();
  const PhaseSample ps = sample_phase(sm.phase, path.ray.direction, u1, u2);
  if (!survives_roulette(scene, events, path.medium, path.beta, rng, roulette.divisor,
                         roulette_scale(scene, path.medium, mode), roulette.single))
    return std::nullopt;
  path.ray = {x, ps.out};
  return ps.pdf;
}

// A new path's w.hero, the carried wavelength whose majorant draws its distances in scattering
// media (media/scattering.h): ⌊u·N⌋, uniform over the carried ones for a uniform u, which the
// spectral MIS needs (in hero mode too: there index 0 is always the bluest of the four). The path
// tracer hands it a number stratified over the pixel's samples (integrators.h:
// start_sample_wavelengths), so that each pixel's paths draw distances at every part of the
// spectrum equally often: where the carried wavelengths' tracking densities barely overlap (milk,
// hundreds of events a path), the spectral MIS gives a path's weight to the wavelengths near its
// hero, and a random hero per path left whole pixels short of some colours. 0 in scenes that do
// not scatter.
template <std::size_t N>
void draw_hero(const RenderScene& scene, SampledWavelengths<N>& w, double u) {
  w.hero = scene.scatters ? std::min(static_cast<int>(u * static_cast<double>(N)), static_cast<int>(N) - 1) : 0;
}
// The same from the path's own stream, drawn only in scenes that scatter (so other scenes' streams
// are unchanged): bdpt_mis_check's samples. The estimators draw theirs from strata
// (integrators.h: start_sample_wavelengths; vcm.cpp over its iterations).
template <std::size_t N>
void draw_hero(const RenderScene& scene, SampledWavelengths<N>& w, Rng& rng) {
  draw_hero(scene, w, scene.scatters ? rng.next_double() : 0.0);
}

}  // namespace bouguer
