#include "bouguer/render/render.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cmath>

#include "bouguer/core/error.h"
#include "bouguer/render/camera.h"
#include "bouguer/render/path.h"
#include "bouguer/render/whitted.h"

namespace bouguer {
namespace {

constexpr int kTileSize = 16;

// Sample s of a pixel: the first m² samples fill an m×m grid of strata (m = ⌊√spp⌋) with one
// jittered point each; the rest are uniform.
std::array<double, 2> subpixel(int s, int spp, Rng& rng) {
  const int m = static_cast<int>(std::sqrt(static_cast<double>(spp)));
  const double jx = rng.next_double(), jy = rng.next_double();
  if (s < m * m) return {(s % m + jx) / m, (s / m + jy) / m};
  return {jx, jy};
}

template <std::size_t N>
void render_tiles(const RenderScene& scene, const SpectralBasis<N>& basis, const RenderOptions& options, Film& film,
                  RenderStats& stats) {
  const SpectralScene<N> spectral = make_spectral_scene(scene, basis);
  const WhittedIntegrator<N> whitted(scene, spectral);
  const PathIntegrator<N> path(scene, spectral);
  const bool use_path = scene.render.integrator == IntegratorType::path;
  auto radiance = [&](const Ray& ray, Rng& rng, std::uint64_t& rays) {
    return use_path ? path.radiance(ray, scene.world_medium, rng, rays)
                    : whitted.radiance(ray, scene.world_medium, 0, 1.0f, rng, rays);
  };
  const Camera camera(scene.camera);
  const int w = film.width, h = film.height, spp = scene.render.spp;
  const int tiles_x = (w + kTileSize - 1) / kTileSize, tiles_y = (h + kTileSize - 1) / kTileSize;
  const int tiles = tiles_x * tiles_y;
  std::atomic<int> done{0};
  tbb::combinable<std::uint64_t> rays([] { return std::uint64_t{0}; });

  auto render_tile = [&](int tile) {
    std::uint64_t& ray_count = rays.local();
    const int x0 = (tile % tiles_x) * kTileSize, y0 = (tile / tiles_x) * kTileSize;
    for (int y = y0; y < std::min(y0 + kTileSize, h); ++y)
      for (int x = x0; x < std::min(x0 + kTileSize, w); ++x) {
        Rng rng(scene.render.seed, static_cast<std::uint64_t>(y) * w + x);
        SampledSpectrum<N> sum;
        for (int s = 0; s < spp; ++s) {
          const auto [u, v] = subpixel(s, spp, rng);
          sum += radiance(camera.generate_ray(x + u, y + v), rng, ray_count);
        }
        const SampledSpectrum<N> mean = sum / static_cast<float>(spp);
        const Vec3 rgb = basis.to_linear_srgb(mean);
        film.set_rgb(x, y, {static_cast<float>(rgb.x), static_cast<float>(rgb.y), static_cast<float>(rgb.z)});
        if (film.has_spectra())
          std::copy(mean.v.begin(), mean.v.end(), film.spectrum_at(x, y).begin());
      }
    const int finished = ++done;
    if (options.progress) options.progress(static_cast<double>(finished) / tiles);
  };

  const int threads = options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& r) {
      for (int t = r.begin(); t != r.end(); ++t) render_tile(t);
    });
  });
  stats.rays = rays.combine(std::plus<>());
}

}  // namespace

Film render(const RenderScene& scene, const RenderOptions& options, RenderStats& stats) {
  const auto start = std::chrono::steady_clock::now();
  const bool full = scene.render.spectral == SpectralMode::full;
  if (scene.render.integrator == IntegratorType::whitted)
    for (const Surface& surface : scene.surfaces)
      if (surface.kind == SurfaceKind::interface && surface.roughness > 0.0)
        fail("{}: object '{}': a rough interface needs the path tracer (--integrator path)", scene.file.string(),
             surface.object);
  if (options.keep_spectra && !full) fail("spectral output needs --spectral full (rgb3 carries R, G, B, not spectra)");
  std::vector<double> wavelengths;
  if (options.keep_spectra) {
    const auto basis = make_full_basis();
    wavelengths.assign(basis.wavelength_nm.begin(), basis.wavelength_nm.end());
  }
  Film film(scene.camera.width_px, scene.camera.height_px, std::move(wavelengths));
  if (full) render_tiles(scene, make_full_basis(), options, film, stats);
  else render_tiles(scene, make_rgb3_basis(), options, film, stats);
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return film;
}

}  // namespace bouguer
