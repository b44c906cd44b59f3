#pragma once
// One interface for every estimator: render a pixel region and a sample range of a compiled scene
// into a film. Each sample is seeded by (seed, pixel, sample index), so any split of the work —
// threads, sample ranges rendered one after another into one film, pixel regions, processes that
// each render whole pixels (distributed/) — gives the bit-identical image. The name → integrator and name → spectral mode tables are in
// scene/render_modes.h; each integrator's render function is bound to its name in
// integrators/render_into.cpp.
#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "bouguer/render/film.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/render_modes.h"

namespace bouguer {

class PathGuide;
class ShellSet;

struct PixelRegion {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // [x0, x1) × [y0, y1)
  static PixelRegion whole(const CameraDesc& c) { return {0, 0, c.width_px, c.height_px}; }
};

struct SampleRange {
  int begin = 0, end = 0;  // sample indices [begin, end) of every pixel, of the settings' spp
};

struct RenderControl {
  int threads = 0;  // 0: all cores
  // Set (from a signal handler) to stop: tiles not yet started are skipped.
  const std::atomic<bool>* cancel = nullptr;
  // Called now and then with the fraction of this call's tiles done (from any thread).
  std::function<void(double fraction_done)> progress;
  // Adaptive sampling (render/adaptive.h): one flag per pixel, row-major; the pixels flagged 0
  // take no more samples. Null: every pixel does. Only the estimators whose samples stay in their
  // pixel read it (those without splats: IntegratorInfo::splats).
  const std::vector<std::uint8_t>* active = nullptr;
  // Path guiding (render/path_guide.h, integrators/guiding.h): what the path tracer draws a share
  // of its directions from, trained before the render. Null: unguided.
  const PathGuide* guide = nullptr;
  // The path tracer's shell-transport tables (integrators/shell_hops.h), made once where a caller
  // renders the same samples in many pieces (distributed.cpp); null, or not covering the call's
  // samples: each call makes its own.
  const ShellSet* shells = nullptr;
};

struct RenderStats {
  double seconds = 0.0;
  std::uint64_t rays = 0;
  // vcm: its iterations, the light subpaths they traced, the photons they kept, the merges made,
  // the radius of the last iteration and the most memory an iteration's kept light subpaths held.
  int iterations = 0;
  std::uint64_t light_paths = 0, photons = 0, merges = 0;
  double radius_m = 0.0;
  std::uint64_t light_subpath_bytes = 0;
};

using RenderFn = void (*)(const RenderScene&, const RenderSettings&, FilmBuffer&, PixelRegion, SampleRange,
                          const RenderControl&, RenderStats&);


}  // namespace bouguer
