#pragma once
// The tile loop: every pixel's samples, tiles in parallel (oneTBB), each pixel with its own
// random stream seeded from (seed, pixel), so the image never depends on the thread count.
#include <cstdint>
#include <functional>

#include "bouguer/render/film.h"
#include "bouguer/scene/compile.h"

namespace bouguer {

struct RenderOptions {
  int threads = 0;             // 0: all cores
  bool keep_spectra = false;   // film keeps each pixel's spectrum (full mode only)
  // Called now and then with the fraction done (from whichever thread finished a tile).
  std::function<void(double fraction_done)> progress;
};

struct RenderStats {
  double seconds = 0.0;
  std::uint64_t rays = 0;
};

Film render(const RenderScene& scene, const RenderOptions& options, RenderStats& stats);

}  // namespace bouguer
