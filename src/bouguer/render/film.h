#pragma once
// The image a render produces: linear Rec.709 (D65 white) floats, three per pixel, rows from the
// top; optionally each pixel's spectrum at `wavelengths_nm` (radiance in the emitters' units: a
// named illuminant with scale 1 has luminance Y = 1, see spectra/cie.h).
#include <cstddef>
#include <span>
#include <vector>

#include "bouguer/core/math.h"

namespace bouguer {

struct Film {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;              // 3 * width * height
  std::vector<double> wavelengths_nm;  // empty when the film keeps no spectra
  std::vector<float> spectral;         // wavelengths_nm.size() * width * height, pixel-interleaved

  Film() = default;
  Film(int width_px, int height_px, std::vector<double> spectrum_wavelengths_nm = {});

  bool has_spectra() const { return !wavelengths_nm.empty(); }
  std::size_t pixel_index(int x, int y) const { return static_cast<std::size_t>(y) * width + x; }

  Vec3f rgb_at(int x, int y) const;
  void set_rgb(int x, int y, const Vec3f& value);
  std::span<float> spectrum_at(int x, int y);
  std::span<const float> spectrum_at(int x, int y) const;
};

}  // namespace bouguer
