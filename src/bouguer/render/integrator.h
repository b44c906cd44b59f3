#pragma once
// One interface for every estimator: render a pixel region and a sample range of a compiled scene
// into a film. Each sample is seeded by (seed, pixel, sample index), so any split of the work —
// threads, sample ranges rendered one after another into one film, pixel regions, processes that
// each render whole pixels (distributed/) — gives the bit-identical image. The name → integrator and name → spectral mode tables below are the only
// lists of them: the scene loader, the command line and the documentation read these.
#include <atomic>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <string_view>

#include "bouguer/render/film.h"
#include "bouguer/scene/compile.h"

namespace bouguer {

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
};

struct RenderStats {
  double seconds = 0.0;
  std::uint64_t rays = 0;
  // vcm: its iterations, the light subpaths they traced, the photons they kept, the merges made
  // and the radius of the last iteration.
  int iterations = 0;
  std::uint64_t light_paths = 0, photons = 0, merges = 0;
  double radius_m = 0.0;
};

using RenderFn = void (*)(const RenderScene&, const RenderSettings&, FilmBuffer&, PixelRegion, SampleRange,
                          const RenderControl&, RenderStats&);

struct IntegratorInfo {
  IntegratorType type;
  std::string_view name;
  std::string_view summary;
  RenderFn render;
  bool rough_interfaces;  // whether it handles rough dielectric interfaces
  bool splats;            // whether its light arrives through the film's splat buffer
  bool scattering_media;  // whether it renders media that scatter
};

std::span<const IntegratorInfo> integrator_table();
const IntegratorInfo* find_integrator(std::string_view name);
const IntegratorInfo& integrator_info(IntegratorType type);

struct SpectralModeInfo {
  SpectralMode mode;
  std::string_view name;
  std::string_view summary;
};
std::span<const SpectralModeInfo> spectral_mode_table();
const SpectralModeInfo* find_spectral_mode(std::string_view name);
std::string_view spectral_mode_name(SpectralMode mode);

// "a, b or c": the names of a table, for messages and help texts.
std::string integrator_names();
std::string spectral_mode_names();

}  // namespace bouguer
