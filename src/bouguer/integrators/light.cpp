// Light tracing: paths start at the lights (one drawn by power, then a point and a direction from
// its own emission sampling) and carry importance-mode BSDF weights; every vertex on a
// non-specular surface is connected to the camera by a shadow ray and splatted at its film
// position, and a lamp's own point is connected too (the lamp seen directly). It finds caustics
// on diffuse receivers (light focused by glass), which the path tracer reaches only by chance.
// What it cannot see: anything the camera sees through a purely specular chain (mirrors, glass)
// and the background or environment seen directly, since a connection to a pinhole ends on a
// non-specular surface or a lamp. The same Russian roulette and depth limit as the path tracer.
// In scattering media: the same delta tracking as the path tracer, and every medium vertex is
// connected to the camera through the phase function.
// The walk is the one random walk of integrators/walk.h; this file is only its visitor.
// Light path i of pixel slot p is seeded by (seed, p, i): region and sample-range splits give the
// same splats, whose fixed-point sums (render/film.h) do not depend on the order of arrival.
#include "bouguer/integrators/integrators.h"
#include "bouguer/integrators/walk.h"

namespace bouguer {
namespace {

// The light tracer's visitor of a light subpath: every vertex on a non-specular surface and every
// medium vertex connected to the camera; at most max_depth surface vertices and kMaxScatterings
// medium vertices.
template <std::size_t N>
struct SplatToCamera {
  static constexpr bool kReverse = false;
  const SceneView<N>& v;
  const SampledWavelengths<N>& w;
  Rng& rng;
  FilmBuffer& film;
  std::uint64_t& rays;
  int surfaces = 0, scatterings = 0;

  bool vertex(const Vertex<N>& x) {
    if (x.kind == VertexKind::medium) {
      if (++scatterings > kMaxScatterings) return false;
      const PhaseFunction& phase = scattering_medium(v.scene, x.medium)->phase;
      splat_medium_to_camera(v, MediumPoint{x.point, -x.wo, phase, x.medium, x.inside}, x.beta, w, x.r_u, rng, film,
                             rays);
      return true;
    }
    if (++surfaces > v.max_depth) return false;
    if (!x.delta) splat_surface_to_camera(v, x.hit, x.event, x.wo, x.beta, w, x.r_u, rng, film, rays);
    return true;
  }
};
static_assert(WalkVisitor<SplatToCamera<kFullBins>, kFullBins> && !TakesMediumPoints<SplatToCamera<kFullBins>> &&
              !SplitsWalks<SplatToCamera<kFullBins>, kFullBins>);

template <std::size_t N>
void trace_light_path(const SceneView<N>& v, SampledWavelengths<N>& w, double dispersion_u, Rng& rng,
                      FilmBuffer& film, std::uint64_t& rays) {
  Vertex<N> y;
  WalkState<N> state;
  if (!start_light_subpath(v, w, rng, y, state)) return;
  state.dispersion_u = dispersion_u;
  if (const Light& lamp = v.scene.lights[static_cast<std::size_t>(y.light)]; on_a_surface(lamp))
    splat_light_to_camera(v, y.hit, lamp, state.medium, y.beta, w, rng, film, rays);
  SplatToCamera<N> splat{v, w, rng, film, rays};
  random_walk(v, WalkMedia{}, TransportMode::importance, state, w, rng, rays, splat);
}

}  // namespace

void render_light(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                  SampleRange range, const RenderControl& control, RenderStats& stats) {
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    const SpectralTables<N> tables(scene.spectra, settings.spectral);
    const Camera camera(scene.camera);
    const SceneView<N> view{scene, tables, camera, settings.max_depth};
    for_each_pixel_sample<N>(scene, tables, settings, film.width(), region, range, control, stats, 1,
                             [&](int, int, int, Rng& rng, SampledWavelengths<N>& w, double dispersion_u,
                                 std::uint64_t& rays) { trace_light_path(view, w, dispersion_u, rng, film, rays); });
  });
}

}  // namespace bouguer
