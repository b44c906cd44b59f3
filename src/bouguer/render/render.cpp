#include "bouguer/render/render.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/global_control.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <numeric>

#include "bouguer/core/error.h"
#include "bouguer/render/camera.h"
#include "bouguer/render/path.h"
#include "bouguer/render/whitted.h"
#include "bouguer/spectra/color_space.h"

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

// Wavelength numbers stratified over a pixel's samples: sample s gets (order[s] + offset) / spp.
// The order is shuffled per pixel, on a stream of its own (the camera sampling stays unchanged),
// so that the stratum is independent of the sub-pixel position, which is stratified by the sample
// index too: paired in index order, each wavelength would see its own part of the pixel, a bias at
// every edge where the image depends on wavelength (dispersion). Used for the hero wavelengths and
// for the wavelength a path keeps at a dispersive interface.
class WavelengthStrata {
 public:
  WavelengthStrata(std::uint64_t seed, std::uint64_t pixel, int spp) : order_(spp) {
    Rng rng(seed ^ 0x9e3779b97f4a7c15ULL, pixel);
    offset_ = rng.next_double();
    std::iota(order_.begin(), order_.end(), 0);
    for (int i = spp - 1; i > 0; --i) std::swap(order_[i], order_[rng.next_u32() % static_cast<std::uint32_t>(i + 1)]);
  }
  double u(int s) const { return (order_[s] + offset_) / static_cast<double>(order_.size()); }

 private:
  std::vector<int> order_;
  double offset_ = 0.0;
};

// Runs pixel(x, y, rng, rays) for every pixel, tiles in parallel, each pixel with its own stream.
template <typename PixelFn>
void for_each_pixel(const RenderScene& scene, const RenderOptions& options, int w, int h, RenderStats& stats,
                    PixelFn pixel) {
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
        pixel(x, y, rng, ray_count);
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

template <std::size_t N>
SampledSpectrum<N> trace(const RenderScene& scene, const SpectralScene<N>& spectral, const Ray& ray,
                         double wavelength_u, Rng& rng, std::uint64_t& rays) {
  if (scene.render.integrator == IntegratorType::path)
    return PathIntegrator<N>(scene, spectral).radiance(ray, scene.world_medium, wavelength_u, rng, rays);
  return WhittedIntegrator<N>(scene, spectral).radiance(ray, scene.world_medium, 0, 1.0f, rng, rays);
}

void set_pixel(Film& film, int x, int y, const Vec3& rgb) {
  film.set_rgb(x, y, {static_cast<float>(rgb.x), static_cast<float>(rgb.y), static_cast<float>(rgb.z)});
}

// full and rgb3: the same wavelengths for every sample; the film may keep the mean spectrum.
template <std::size_t N>
void render_fixed(const RenderScene& scene, const SpectralBasis<N>& basis, const RenderOptions& options, Film& film,
                  RenderStats& stats) {
  const SpectralScene<N> spectral = make_spectral_scene(scene, basis);
  const Camera camera(scene.camera);
  const int spp = scene.render.spp;
  for_each_pixel(scene, options, film.width, film.height, stats, [&](int x, int y, Rng& rng, std::uint64_t& rays) {
    SampledSpectrum<N> sum;
    const WavelengthStrata strata(scene.render.seed, static_cast<std::uint64_t>(y) * film.width + x, spp);
    for (int s = 0; s < spp; ++s) {
      const auto [u, v] = subpixel(s, spp, rng);
      sum += trace(scene, spectral, camera.generate_ray(x + u, y + v), strata.u(s), rng, rays);
    }
    const SampledSpectrum<N> mean = sum / static_cast<float>(spp);
    set_pixel(film, x, y, basis.to_linear_srgb(mean));
    if (film.has_spectra()) std::copy(mean.v.begin(), mean.v.end(), film.spectrum_at(x, y).begin());
  });
}

// hero: new wavelengths for every sample, each sample turned into XYZ at once.
void render_hero(const RenderScene& scene, const RenderOptions& options, Film& film, RenderStats& stats) {
  const SpectralTables tables = make_spectral_tables(scene);
  const Camera camera(scene.camera);
  const int spp = scene.render.spp;
  for_each_pixel(scene, options, film.width, film.height, stats, [&](int x, int y, Rng& rng, std::uint64_t& rays) {
    SpectralScene<kHeroCount> spectral;
    Vec3 xyz;
    const WavelengthStrata strata(scene.render.seed, static_cast<std::uint64_t>(y) * film.width + x, spp);
    for (int s = 0; s < spp; ++s) {
      const auto [u, v] = subpixel(s, spp, rng);
      // The heroes are stratified over the pixel's samples, in the shuffled order.
      const HeroWavelengths w = sample_hero_wavelengths(strata.u(s) / kHeroCount);
      fill_spectral_scene(tables, w.nm, spectral);
      xyz += hero_to_xyz(trace(scene, spectral, camera.generate_ray(x + u, y + v), rng.next_double(), rng, rays), w);
    }
    set_pixel(film, x, y, xyz_to_linear_rgb(kRec709, xyz / static_cast<double>(spp)));
  });
}

}  // namespace

Film render(const RenderScene& scene, const RenderOptions& options, RenderStats& stats) {
  const auto start = std::chrono::steady_clock::now();
  if (options.keep_spectra && scene.render.spectral != SpectralMode::full)
    fail("spectral output needs --spectral full (rgb3 carries R, G, B; hero other wavelengths per sample)");
  if (scene.render.integrator == IntegratorType::whitted)
    for (const Surface& surface : scene.surfaces)
      if (surface.kind == SurfaceKind::interface && surface.roughness > 0.0)
        fail("{}: object '{}': a rough interface needs the path tracer (--integrator path)", scene.file.string(),
             surface.object);
  const auto full_basis = make_full_basis();
  std::vector<double> wavelengths;
  if (options.keep_spectra) wavelengths.assign(full_basis.wavelength_nm.begin(), full_basis.wavelength_nm.end());
  Film film(scene.camera.width_px, scene.camera.height_px, std::move(wavelengths));
  switch (scene.render.spectral) {
    case SpectralMode::full: render_fixed(scene, full_basis, options, film, stats); break;
    case SpectralMode::rgb3: render_fixed(scene, make_rgb3_basis(), options, film, stats); break;
    case SpectralMode::hero: render_hero(scene, options, film, stats); break;
  }
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return film;
}

}  // namespace bouguer
