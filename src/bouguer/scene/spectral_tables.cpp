#include "bouguer/scene/spectral_tables.h"

#include <algorithm>

#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {

double eval(const SceneSpectrum& s, double wavelength_nm) {
  if (const auto* spectrum = std::get_if<Spectrum>(&s.source)) return eval(*spectrum, wavelength_nm);
  return ior_at(std::get<IorModel>(s.source), wavelength_nm);
}

namespace {

template <std::size_t N>
SpectralBasis<N> basis_for(SpectralMode mode) {
  if constexpr (N == kFullBins) {
    if (mode == SpectralMode::full) return make_full_basis();
  } else if constexpr (N == 3) {
    if (mode == SpectralMode::rgb3) return make_rgb3_basis();
  }
  SpectralBasis<N> b;
  b.mode = mode;
  return b;
}

// The spectrum as the basis takes it in (spectral_sampling.h).
template <std::size_t N>
SampledSpectrum<N> fixed_values(const SceneSpectrum& s, const SpectralBasis<N>& basis) {
  const Spectrum spectrum = std::holds_alternative<Spectrum>(s.source)
                                ? std::get<Spectrum>(s.source)
                                : Spectrum{tabulate_visible([&](double nm) { return eval(s, nm); })};
  switch (s.role) {
    case SpectrumRole::radiance: return basis.emission(spectrum);
    case SpectrumRole::reflectance:
    case SpectrumRole::coefficient:
      return basis.mode == SpectralMode::rgb3 ? basis.at_wavelengths(spectrum) : basis.emission(spectrum);
    case SpectrumRole::point:
    case SpectrumRole::absorption: break;
  }
  SampledSpectrum<N> out;  // point values, from the source itself (an IOR model stays exact)
  for (std::size_t i = 0; i < N; ++i) out[i] = static_cast<float>(eval(s, basis.wavelength_nm[i]));
  return out;
}

}  // namespace

template <std::size_t N>
SpectralTables<N>::SpectralTables(const std::vector<SceneSpectrum>& spectra, SpectralMode mode)
    : mode_(mode), basis_(basis_for<N>(mode)) {
  for (const SceneSpectrum& s : spectra) {
    for (int i = 0; i < kCmfCount; ++i) dense_.push_back(static_cast<float>(eval(s, kLambdaMinNm + i)));
    if (mode == SpectralMode::hero) continue;
    fixed_.push_back(fixed_values(s, basis_));
    SubBinValues<N> sub{};
    if (mode == SpectralMode::full && s.role == SpectrumRole::absorption)
      sub = basis_.at_sub_bins(std::get<Spectrum>(s.source));
    sub_.push_back(sub);
  }
  if (mode == SpectralMode::full) {
    // XYZ per bin, then the XYZ → Rec.709 matrix, folded into one weight per bin and channel.
    for (std::size_t b = 0; b < N; ++b) {
      const Vec3 rgb = xyz_to_linear_rgb(kRec709, basis_.xyz_weight[b]);
      for (int c = 0; c < 3; ++c) rgb_weight_[c][b] = static_cast<float>(rgb[c]);
    }
    // The sigmoid factor of a texel is smooth: taken at the bin centre, D65 as its bin mean.
    env_white_ = basis_.emission(tabulate_visible(d65_unit_luminance));
  }
}

template <std::size_t N>
float SpectralTables<N>::at_nm(int id, double wavelength_nm) const {
  const double x = std::clamp(wavelength_nm - kLambdaMinNm, 0.0, kLambdaMaxNm - kLambdaMinNm);
  const auto lo = std::min(static_cast<std::size_t>(x), static_cast<std::size_t>(kCmfCount - 2));
  const auto t = static_cast<float>(x - static_cast<double>(lo));
  const float* v = dense_.data() + static_cast<std::size_t>(id) * kCmfCount;
  return v[lo] + t * (v[lo + 1] - v[lo]);
}

template <std::size_t N>
SampledWavelengths<N> SpectralTables<N>::wavelengths(double u) const {
  SampledWavelengths<N> w;
  w.mode = mode_;
  if (mode_ != SpectralMode::hero) {
    w.nm = basis_.wavelength_nm;
    return w;
  }
  const HeroWavelengths h = sample_hero_wavelengths(u);  // equal offsets: a stratified set
  for (std::size_t i = 0; i < N && i < kHeroCount; ++i) w.nm[i] = h.nm[i], w.pdf[i] = h.pdf[i];
  return w;
}

template <std::size_t N>
double SpectralTables<N>::kept_wavelength_nm(const SampledWavelengths<N>& w, int j, double u) const {
  const auto& bin = basis_.bin_nm[static_cast<std::size_t>(j)];
  if (mode_ != SpectralMode::full || bin.empty()) return w.nm[static_cast<std::size_t>(j)];
  return bin.front() - 0.5 + u * static_cast<double>(bin.size());
}

template <std::size_t N>
SampledSpectrum<N> SpectralTables<N>::environment(const EnvironmentMap& map, int texel,
                                                  const SampledWavelengths<N>& w) const {
  SampledSpectrum<N> l;
  const auto t = static_cast<std::size_t>(texel);
  if (mode_ == SpectralMode::rgb3) {
    const Vec3f& c = map.rgb[t];
    for (std::size_t i = 0; i < N && i < 3; ++i) l[i] = c[i];
    return l;
  }
  const RgbIlluminantSpectrum& s = map.spectra[t];
  auto at = [&](std::size_t i) {
    const float white = mode_ == SpectralMode::full ? env_white_[i] : static_cast<float>(d65_unit_luminance(w.nm[i]));
    return static_cast<float>(s.scale * s.poly(w.nm[i])) * white;
  };
  // A walk of one wavelength in full mode (a split, a dispersive interface) reads its own bin
  // alone, as transmittance() does: every other bin meets the zeros of its throughput. (A dense
  // walk's connections to the map took 96 sigmoids each: 7 % of the whole-milk glass.)
  if (mode_ == SpectralMode::full && w.secondary_terminated())
    return only_bin(w.single, at(static_cast<std::size_t>(w.single)));
  for (std::size_t i = 0; i < N; ++i) l[i] = at(i);
  return l;
}

template <std::size_t N>
Vec3 SpectralTables<N>::spectral_to_linear_rgb(const SampledSpectrum<N>& l, const SampledWavelengths<N>& w) const {
  switch (mode_) {
    case SpectralMode::rgb3: return {l[0], l[1], l[2]};  // (to_linear_rgb takes it inline)
    case SpectralMode::hero: {
      HeroWavelengths h;
      for (std::size_t i = 0; i < N && i < kHeroCount; ++i) h.nm[i] = w.nm[i], h.pdf[i] = w.pdf[i];
      SampledSpectrum<kHeroCount> v;
      for (std::size_t i = 0; i < N && i < kHeroCount; ++i) v[i] = l[i];
      return xyz_to_linear_rgb(kRec709, hero_to_xyz(v, h));
    }
    case SpectralMode::full: break;
  }
  const float* weight[3] = {rgb_weight_[0].data(), rgb_weight_[1].data(), rgb_weight_[2].data()};
  float rgb[3];
  weighted_sums3(l.v.data(), weight, N, rgb);
  return {rgb[0], rgb[1], rgb[2]};
}

template class SpectralTables<kFullBins>;
template class SpectralTables<3>;
template class SpectralTables<kHeroCount>;

}  // namespace bouguer
