#include "bouguer/render/film.h"

#include <cassert>

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

std::span<float> Film::spectrum_at(int x, int y) {
  const std::size_t n = wavelengths_nm.size();
  return {spectral.data() + n * pixel_index(x, y), n};
}

std::span<const float> Film::spectrum_at(int x, int y) const {
  const std::size_t n = wavelengths_nm.size();
  return {spectral.data() + n * pixel_index(x, y), n};
}

}  // namespace bouguer
