#pragma once
// The wavelengths one path carries, per spectral mode, and how spectra enter and leave them.
//   full: kFullBins equal bins over 360–830 nm. Emission and reflectance enter as their mean over
//         the bin (1 nm samples); absorption and IOR are taken at the bin centre (they act through
//         exp(), which is not linear, so a mean would be wrong too); colour leaves through the CIE
//         1931 functions summed over each bin's 1 nm samples: XYZ = Σ_b L_b Σ_{λ∈b} x̄(λ) / Σ ȳ.
//   rgb3: the paper's RGB approach: 700.0, 546.1, 435.8 nm used directly as R, G, B. Emitters enter
//         as their linear sRGB colour; absorption and reflectance are taken at the three wavelengths.
#include <array>
#include <cstddef>
#include <vector>

#include "bouguer/core/math.h"
#include "bouguer/spectra/sampled_wavelengths.h"
#include "bouguer/spectra/sampled_spectrum.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

// 96 bins of 4.9 nm, with σ_a at 4 points per bin, keep the binning error below ΔE00 0.06 on the
// paper's materials and below 0.14 on the whole library over its usual thicknesses (see
// tests/unit/test_spectral_sampling.cpp, which measures it); 48 bins with σ_a at the centre
// reached 0.6 on the dyes. A multiple of 16 for SIMD.
inline constexpr std::size_t kFullBins = 96;
inline constexpr std::array<double, 3> kRgb3WavelengthsNm = {700.0, 546.1, 435.8};

// Full mode: σ_a is also taken at kSubBins points inside each bin, and a bin's transmittance is
// the mean of their exp(−σ_a l) rather than the value at the centre: exp is convex, and a steep
// absorption edge inside a bin is misjudged by its centre (ΔE00 up to 0.6 on the dyes' slabs
// with 48 bins and the centre only). Measured alternatives: 2 points per bin, or σ_a linear
// between the bin's edges (exact mean in closed form), leave 0.45 and 0.37 on the library over
// its usual thicknesses; 4 points leave 0.13 (tests/unit/test_spectral_sampling.cpp).
inline constexpr int kSubBins = 4;

template <std::size_t N>
using SubBinValues = std::array<SampledSpectrum<N>, kSubBins>;

// sum[i] += values[i]·scale for i < n (the optical depths of several absorbers on a segment),
// compiled for AVX2 and the baseline like mean_transmittance.
void add_scaled(float* sum, const float* values, float scale, std::size_t n);

// out[i] = mean over k of exp(−sigma[k][i] · length_m), i < n. Compiled for AVX2 and for the
// baseline, chosen at load time (the hottest loop of full mode in absorbing media).
void mean_transmittance(const float* const sigma[kSubBins], std::size_t n, float length_m, float* out);

// out[c] = Σ_i weight[c][i] · values[i] for c < 3, i < n, with eight partial sums in a fixed order
// (the same in every run), compiled for AVX2 and the baseline: a full-mode sample's colour,
// computed for every camera sample.
void weighted_sums3(const float* values, const float* const weight[3], std::size_t n, float out[3]);

// The mean over the sub-bin points of exp(−σ_a l), per bin.
template <std::size_t N>
SampledSpectrum<N> sub_bin_transmittance(const SubBinValues<N>& sigma_a_per_m, float length_m) {
  SampledSpectrum<N> t;
  const float* sigma[kSubBins];
  for (int k = 0; k < kSubBins; ++k) sigma[k] = sigma_a_per_m[k].v.data();
  mean_transmittance(sigma, N, length_m, t.v.data());
  return t;
}

template <std::size_t N>
struct SpectralBasis {
  SpectralMode mode = SpectralMode::full;
  std::array<double, N> wavelength_nm{};  // bin centres (full) or the three lines (rgb3)
  std::array<Vec3, N> xyz_weight{};       // full: CMF sums over the bin divided by Σ ȳ
  std::array<std::vector<int>, N> bin_nm; // full: the integer wavelengths of each bin
  // full: the probability with which a walk split at a dense chromatic medium draws each bin
  // (dense_media.h: keep_split_wavelength), and its running sum (the last 1). Its density per nm
  // goes as sqrt(x̄ + ȳ + z̄/2): the split's walks of different wavelengths correlate only in part
  // (a curved wall parts them), so the colour's noise (which CIEDE2000 weighs more than lightness
  // near white) is least when the bins that decide x and z are drawn more often than the
  // eye-sensitivity density draws them (docs/performance.md, "The split's wavelengths").
  std::array<double, N> split_probability{};
  std::array<double, N> split_cdf{};

  SampledSpectrum<N> emission(const Spectrum& s) const;  // radiance, reflectance: bin means / sRGB
  SampledSpectrum<N> at_wavelengths(const Spectrum& s) const;  // σ_a, IOR: point values
  SubBinValues<N> at_sub_bins(const Spectrum& s) const;        // full: kSubBins points per bin
  Vec3 to_linear_srgb(const SampledSpectrum<N>& v) const;
};

// hero: kHeroCount wavelengths per camera sample (Wilkie et al. 2014): the hero drawn from a
//       density that follows the eye's sensitivity over 360–830 nm (the one pbrt-v4 uses,
//       ∝ 1/cosh²(0.0072 (λ − 538 nm))), the others at equal offsets of its uniform number, so the
//       set is stratified. Spectra are evaluated at the wavelengths themselves; a sample's colour is
//       XYZ = (1/H) Σ_i L(λ_i) x̄(λ_i) / (p(λ_i) Σ ȳ).
inline constexpr std::size_t kHeroCount = 4;

double sample_visible_wavelength(double u);
double visible_wavelength_pdf(double wavelength_nm);

struct HeroWavelengths {
  std::array<double, kHeroCount> nm{};
  std::array<double, kHeroCount> pdf{};
};
HeroWavelengths sample_hero_wavelengths(double u);
Vec3 hero_to_xyz(const SampledSpectrum<kHeroCount>& radiance, const HeroWavelengths& w);

SpectralBasis<kFullBins> make_full_basis();
SpectralBasis<3> make_rgb3_basis();

}  // namespace bouguer
