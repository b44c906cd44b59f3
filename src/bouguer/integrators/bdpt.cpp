// Bidirectional path tracing (Veach 1997; pbrt-v4's BDPT): per camera sample one camera subpath
// and one light subpath and every connection strategy between them (integrators/bidirectional.h).
#include "bouguer/integrators/bidirectional.h"

namespace bouguer {
namespace {

using bidir::Bdpt;
using bidir::begin_sample;

template <std::size_t N>
void render(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
            SampleRange range, const RenderControl& control, RenderStats& stats) {
  const SpectralTables<N> tables(scene.spectra, settings.spectral);
  const Camera camera(scene.camera);
  const SceneView<N> view{scene, tables, camera, settings.max_depth, exit_guide_enabled(settings, scene),
                          settings.manifold};
  for_each_pixel_sample<N>(
      scene, tables, settings, film.width(), region, range, control, stats, 2,
      [&](int x, int y, int s, Rng& rng, SampledWavelengths<N>& w, double dispersion_u, std::uint64_t& rays) {
        thread_local std::vector<Vertex<N>> camera_path, light_path;
        thread_local std::vector<double> sigma_mean;
        thread_local SampledWavelengths<N> kept;
        const SampledSpectrum<N> keep = begin_sample(view, w, dispersion_u, rng, sigma_mean, kept);
        const WalkMedia media{sigma_mean};
        Bdpt<N> bdpt(view, media, w, scene.dispersive ? &kept : nullptr, rng, rays);
        const auto [u, v] = subpixel(s, settings.spp, settings.seed, pixel_index(x, y, film.width()), rng);
        bdpt.camera_subpath(camera.generate_ray(x + u, y + v), camera_path, &keep);
        bdpt.light_subpath(light_path);
        add_camera_sample(film, tables, w, x, y, s,
                          bdpt.connect_all(light_path, camera_path, film, keep) + bdpt.camera_tail());
      });
}

}  // namespace

void render_bdpt(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                 SampleRange range, const RenderControl& control, RenderStats& stats) {
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    render<N>(scene, settings, film, region, range, control, stats);
  });
}

}  // namespace bouguer
