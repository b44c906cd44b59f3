#include "bouguer/integrators/guiding.h"

#include <algorithm>
#include <chrono>
#include <vector>

#include "bouguer/integrators/integrators.h"
#include "bouguer/integrators/radiance.h"

namespace bouguer {
namespace {

// The salt of the training samples' streams (render/sampling.h: sample_rng), apart from every
// estimator's own.
constexpr std::uint64_t kGuideTrainingSalt = 7;
constexpr int kBandRows = 16;
constexpr int kMaxGuideIterations = 7;

// Training iterations for a render of `spp` samples per pixel (prepare_guide says how many).
int guide_training_iterations(int spp) {
  int k = 1;
  while (k < kMaxGuideIterations && (1 << (k + 1)) - 1 <= spp / 4) ++k;
  return k;
}

template <std::size_t N>
void train(const RenderScene& scene, const RenderSettings& settings, int iterations, const RenderControl& control,
           RenderStats& stats, GuideTraining& report, double max_seconds, PathGuide& guide) {
  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const SpectralTables<N> tables(scene.spectra, settings.spectral);
  const Camera camera(scene.camera);
  const SceneView<N> view{scene, tables, camera, settings.max_depth, exit_guide_enabled(settings, scene),
                          settings.manifold, settings.area_lamp_chains};
  const int width = scene.camera.width_px, height = scene.camera.height_px;
  RenderControl c;
  c.threads = control.threads;
  c.cancel = control.cancel;
  double last_s = 0.0;
  for (int k = 0; k < iterations; ++k) {
    // (the next iteration takes about twice the last one's time)
    if (max_seconds > 0.0 && k > 0 && elapsed() + 2.0 * last_s > max_seconds) break;
    if (control.cancel && control.cancel->load()) break;
    const double began = elapsed();
    RenderSettings s = settings;
    s.spp = 1 << k;
    s.seed = settings.seed * 0x9e3779b97f4a7c15ULL + static_cast<std::uint64_t>(k + 1);
    const PathGuide* from = k > 0 ? &guide : nullptr;
    for (int y0 = 0; y0 < height; y0 += kBandRows) {
      const PixelRegion band{0, y0, width, std::min(y0 + kBandRows, height)};
      // Each pixel's records apart (its samples run in order on one thread), added in pixel order.
      std::vector<std::vector<GuideRecord>> records(static_cast<std::size_t>(width) *
                                                    static_cast<std::size_t>(band.y1 - band.y0));
      for_each_pixel_sample<N>(scene, tables, s, width, band, {0, s.spp}, c, stats, kGuideTrainingSalt,
                               [&](int x, int y, int sample, Rng& rng, SampledWavelengths<N>& w, double dispersion_u,
                                   std::uint64_t& rays) {
                                 const auto [u, v] = subpixel(sample, s.spp, s.seed, pixel_index(x, y, width), rng);
                                 auto& out = records[static_cast<std::size_t>(y - y0) * static_cast<std::size_t>(width) +
                                                     static_cast<std::size_t>(x)];
                                 path_radiance(view, camera.generate_ray(x + u, y + v), w, dispersion_u, rng, rays, from,
                                               &out);
                               });
      for (const auto& r : records) {
        guide.add(r);
        report.records += r.size();
      }
    }
    guide.end_iteration(k);
    report.iterations = k + 1;
    report.spp += s.spp;
    last_s = elapsed() - began;
  }
  report.seconds = elapsed();
  report.leaves = guide.leaf_count();
  report.bytes = guide.bytes();
}

}  // namespace

bool guiding_enabled(const RenderSettings& settings) {
  return settings.integrator == IntegratorType::path && settings.guiding;
}

std::unique_ptr<PathGuide> prepare_guide(const RenderScene& scene, const RenderSettings& settings,
                                         const RenderControl& control, RenderStats& stats, GuideTraining& report,
                                         double max_seconds) {
  if (!guiding_enabled(settings)) return nullptr;
  auto guide = std::make_unique<PathGuide>(scene.bounds.centre_m, scene.bounds.radius_m * 1.001);
  with_carried_count(settings.spectral, [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
    train<N>(scene, settings, guide_training_iterations(settings.spp), control, stats, report, max_seconds, *guide);
  });
  stats.seconds += report.seconds;
  return guide;
}

}  // namespace bouguer
