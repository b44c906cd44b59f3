#pragma once
// Accumulating a render: FilmBuffer, resolved into the Film image of io/image.h.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "bouguer/core/math.h"
#include "bouguer/io/image.h"

namespace bouguer {

// What one render accumulates, pixel by pixel: weighted sums of camera samples and a splat
// buffer for light paths that land anywhere on the film; resolve() turns them into the image.
// Deterministic under any split of the work: a pixel's samples are added by one thread at a time
// in sample order (so sample ranges rendered one after another sum in the same order as one
// render), and splats are added as fixed-point integers (so their sum does not depend on the
// order threads add them in).
// Across processes: each renders whole pixels (every sample of the pixel regions it is given)
// into a film of the full size, and merge() adds the films: a pixel's camera sums come from the
// one film that has them (adding zero is exact), the splats as integers (exact in any order,
// wrapping as the atomic adds of one process do), so the merged film is bit for bit the film of
// one process (tests/unit/test_film_merge.cpp).
class FilmBuffer {
 public:
  FilmBuffer(int width_px, int height_px, std::vector<double> spectrum_wavelengths_nm = {});
  FilmBuffer(FilmBuffer&& other) noexcept;

  // The most wavelengths a film's spectra may have (the full mode keeps 96).
  static constexpr std::size_t kMaxSpectrumWavelengths = 4096;

  // The memory a render of this size takes for its image: this buffer, the resolved Film and the
  // image writers' conversion buffers (what make_film checks before allocating).
  static std::uint64_t bytes_needed(int width_px, int height_px, std::size_t spectrum_wavelengths);

  int width() const { return width_; }
  int height() const { return height_; }
  bool has_spectra() const { return !wavelengths_nm_.empty(); }

  // One camera sample of pixel (x, y): its linear Rec.709 value and, when the film keeps
  // spectra, its values at the spectrum wavelengths. `odd`: an odd-numbered sample (kept apart
  // too where the film keeps halves).
  void add_sample(int x, int y, const Vec3& rgb, double weight, std::span<const float> spectrum = {},
                  bool odd = false) {
    const std::size_t p = static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x);
    for (std::size_t c = 0; c < 3; ++c) rgb_sum_[3 * p + c] += weight * rgb[c];
    weight_sum_[p] += weight;
    const std::size_t n = wavelengths_nm_.size();
    for (std::size_t i = 0; i < n && i < spectrum.size(); ++i) spectral_sum_[n * p + i] += weight * spectrum[i];
    if (odd && !odd_weight_sum_.empty()) {
      for (std::size_t c = 0; c < 3; ++c) odd_rgb_sum_[3 * p + c] += weight * rgb[c];
      odd_weight_sum_[p] += weight;
    }
  }

  // Adaptive sampling (render/adaptive.h): from now on the odd-numbered camera samples are also
  // summed apart, so that every pixel has two independent half estimates (Cycles' two buffers).
  // Not serialised: a film that keeps halves is not merged across processes.
  void keep_halves();
  bool keeps_halves() const { return !odd_weight_sum_.empty(); }
  // The camera samples' weight in pixel (x, y) (camera samples weigh 1: their count).
  double weight_at(int x, int y) const {
    return weight_sum_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x)];
  }
  // The weight of its odd-numbered camera samples (keeps_halves; else 0).
  double odd_weight_at(int x, int y) const {
    return keeps_halves() ? odd_weight_sum_[static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
                                            static_cast<std::size_t>(x)]
                          : 0.0;
  }
  // The means of the pixel's even- and odd-numbered samples (keeps_halves; zero where a half has
  // none).
  std::array<Vec3, 2> half_means(int x, int y) const;
  // Light arriving at a film position (pixels) from a light path; safe from any thread.
  void add_splat(double film_x, double film_y, const Vec3& rgb, std::span<const float> spectrum = {});

  // The image: each pixel's weighted mean plus its splats times splat_scale (1 / light paths per
  // pixel). Splats that did not fit the fixed-point range are counted in saturated_splats().
  Film resolve(double splat_scale) const;
  std::uint64_t saturated_splats() const { return saturated_.load(); }

  // Adds another film of the same size and wavelengths. The pixels with camera samples must be
  // in one of the two films only (an Error names the first pixel in both): then the result is
  // exactly the film one render of both parts gives.
  void merge(const FilmBuffer& other);

  // Every sum in a flat byte layout of the native byte order (a header that names the size and
  // wavelengths, then the arrays), and back: deserialise checks the header against the limits
  // and the byte count against the header before allocating, so a truncated or hostile buffer is
  // an Error naming `source`, never a crash or an allocation the bytes do not pay for.
  std::vector<std::byte> serialise() const;
  std::uint64_t serialised_bytes() const;
  static FilmBuffer deserialise(std::span<const std::byte> bytes, std::string_view source);

 private:
  static constexpr double kSplatUnit = 1.0 / (1 << 20);  // fixed-point step of the splat sums
  void add_fixed(std::int64_t& cell, double value);

  int width_ = 0, height_ = 0;
  std::vector<double> wavelengths_nm_;
  std::vector<double> rgb_sum_, weight_sum_, spectral_sum_;
  std::vector<double> odd_rgb_sum_, odd_weight_sum_;  // keep_halves
  std::vector<std::int64_t> splat_rgb_, splat_spectral_;
  std::atomic<std::uint64_t> saturated_{0};
};

}  // namespace bouguer
