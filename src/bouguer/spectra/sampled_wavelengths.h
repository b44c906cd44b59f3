#pragma once
// The wavelengths one path carries, made per camera (or light) sample and passed to every
// evaluation: a path owns them, no integrator or scene object does.
//   full: the bin centres of kFullBins equal bins (every path the same),
//   rgb3: the paper's 700.0, 546.1 and 435.8 nm (every path the same),
//   hero: kHeroCount wavelengths drawn per sample, with the density each was drawn with.
// At the first dispersive interface a path keeps one wavelength (terminate_secondary): from there
// on `single` names it and `single_nm` is the wavelength its geometry follows (in full mode drawn
// uniformly within the kept bin, which stands for all its wavelengths).
#include <array>
#include <cstddef>

namespace bouguer {

enum class SpectralMode { full, rgb3, hero };

template <std::size_t N>
struct SampledWavelengths {
  SpectralMode mode = SpectralMode::full;
  std::array<double, N> nm{};   // the carried wavelengths (bin centres, the three lines, or drawn)
  std::array<double, N> pdf{};  // hero: density per nm of each draw; 0 in the fixed modes
  int single = -1;              // the one wavelength left after a dispersive interface, or -1
  double single_nm = 0.0;
  // The carried wavelength whose majorant draws distances in scattering media
  // (media/scattering.h), drawn per sample (integrators/events.h: draw_hero; the path tracer's
  // stratified over the pixel's samples).
  int hero = 0;
  // Places the bins of full mode's split at a dense chromatic medium (integrators/dense_media.h:
  // keep_split_wavelength): uniform, independent of the hero; the path tracer's stratified.
  double split_u = 0.0;

  // Whether the values at the carried wavelengths are the same for every path (full, rgb3), so
  // spectra can be taken from tables precomputed for the mode.
  bool fixed() const { return mode != SpectralMode::hero; }
  bool secondary_terminated() const { return single >= 0; }
  void terminate_secondary(int kept, double kept_nm) {
    single = kept;
    single_nm = kept_nm;
  }
};

}  // namespace bouguer
