#pragma once
// The image a render produces (the film resolved; render/film.h accumulates it), as the image
// writers take it: linear Rec.709 (D65 white) floats, three per pixel, rows from the
// top; optionally each pixel's spectrum at `wavelengths_nm` (radiance in the emitters' units: a
// named illuminant with scale 1 has luminance Y = 1, see spectra/cie.h).
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
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

// Pixels holding NaN or infinity in any channel or spectrum value: how many, and the first in
// reading order (for the one line `bouguer render` prints instead of writing such an image).
struct NonFinitePixels {
  std::size_t count = 0;
  int first_x = -1, first_y = -1;
};
NonFinitePixels find_non_finite(const Film& film);

}  // namespace bouguer
