#include "bouguer/spectra/spectral_sampling.h"

#include <algorithm>
#include <cmath>

#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {

__attribute__((target_clones("avx2", "default"))) void mean_transmittance(const float* const sigma[kSubBins],
                                                                             std::size_t n, float length_m,
                                                                             float* out) {
  for (std::size_t i = 0; i < n; ++i) {
    float sum = 0.0f;
    for (int k = 0; k < kSubBins; ++k) sum += exp_nonpositive(-sigma[k][i] * length_m);
    out[i] = sum * (1.0f / kSubBins);
  }
}

__attribute__((target_clones("avx2", "default"))) void add_scaled(float* sum, const float* values, float scale,
                                                                     std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) sum[i] += values[i] * scale;
}

__attribute__((target_clones("avx2", "default"))) void weighted_sums3(const float* values,
                                                                         const float* const weight[3], std::size_t n,
                                                                         float out[3]) {
  for (int c = 0; c < 3; ++c) {
    float part[8] = {};
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8)
      for (std::size_t k = 0; k < 8; ++k) part[k] += weight[c][i + k] * values[i + k];
    for (; i < n; ++i) part[i % 8] += weight[c][i] * values[i];
    out[c] = ((part[0] + part[1]) + (part[2] + part[3])) + ((part[4] + part[5]) + (part[6] + part[7]));
  }
}

template <std::size_t N>
SampledSpectrum<N> SpectralBasis<N>::emission(const Spectrum& s) const {
  SampledSpectrum<N> out;
  if (mode == SpectralMode::rgb3) {
    const Vec3 rgb = xyz_to_linear_rgb(kRec709, spectrum_to_xyz(s));
    for (std::size_t i = 0; i < N && i < 3; ++i) out[i] = static_cast<float>(rgb[i]);
    return out;
  }
  for (std::size_t b = 0; b < N; ++b) {
    double sum = 0.0;
    for (int nm : bin_nm[b]) sum += eval(s, nm);
    out[b] = static_cast<float>(sum / static_cast<double>(bin_nm[b].size()));
  }
  return out;
}

template <std::size_t N>
SubBinValues<N> SpectralBasis<N>::at_sub_bins(const Spectrum& s) const {
  SubBinValues<N> out;
  for (int k = 0; k < kSubBins; ++k)
    for (std::size_t b = 0; b < N; ++b) {
      if (bin_nm[b].empty()) {  // not a binned mode: the point value
        out[k][b] = static_cast<float>(eval(s, wavelength_nm[b]));
        continue;
      }
      const double lo = bin_nm[b].front() - 0.5, width = static_cast<double>(bin_nm[b].size());
      out[k][b] = static_cast<float>(eval(s, lo + width * (k + 0.5) / kSubBins));
    }
  return out;
}

template <std::size_t N>
SampledSpectrum<N> SpectralBasis<N>::at_wavelengths(const Spectrum& s) const {
  SampledSpectrum<N> out;
  for (std::size_t i = 0; i < N; ++i) out[i] = static_cast<float>(eval(s, wavelength_nm[i]));
  return out;
}

template <std::size_t N>
Vec3 SpectralBasis<N>::to_linear_srgb(const SampledSpectrum<N>& v) const {
  if (mode == SpectralMode::rgb3) return {v[0], v[1], v[2]};
  Vec3 xyz;
  for (std::size_t b = 0; b < N; ++b) xyz += xyz_weight[b] * double(v[b]);
  return xyz_to_linear_rgb(kRec709, xyz);
}

template struct SpectralBasis<kFullBins>;
template struct SpectralBasis<3>;
template struct SpectralBasis<kHeroCount>;

double sample_visible_wavelength(double u) { return 538.0 - 138.888889 * std::atanh(0.85691062 - 1.82750197 * u); }

double visible_wavelength_pdf(double wavelength_nm) {
  if (wavelength_nm < kLambdaMinNm || wavelength_nm > kLambdaMaxNm) return 0.0;
  const double c = std::cosh(0.0072 * (wavelength_nm - 538.0));
  return 0.0039398042 / (c * c);
}

