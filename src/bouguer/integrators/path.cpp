// The unidirectional spectral path tracer. Next-event estimation (integrators/events.h) combined
// with BSDF sampling by multiple importance sampling (power heuristic). At a smooth interface the
// path reflects with probability F and refracts otherwise (weight 1: the Fresnel factor cancels),
// so the same interface and medium model as the Whitted integrator hold, and both converge to the
// same image. Shadow rays are blocked by any surface; light reaches diffuse surfaces through glass
// along BSDF-sampled paths (caustics, coloured shadows).
// Russian roulette starts at depth 4 and is never played where the medium forbids it (inside an
// absorber, media/medium.h); the survival probability is the largest throughput over
// wavelengths, at least 5 %.
// Dispersion: at the first dispersive interface the path keeps one wavelength (keep_one_wavelength;
// its choice stratified over the pixel's samples by the caller) and follows n(λ) from there on;
// each wavelength's expected contribution is unchanged.
// Scattering media: delta tracking of the scattering with spectral MIS (media/scattering.h), the
// absorption in closed form; next-event estimation at every medium vertex through the phase
// function, and near the boundary of a dense medium next-event estimation through its smooth
// interfaces to the environment map (events.h: ExitGuide); Russian roulette by throughput there
// too. Scattering events do not count against max_depth; a path stops after kMaxScatterings of
// them (integrators/events.h). Index-matched interfaces are crossed without a vertex.
// The walk is the one random walk of integrators/walk.h; this file is its visitor.
#include "bouguer/integrators/integrators.h"
#include "bouguer/integrators/walk.h"

namespace bouguer {
namespace {

// The path tracer's visitor: at each vertex of a camera walk, what it sees directly (an emitter or
// the environment, weighted against next-event estimation) and next-event estimation; at most
// max_depth surface vertices and kMaxScatterings medium vertices.
template <std::size_t N>
struct Radiance {
  static constexpr bool kReverse = false;
  const SceneView<N>& v;
  const SampledWavelengths<N>& w;
  WalkState<N>& state;  // its mis: r_u over the path, r_l since its last vertex (media/scattering.h)
  Rng& rng;
  std::uint64_t& rays;
  Vec3 previous;  // the last vertex: where next-event estimation would have started
  SampledSpectrum<N> l;
  int surfaces = 0, scatterings = 0;

  // A light met along a direction drawn with density state.pdf_dir (0: specular, or the camera).
  void arrived_at_light(const Vertex<N>& x) {
    const RenderScene& scene = v.scene;
    const double arrived = state.pdf_dir;
    const Vec3 d = -x.wo;
    if (x.infinite) {  // an environment map is also reached by next-event estimation: weighted against it
      // (through smooth interfaces from a guided medium vertex: against the guide, events.h)
      const double weight =
          arrived == 0.0 || !scene.environment
              ? (arrived == 0.0 && state.guide.active()
                     ? power_heuristic(state.guide_phase_pdf, exit_guide_pdf(scene, state.guide, state.guide_dir))
                     : 1.0)
              : spectral_power_heuristic(scene, arrived, state.mis.r_u, environment_pdf(scene, d), state.mis.r_l);
      l += x.beta * escaped(v, -1, d, w) * static_cast<float>(weight / mean_ratio(scene, state.mis.r_u));
      return;
    }
    const double weight =
        arrived == 0.0 ? 1.0
                       : spectral_power_heuristic(scene, arrived, state.mis.r_u, area_light_pdf(scene, x.hit, previous, d),
                                                  state.mis.r_l);
    l += x.beta * emitted(v, x.hit, x.wo, w) * static_cast<float>(weight / mean_ratio(scene, state.mis.r_u));
  }

  // A walk of one wavelength from here on (walk.h: the split at a dense chromatic medium), adding
  // to nothing yet; join() takes what it found.
  Radiance split(WalkState<N>& s, const SampledWavelengths<N>& wk, Rng& r) const {
    return Radiance{v, wk, s, r, rays, previous, {}, surfaces, scatterings};
  }
  void join(const Radiance& child) { l += child.l; }

  bool vertex(const Vertex<N>& x) {
    if (x.kind == VertexKind::light) {
      arrived_at_light(x);
      return false;
    }
    if (x.kind == VertexKind::medium) return medium_vertex(x.point);  // (the walk calls it itself)
    if (++surfaces > v.max_depth) return false;
    if (!x.delta) l += x.beta * direct_light(v, x.hit, x.event, x.wo, w, state.mis.r_u, rng, rays, true, true);
    moved_to(x.point);
    return true;
  }

  // A scattering event at `point`; its throughput, medium and nested set are the walk's state's.
  bool medium_vertex(const Vec3& point) {
    const RenderScene& scene = v.scene;
    if (++scatterings > kMaxScatterings) return false;
    const int medium = state.medium;
    const Vec3 direction = state.ray.direction;  // the one it arrived along
    const PhaseFunction& phase = scattering_medium(scene, medium)->phase;
    // Thinned deep in a dense medium, where it finds nothing (events.h: nee_probability_in_medium).
    const double q = nee_probability_in_medium(v, medium, point, w, state.near);
    if (q >= 1.0 || rng.next_double() < q)
      l += state.beta *
           direct_light_in_medium(v, point, direction, phase, medium, w, state.mis.r_u, rng, rays, state.inside) *
           static_cast<float>(1.0 / q);
    // Near the boundary, through it (events.h: ExitGuide). Its numbers come from a stream of its
    // own, so the walk's moves on by one however many the connection takes.
    // (None where the walk could not cross one more surface.)
    state.guide = surfaces < v.max_depth ? exit_guide_at(v, medium, point, w, state.near) : ExitGuide{};
    if (state.guide.active()) {
      Rng side(rng.next_u32(), kExitGuideStream);
      l += state.beta *
           environment_through_interfaces(v, point, direction, phase, medium, state.guide, w, side, rays,
                                          state.inside, v.max_depth - surfaces, state.crossings) *
           static_cast<float>(1.0 / mean_ratio(scene, state.mis.r_u));
    }
    moved_to(point);
    return true;
  }

  void moved_to(const Vec3& point) {
    if (v.scene.scatters) state.mis.r_l = state.mis.r_u;  // (all ones otherwise)
    previous = point;
  }
};

template <std::size_t N>
SampledSpectrum<N> path(const SceneView<N>& v, Ray ray, SampledWavelengths<N>& w, double dispersion_u, Rng& rng,
                        std::uint64_t& rays) {
  WalkState<N> state;
  state.ray = ray;
  state.from = state.start = ray.origin;
  state.medium = v.scene.world_medium;
  state.dispersion_u = dispersion_u;
  const Camera::Cone cone = v.camera.pixel_cone();
  state.cone_width_m = cone.width_m;
  state.cone_spread_rad = cone.spread_rad;
  Radiance<N> li{v, w, state, rng, rays, ray.origin, {}, 0, 0};
  random_walk(v, WalkMedia{}, TransportMode::radiance, state, w, rng, rays, li);
  return li.l;
}

}  // namespace

void render_path(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                 SampleRange range, const RenderControl& control, RenderStats& stats) {
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    render_camera_paths<N>(scene, settings, film, region, range, control, stats, path<N>);
  });
}

}  // namespace bouguer
