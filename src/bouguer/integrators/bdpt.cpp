// Bidirectional path tracing (Veach 1997; pbrt-v4's BDPT): per camera sample one camera subpath
// and one light subpath and every connection strategy between them (integrators/bidirectional.h).
#include "bouguer/integrators/bidirectional.h"

namespace bouguer {
namespace {

using bidir::Bdpt;
using bidir::begin_sample;
using bidir::is_delta_light;


template <std::size_t N>
void render(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
            SampleRange range, const RenderControl& control, RenderStats& stats) {
  const SpectralTables<N> tables(scene.spectra, settings.spectral);
  const Camera camera(scene.camera);
  const SceneView<N> view{scene, tables, camera, settings.max_depth};
  for_each_pixel_sample<N>(
      scene, tables, settings, film.width(), region, range, control, stats, 2,
      [&](int x, int y, int s, Rng& rng, SampledWavelengths<N>& w, double dispersion_u, std::uint64_t& rays) {
        thread_local std::vector<Vertex<N>> camera_path, light_path;
        thread_local std::vector<double> sigma_mean;
        thread_local SampledWavelengths<N> kept;
        const SampledSpectrum<N> keep = begin_sample(view, w, dispersion_u, rng, sigma_mean, kept);
        const WalkMedia media{sigma_mean};
        Bdpt<N> bdpt(view, media, w, scene.dispersive ? &kept : nullptr, rng, rays);
        const auto [u, v] = subpixel(s, settings.spp, rng);
        bdpt.camera_subpath(camera.generate_ray(x + u, y + v), camera_path);
        bdpt.light_subpath(light_path);
        const int nc = static_cast<int>(camera_path.size()), nl = static_cast<int>(light_path.size());
        if (light_path.empty()) light_path.emplace_back();  // the slot of s = 1's own light sample
        SampledSpectrum<N> l;
        for (int t = 1; t <= nc; ++t)
          for (int k = 0; k <= std::max(nl, 1); ++k) {
            const int depth = k + t - 2;
            if ((k == 1 && t == 1) || depth < 0 || depth > settings.max_depth) continue;
            l += bdpt.connect(light_path, camera_path, k, t, film, keep);
          }
        const Vec3 rgb = tables.to_linear_rgb(l, w);
        if (film.has_spectra())
          film.add_sample(x, y, rgb, 1.0, std::span<const float>(l.v.data(), N));
        else
          film.add_sample(x, y, rgb, 1.0);
      });
}

}  // namespace

BdptMisCheck bdpt_mis_check(const RenderScene& scene, const RenderSettings& settings, int x, int y, int sample) {
  BdptMisCheck out;
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    bidir::mis_check<N>(scene, settings, x, y, sample, {},
                        [](const Bdpt<N>&, const std::vector<Vertex<N>>&, const std::vector<Vertex<N>>&) { return 0.0; }, out);
  });
  return out;
}

void render_bdpt(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, PixelRegion region,
                 SampleRange range, const RenderControl& control, RenderStats& stats) {
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    render<N>(scene, settings, film, region, range, control, stats);
  });
}

}  // namespace bouguer