HeroWavelengths sample_hero_wavelengths(double u) {
  HeroWavelengths w;
  for (std::size_t i = 0; i < kHeroCount; ++i) {
    double ui = u + static_cast<double>(i) / kHeroCount;
    if (ui >= 1.0) ui -= 1.0;
    w.nm[i] = std::clamp(sample_visible_wavelength(ui), kLambdaMinNm, kLambdaMaxNm);
    w.pdf[i] = visible_wavelength_pdf(w.nm[i]);
  }
  return w;
}

Vec3 hero_to_xyz(const SampledSpectrum<kHeroCount>& radiance, const HeroWavelengths& w) {
  const ObserverTable& cmf = observer_table(Observer::cie1931_2deg);
  Vec3 xyz;
  for (std::size_t i = 0; i < kHeroCount; ++i) {
    if (radiance[i] == 0.0f || w.pdf[i] == 0.0) continue;
    const double x = w.nm[i] - kLambdaMinNm;
    const auto lo = std::min(static_cast<std::size_t>(x), static_cast<std::size_t>(kCmfCount - 2));
    const double t = x - static_cast<double>(lo);
    const Vec3 bar = Vec3{cmf.xbar[lo], cmf.ybar[lo], cmf.zbar[lo]} * (1.0 - t) +
                     Vec3{cmf.xbar[lo + 1], cmf.ybar[lo + 1], cmf.zbar[lo + 1]} * t;
    xyz += bar * (radiance[i] / (w.pdf[i] * cmf.ybar_sum));
  }
  return xyz / static_cast<double>(kHeroCount);
}

SpectralBasis<kFullBins> make_full_basis() {
  SpectralBasis<kFullBins> basis;
  basis.mode = SpectralMode::full;
  const double width = (kLambdaMaxNm - kLambdaMinNm + 1.0) / kFullBins;  // 471 one-nm samples
  const ObserverTable& cmf = observer_table(Observer::cie1931_2deg);
  for (int i = 0; i < kCmfCount; ++i) {
    const auto b = std::min(static_cast<std::size_t>(i / width), kFullBins - 1);
    basis.bin_nm[b].push_back(static_cast<int>(kLambdaMinNm) + i);
    basis.xyz_weight[b] += Vec3{cmf.xbar[i], cmf.ybar[i], cmf.zbar[i]} / cmf.ybar_sum;
  }
  for (std::size_t b = 0; b < kFullBins; ++b)
    basis.wavelength_nm[b] = 0.5 * (basis.bin_nm[b].front() + basis.bin_nm[b].back());
  // The split's bins: n·sqrt(mean of x̄ + ȳ + z̄/2 over the bin's n nanometres), plus a thousandth
  // of the largest in every bin, so that no walk's weight 1/(4·P) runs past about 5500 (the bins
  // beyond about 785 nm, which add next to nothing to the colour).
  double largest = 0.0, total = 0.0;
  for (std::size_t b = 0; b < kFullBins; ++b) {
    const Vec3& c = basis.xyz_weight[b];
    const double n = static_cast<double>(basis.bin_nm[b].size());
    basis.split_probability[b] = std::sqrt(n * std::max(0.0, c.x + c.y + 0.5 * c.z));
    largest = std::max(largest, basis.split_probability[b]);
  }
  for (double& p : basis.split_probability) total += (p += 1e-3 * largest);
  double sum = 0.0;
  for (std::size_t b = 0; b < kFullBins; ++b) {
    basis.split_probability[b] /= total;
    basis.split_cdf[b] = (sum += basis.split_probability[b]);
  }
  basis.split_cdf[kFullBins - 1] = 1.0;
  return basis;
}

SpectralBasis<3> make_rgb3_basis() {
  SpectralBasis<3> basis;
  basis.mode = SpectralMode::rgb3;
  for (std::size_t i = 0; i < 3; ++i) basis.wavelength_nm[i] = kRgb3WavelengthsNm[i];
  return basis;
}

}  // namespace bouguer
