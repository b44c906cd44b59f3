// Light tracing: paths start at the lights (one drawn by power, then a point and a direction from
// its own emission sampling) and carry importance-mode BSDF weights; every vertex on a
// non-specular surface is connected to the camera by a shadow ray and splatted at its film
// position, and a lamp's own point is connected too (the lamp seen directly). It finds caustics
// on diffuse receivers (light focused by glass), which the path tracer reaches only by chance.
// Where smooth glass stands between a vertex and a pinhole camera, the connection is solved
// through it (splats.cpp: splat_through_glass, as next-event estimation through glass). What it
// cannot see: what the camera sees by a reflection (a mirror, the glass's own reflections), and
// the background or environment seen directly, since a connection ends on a non-specular surface
// or a lamp. The same Russian roulette and depth limit as the path tracer.
// The same walk also gives the path tracer its light paths (render.light_paths): only the splats
// of paths that its next-event estimation does not make (LightSplats::beyond_next_event).
// In scattering media: the same delta tracking as the path tracer, and every medium vertex is
// connected to the camera through the phase function.
// The walk is the one random walk of integrators/walk.h; this file is only its visitor.
// Light path i of pixel slot p is seeded by (seed, p, i): region and sample-range splits give the
// same splats, whose fixed-point sums (render/film.h) do not depend on the order of arrival.
#include "bouguer/integrators/integrators.h"
#include "bouguer/integrators/light_prefix.h"
#include "bouguer/integrators/walk.h"

namespace bouguer {
namespace {

// Which splats a light path makes: all of them (the light tracer), or only those of a path from a
// point, spot or distant lamp that the path tracer's next-event estimation does not make at the path's first
// vertex that is not specular (manifold.h: next_event_makes): light a mirror or a glass reflected
// on its way there, light through glass along a path the connection through the glass does not
// solve. Added to the path tracer's image, these make every path either estimator makes count
// once (render.light_paths).
enum class LightSplats { all, beyond_next_event };

// The light tracer's visitor of a light subpath: every vertex on a non-specular surface and every
// medium vertex connected to the camera; at most max_depth surface vertices and kMaxScatterings
// medium vertices. beyond_next_event: first the path's specular prefix (light_prefix.h), and at
// its first vertex that is not specular whether next-event estimation makes the path; where it
// does, the walk stops there.
template <std::size_t N>
struct SplatToCamera {
  static constexpr bool kReverse = false;
  const SceneView<N>& v;
  const SampledWavelengths<N>& w;
  Rng& rng;
  FilmBuffer& film;
  std::uint64_t& rays;
  std::optional<LightPrefix<N>> prefix = std::nullopt;  // beyond_next_event, until it is decided
  int surfaces = 0, scatterings = 0;

  bool vertex(const Vertex<N>& x) {
    // (The walk's limits first: where it stops anyway, no decision need be paid for.)
    if (x.kind == VertexKind::medium ? ++scatterings > kMaxScatterings : ++surfaces > v.max_depth) return false;
    if (prefix) {
      const PrefixVerdict verdict = prefix->add(v, x, w, rays);
      if (verdict == PrefixVerdict::made) return false;
      if (verdict == PrefixVerdict::beyond) prefix.reset();
    }
    splat_vertex_to_camera(v, x, x.beta, w, rng, film, rays);
    return true;
  }
};
static_assert(WalkVisitor<SplatToCamera<kFullBins>, kFullBins> && !TakesMediumPoints<SplatToCamera<kFullBins>> &&
              !SplitsWalks<SplatToCamera<kFullBins>, kFullBins>);

template <std::size_t N>
void trace_light_path(const SceneView<N>& v, SampledWavelengths<N>& w, double dispersion_u, Rng& rng,
                      FilmBuffer& film, std::uint64_t& rays, LightSplats which) {
  Vertex<N> y;
  WalkState<N> state;
  // (The path tracer's light paths start at its point, spot and distant lamps alone: its own
  // directions meet every other lamp.)
  if (!start_light_subpath(v, w, rng, y, state,
                           which == LightSplats::beyond_next_event ? &v.scene.delta_lamps : nullptr))
    return;
  state.dispersion_u = dispersion_u;
  const Light& lamp = v.scene.lights[static_cast<std::size_t>(y.light)];
  SplatToCamera<N> splat{v, w, rng, film, rays};
  if (which == LightSplats::beyond_next_event) {
    splat.prefix = light_prefix<N>(lamp, y.point);
    if (!splat.prefix) return;
  } else if (on_a_surface(lamp)) {
    splat_light_to_camera(v, y.hit, lamp, state.medium, y.beta, w, rng, film, rays);
  }
  random_walk(v, WalkMedia{}, TransportMode::importance, state, w, rng, rays, splat);
}

template <std::size_t N>
void render_light_paths(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                        SampleRange range, const RenderControl& control, RenderStats& stats) {
  const SpectralTables<N> tables(scene.spectra, settings.spectral);
  const Camera camera(scene.camera);
  const SceneView<N> view{scene, tables, camera, settings.max_depth, true, settings.manifold};
  for_each_pixel_sample<N>(scene, tables, settings, film.width(), region, range, control, stats, 1,
                           [&](int, int, int, Rng& rng, SampledWavelengths<N>& w, double dispersion_u,
                               std::uint64_t& rays) {
                             trace_light_path(view, w, dispersion_u, rng, film, rays, LightSplats::all);
                           });
}

}  // namespace

void render_light(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                  SampleRange range, const RenderControl& control, RenderStats& stats) {
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    render_light_paths<N>(scene, settings, film, region, range, control, stats);
  });
}

template <std::size_t N>
void trace_light_path_beyond_next_event(const SceneView<N>& v, SampledWavelengths<N>& w, double dispersion_u, Rng& rng,
                                        FilmBuffer& film, std::uint64_t& rays) {
  trace_light_path(v, w, dispersion_u, rng, film, rays, LightSplats::beyond_next_event);
}
template void trace_light_path_beyond_next_event(const SceneView<kFullBins>&, SampledWavelengths<kFullBins>&, double,
                                                 Rng&, FilmBuffer&, std::uint64_t&);
template void trace_light_path_beyond_next_event(const SceneView<3>&, SampledWavelengths<3>&, double, Rng&,
                                                 FilmBuffer&, std::uint64_t&);
template void trace_light_path_beyond_next_event(const SceneView<kHeroCount>&, SampledWavelengths<kHeroCount>&,
                                                 double, Rng&, FilmBuffer&, std::uint64_t&);

}  // namespace bouguer
