#pragma once
// Sampling and seeding shared by the estimators: every camera or light sample has its own random
// stream, seeded by (seed, pixel, sample index), so a render split into threads, sample ranges or
// pixel regions draws the very same numbers; the tile loop that runs pixels in parallel.
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numeric>
#include <vector>

#include "bouguer/render/integrator.h"
#include "bouguer/render/rng.h"

namespace bouguer {

// The stream of sample `sample` of pixel `pixel` (pixel = y·width + x). `salt` separates the
// streams of different estimators (camera and light paths).
inline Rng sample_rng(std::uint64_t seed, std::uint64_t pixel, int sample, std::uint64_t salt = 0) {
  auto mix = [](std::uint64_t z) {  // splitmix64's finaliser
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  };
  const std::uint64_t key = (pixel << 21) ^ static_cast<std::uint64_t>(sample) ^ (salt << 60);
  return Rng(mix(seed ^ mix(key)), key);
}

// Sample s of spp: the first m² samples fill an m×m grid of strata (m = ⌊√spp⌋) with one
// jittered point each; the rest are uniform.
inline std::array<double, 2> subpixel(int s, int spp, Rng& rng) {
  const int m = static_cast<int>(std::sqrt(static_cast<double>(spp)));
  const double jx = rng.next_double(), jy = rng.next_double();
  if (s < m * m) return {(s % m + jx) / m, (s / m + jy) / m};
  return {jx, jy};
}

// Wavelength numbers stratified over a pixel's samples: sample s gets (order[s] + offset) / spp.
// The order is shuffled per pixel, on a stream of its own, so that the stratum is independent of
// the sub-pixel position, which is stratified by the sample index too: paired in index order,
// each wavelength would see its own part of the pixel, a bias at every edge where the image
// depends on wavelength (dispersion). Used for the hero wavelengths and for the wavelength a path
// keeps at a dispersive interface.
class WavelengthStrata {
 public:
  // Prepares pixel `pixel`'s order; the object is reused from pixel to pixel (no allocation).
  void reset(std::uint64_t seed, std::uint64_t pixel, int spp) {
    Rng rng(seed ^ 0x9e3779b97f4a7c15ULL, pixel);
    offset_ = rng.next_double();
    order_.resize(static_cast<std::size_t>(spp));
    std::iota(order_.begin(), order_.end(), 0);
    for (int i = spp - 1; i > 0; --i) {  // Fisher–Yates, the bound by multiply-shift (Lemire 2019)
      const auto j = static_cast<std::size_t>((static_cast<std::uint64_t>(rng.next_u32()) * static_cast<std::uint64_t>(i + 1)) >> 32);
      std::swap(order_[static_cast<std::size_t>(i)], order_[j]);
    }
  }
  double u(int s) const { return (order_[static_cast<std::size_t>(s)] + offset_) / static_cast<double>(order_.size()); }

 private:
  std::vector<int> order_;
  double offset_ = 0.0;
};

// Runs tile(region of ≤ 16×16 pixels, rays) over `region`, tiles in parallel (oneTBB), skipping
// the tiles not yet started once control.cancel is set; adds the rays traced to stats.
void for_each_tile(PixelRegion region, const RenderControl& control, RenderStats& stats,
                   const std::function<void(const PixelRegion& tile, std::uint64_t& rays)>& tile);

// Calls f(std::integral_constant<std::size_t, N>{}) with the number of values the mode carries.
template <typename F>
void with_carried_count(SpectralMode mode, F&& f);

}  // namespace bouguer

#include "bouguer/render/spectral_tables.h"

namespace bouguer {
template <typename F>
void with_carried_count(SpectralMode mode, F&& f) {
  switch (mode) {
    case SpectralMode::full: f(std::integral_constant<std::size_t, kFullBins>{}); break;
    case SpectralMode::rgb3: f(std::integral_constant<std::size_t, 3>{}); break;
    case SpectralMode::hero: f(std::integral_constant<std::size_t, kHeroCount>{}); break;
  }
}
}  // namespace bouguer
