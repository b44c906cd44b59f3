#include "bouguer/render/render.h"

#include <tbb/blocked_range.h>
#include <tbb/combinable.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <chrono>
#include <fmt/format.h>

#include "bouguer/core/error.h"
#include "bouguer/core/memory.h"
#include "bouguer/render/denoise.h"

namespace bouguer {
namespace {

constexpr int kTileSize = 16;

}  // namespace

void for_each_tile(PixelRegion region, const RenderControl& control, RenderStats& stats,
                   const std::function<void(const PixelRegion& tile, std::uint64_t& rays)>& tile) {
  const int w = region.x1 - region.x0, h = region.y1 - region.y0;
  if (w <= 0 || h <= 0) return;
  const int threads = control.threads > 0 ? control.threads : tbb::this_task_arena::max_concurrency();
  // Smaller tiles for small regions, so every thread has work (pixels are independent: the tile
  // size never changes the image).
  int size = kTileSize;
  while (size > 1 && ((w + size - 1) / size) * ((h + size - 1) / size) < 8 * threads) size /= 2;
  const int tiles_x = (w + size - 1) / size, tiles_y = (h + size - 1) / size;
  const int tiles = tiles_x * tiles_y;
  std::atomic<int> done{0};
  tbb::combinable<std::uint64_t> rays([] { return std::uint64_t{0}; });
  auto run = [&](int t) {
    if (control.cancel && control.cancel->load()) return;
    const int x0 = region.x0 + (t % tiles_x) * size, y0 = region.y0 + (t / tiles_x) * size;
    tile({x0, y0, std::min(x0 + size, region.x1), std::min(y0 + size, region.y1)}, rays.local());
    const int finished = ++done;
    if (control.progress) control.progress(static_cast<double>(finished) / tiles);
  };
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles, 1), [&](const tbb::blocked_range<int>& r) {
      for (int t = r.begin(); t != r.end(); ++t) run(t);
    });
  });
  stats.rays += rays.combine(std::plus<>());
}

void check_settings(const RenderScene& scene, const RenderSettings& settings, bool keep_spectra) {
  if (keep_spectra && settings.spectral != SpectralMode::full)
    fail("spectral output needs --spectral full (rgb3 carries R, G, B; hero other wavelengths per sample)");
  const IntegratorInfo& integrator = integrator_info(settings.integrator);
  if (!integrator.rough_interfaces)
    for (const Surface& surface : scene.surfaces)
      if (surface.kind == SurfaceKind::interface && surface.roughness > 0.0)
        fail("{}: object '{}': a rough interface needs the path tracer (--integrator path)", scene.file.string(),
             surface.object);
  if (!integrator.scattering_media)
    for (const Surface& surface : scene.surfaces)
      for (const int m : {surface.medium_front, surface.medium_behind})
        if (m >= 0 && scattering(scene.media[static_cast<std::size_t>(m)].medium))
          fail("{}: object '{}': medium '{}' scatters; the {} integrator renders absorption only (use --integrator "
               "path, bdpt, vcm or light)",
               scene.file.string(), surface.object, scene.media[static_cast<std::size_t>(m)].name, integrator.name);
}

FilmBuffer make_film(const RenderScene& scene, bool keep_spectra, bool denoised) {
  std::vector<double> wavelengths;
  if (keep_spectra) {
    const auto basis = make_full_basis();
    wavelengths.assign(basis.wavelength_nm.begin(), basis.wavelength_nm.end());
  }
  const int w = scene.camera.width_px, h = scene.camera.height_px;
  require_memory(FilmBuffer::bytes_needed(w, h, wavelengths.size()) + (denoised ? denoise_bytes_needed(w, h) : 0),
                 fmt::format("{}: a {}x{} image{}{}", scene.file.string(), w, h, keep_spectra ? " with spectra" : "",
                             denoised ? ", denoised" : ""));
  FilmBuffer film(scene.camera.width_px, scene.camera.height_px, std::move(wavelengths));
  if (denoised) film.keep_halves();
  return film;
}

Film resolve(const FilmBuffer& film, int samples_done) {
  return film.resolve(samples_done > 0 ? 1.0 / samples_done : 0.0);
}

}  // namespace bouguer
