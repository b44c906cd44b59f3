#include "bouguer/io/image.h"

#include <cassert>
#include <cmath>
#include <cstring>


namespace bouguer {

Film::Film(int width_px, int height_px, std::vector<double> spectrum_wavelengths_nm)
    : width(width_px),
      height(height_px),
      rgb(3 * static_cast<std::size_t>(width_px) * height_px, 0.0f),
      wavelengths_nm(std::move(spectrum_wavelengths_nm)),
      spectral(wavelengths_nm.size() * width_px * height_px, 0.0f) {
  assert(width_px >= 0 && height_px >= 0);
}

Vec3f Film::rgb_at(int x, int y) const {
  const std::size_t i = 3 * pixel_index(x, y);
  return {rgb[i], rgb[i + 1], rgb[i + 2]};
}

void Film::set_rgb(int x, int y, const Vec3f& value) {
  const std::size_t i = 3 * pixel_index(x, y);
  rgb[i] = value.x;
  rgb[i + 1] = value.y;
  rgb[i + 2] = value.z;
}

NonFinitePixels find_non_finite(const Film& film) {
  NonFinitePixels found;
  for (int y = 0; y < film.height; ++y)
    for (int x = 0; x < film.width; ++x) {
      const Vec3f rgb = film.rgb_at(x, y);
      bool finite = std::isfinite(rgb.x) && std::isfinite(rgb.y) && std::isfinite(rgb.z);
      if (film.has_spectra())
        for (float v : film.spectrum_at(x, y)) finite = finite && std::isfinite(v);
      if (finite) continue;
      if (found.count++ == 0) found.first_x = x, found.first_y = y;
    }
  return found;
}

std::span<float> Film::spectrum_at(int x, int y) {
  const std::size_t n = wavelengths_nm.size();
  return {spectral.data() + n * pixel_index(x, y), n};
}

std::span<const float> Film::spectrum_at(int x, int y) const {
  const std::size_t n = wavelengths_nm.size();
  return {spectral.data() + n * pixel_index(x, y), n};
}

}  // namespace bouguer
