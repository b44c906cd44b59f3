#include "bouguer/render/film.h"

#include <cassert>
#include <cmath>

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

namespace bouguer {

FilmBuffer::FilmBuffer(int width_px, int height_px, std::vector<double> spectrum_wavelengths_nm)
    : width_(width_px), height_(height_px), wavelengths_nm_(std::move(spectrum_wavelengths_nm)) {
  const auto pixels = static_cast<std::size_t>(width_px) * static_cast<std::size_t>(height_px);
  rgb_sum_.assign(3 * pixels, 0.0);
  weight_sum_.assign(pixels, 0.0);
  splat_rgb_.assign(3 * pixels, 0);
  spectral_sum_.assign(wavelengths_nm_.size() * pixels, 0.0);
  splat_spectral_.assign(wavelengths_nm_.size() * pixels, 0);
}

std::uint64_t FilmBuffer::bytes_needed(int width_px, int height_px, std::size_t spectrum_wavelengths) {
  const auto pixels = static_cast<std::uint64_t>(width_px) * static_cast<std::uint64_t>(height_px);
  const std::uint64_t n = spectrum_wavelengths;
  const std::uint64_t buffer = 7 * sizeof(double) + n * (sizeof(double) + sizeof(std::int64_t));
  const std::uint64_t film = 3 * sizeof(float) + n * sizeof(float);
  const std::uint64_t writers = 3 * sizeof(float) + n * sizeof(float);  // one converted copy at a time
  return pixels * (buffer + film + writers);
}

void FilmBuffer::add_fixed(std::int64_t& cell, double value) {
  const double units = value / kSplatUnit;
  if (!(std::abs(units) < 9.0e15)) {  // NaN, or beyond what one cell can hold exactly
    saturated_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  std::atomic_ref<std::int64_t>(cell).fetch_add(std::llround(units), std::memory_order_relaxed);
}

void FilmBuffer::add_splat(double film_x, double film_y, const Vec3& rgb, std::span<const float> spectrum) {
  const int x = static_cast<int>(film_x), y = static_cast<int>(film_y);
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
  const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
  for (std::size_t c = 0; c < 3; ++c) add_fixed(splat_rgb_[3 * p + c], rgb[c]);
  const std::size_t n = wavelengths_nm_.size();
  for (std::size_t i = 0; i < n && i < spectrum.size(); ++i) add_fixed(splat_spectral_[n * p + i], spectrum[i]);
}

Film FilmBuffer::resolve(double splat_scale) const {
  Film film(width_, height_, wavelengths_nm_);
  const std::size_t n = wavelengths_nm_.size();
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x) {
      const std::size_t p = film.pixel_index(x, y);
      const double w = weight_sum_[p];
      auto value = [&](double sum, std::int64_t splat) {
        return static_cast<float>((w > 0.0 ? sum / w : 0.0) + static_cast<double>(splat) * kSplatUnit * splat_scale);
      };
      film.set_rgb(x, y, {value(rgb_sum_[3 * p], splat_rgb_[3 * p]), value(rgb_sum_[3 * p + 1], splat_rgb_[3 * p + 1]),
                          value(rgb_sum_[3 * p + 2], splat_rgb_[3 * p + 2])});
      auto spectrum = film.spectrum_at(x, y);
      for (std::size_t i = 0; i < n; ++i) spectrum[i] = value(spectral_sum_[n * p + i], splat_spectral_[n * p + i]);
    }
  return film;
}

}  // namespace bouguer
