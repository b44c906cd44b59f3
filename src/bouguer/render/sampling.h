#pragma once
// Sampling and seeding shared by the estimators: every camera or light sample has its own random
// stream, seeded by (seed, pixel, sample index), so a render split into threads, sample ranges or
// pixel regions draws the very same numbers; the tile loop that runs pixels in parallel.
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "bouguer/render/integrator.h"
#include "bouguer/core/rng.h"

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

inline std::uint32_t permutation_element(std::uint32_t i, std::uint32_t n, std::uint32_t key);

// A pixel's index in the film, row-major: what seeds its samples (sample_rng) and strata.
inline std::uint64_t pixel_index(int x, int y, int width) {
  return static_cast<std::uint64_t>(y) * static_cast<std::uint64_t>(width) + static_cast<std::uint64_t>(x);
}

// Sample s of spp of the pixel `pixel` (y·width + x): the first m² samples fill an m×m grid of
// strata (m = ⌊√spp⌋) with one jittered point each, in an order permuted per pixel and seed, so
// that every prefix of them is spread over the whole pixel (a render cut short by --time or an
// interruption, or a pixel that adaptive sampling stops, sees all of it; taken in row order, the
// first samples of 1024 saw only its top row of strata, a shift of the image by almost half a
// pixel); the rest are uniform.
inline std::array<double, 2> subpixel(int s, int spp, std::uint64_t seed, std::uint64_t pixel, Rng& rng) {
  const int m = static_cast<int>(std::sqrt(static_cast<double>(spp)));
  const double jx = rng.next_double(), jy = rng.next_double();
  if (s >= m * m) return {jx, jy};
  const auto key = static_cast<std::uint32_t>((seed * 0x9e3779b97f4a7c15ULL + pixel) * 0xbf58476d1ce4e5b9ULL >> 32);
  const auto k = static_cast<int>(
      permutation_element(static_cast<std::uint32_t>(s), static_cast<std::uint32_t>(m * m), key));
  return {(k % m + jx) / m, (k / m + jy) / m};
}

// Element i of a pseudo-random permutation of [0, n) chosen by `key`, in O(1) and without
// storing the permutation (Kensler 2013, "Correlated Multi-Jittered Sampling": a hash that is a
// bijection on the next power of two, cycle-walked back into [0, n)). n ≤ 2³².
inline std::uint32_t permutation_element(std::uint32_t i, std::uint32_t n, std::uint32_t key) {
  std::uint32_t w = n - 1;
  w |= w >> 1, w |= w >> 2, w |= w >> 4, w |= w >> 8, w |= w >> 16;
  do {
    i ^= key, i *= 0xe170893du, i ^= key >> 16, i ^= (i & w) >> 4, i ^= key >> 8, i *= 0x0929eb3fu, i ^= key >> 23;
    i ^= (i & w) >> 1, i *= 1u | key >> 27, i *= 0x6935fa69u, i ^= (i & w) >> 11, i *= 0x74dcb303u, i ^= (i & w) >> 2;
    i *= 0x9e501cc3u, i ^= (i & w) >> 2, i *= 0xc860a3dfu, i &= w, i ^= i >> 5;
  } while (i >= n);
  return (i + key) % n;
}

// Wavelength numbers stratified over a pixel's samples: sample s gets (π(s) + offset) / spp for a
// permutation π of the strata chosen per pixel, so that the stratum is independent of the
// sub-pixel position, which is stratified by the sample index too: paired in index order, each
// wavelength would see its own part of the pixel, a bias at every edge where the image depends on
// wavelength (dispersion). Used for the hero wavelengths and for the wavelength a path keeps at a
// dispersive interface, and (with a salt of their own) for the hero of scattering media.
// O(1) per sample, so a sample range costs only its own samples.
class WavelengthStrata {
 public:
  // salt: an independent set of strata for another choice of the same samples (the hero wavelength).
  void reset(std::uint64_t seed, std::uint64_t pixel, int spp, std::uint64_t salt = 0) {
    Rng rng(seed ^ 0x9e3779b97f4a7c15ULL ^ (salt * 0xd1b54a32d192ed03ULL), pixel);
    offset_ = rng.next_double();
    key_ = rng.next_u32();
    spp_ = static_cast<std::uint32_t>(spp);
  }
  double u(int s) const {
    return (permutation_element(static_cast<std::uint32_t>(s), spp_, key_) + offset_) / static_cast<double>(spp_);
  }

 private:
  double offset_ = 0.0;
  std::uint32_t key_ = 0, spp_ = 1;
};

// Runs tile(region of at most 16×16 pixels, rays) over `region`, tiles in parallel (oneTBB), skipping
// the tiles not yet started once control.cancel is set; adds the rays traced to stats.
void for_each_tile(PixelRegion region, const RenderControl& control, RenderStats& stats,
                   const std::function<void(const PixelRegion& tile, std::uint64_t& rays)>& tile);

// Calls f(std::integral_constant<std::size_t, N>{}) with the number of values the mode carries.
template <typename F>
void with_carried_count(SpectralMode mode, F&& f);

}  // namespace bouguer

#include "bouguer/scene/spectral_tables.h"

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
