#pragma once
// Every spectrum of a compiled scene, made ready for one spectral mode at the start of a render:
// flat tables read per event with the path's own SampledWavelengths.
//   fixed modes (full, rgb3): the values at the mode's wavelengths, computed once (radiance and
//     reflectance as bin means in full mode, absorption also at kSubBins points per bin);
//   any mode: a 1 nm table over 360–830 nm, for wavelengths drawn per path (hero) and the one
//     wavelength a path keeps after a dispersive interface.
#include <cstddef>
#include <span>
#include <variant>
#include <vector>

#include "bouguer/core/math.h"
#include "bouguer/media/ior.h"
#include "bouguer/media/optical_depth.h"
#include "bouguer/spectra/spectral_sampling.h"
#include "bouguer/spectra/sampled_wavelengths.h"
#include "bouguer/lights/environment.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

// How a spectrum enters the carried wavelengths (spectral_sampling.h): radiance as bin means
// (rgb3: its linear sRGB colour), reflectance and scattering coefficients as bin means (rgb3: the
// values at the three lines), point quantities (n, k) at the wavelengths, absorption at the
// wavelengths and the sub-bins.
enum class SpectrumRole { radiance, reflectance, coefficient, point, absorption };

struct SceneSpectrum {
  std::variant<Spectrum, IorModel> source;
  SpectrumRole role = SpectrumRole::point;
};

double eval(const SceneSpectrum& s, double wavelength_nm);

template <std::size_t N>
class SpectralTables {
 public:
  SpectralTables(const std::vector<SceneSpectrum>& spectra, SpectralMode mode);

  // The spectrum `id` at the path's wavelengths.
  SampledSpectrum<N> at(int id, const SampledWavelengths<N>& w) const {
    if (w.fixed()) return fixed_[static_cast<std::size_t>(id)];
    SampledSpectrum<N> s;
    for (std::size_t i = 0; i < N; ++i) s[i] = at_nm(id, w.nm[i]);
    return s;
  }
  // Its value at carried wavelength j alone (at(id, w)[j], without the others: a walk of one
  // wavelength).
  float at_index(int id, const SampledWavelengths<N>& w, std::size_t j) const {
    if (w.fixed()) return fixed_[static_cast<std::size_t>(id)][j];
    return at_nm(id, w.nm[j]);
  }
  // At any wavelength (linear between whole nanometres, held beyond 360–830 nm).
  float at_nm(int id, double wavelength_nm) const;
  // exp(−σ_a·l) for the absorption spectrum `id` (full mode: the mean over the sub-bin points).
  SampledSpectrum<N> transmittance(int id, double length_m, const SampledWavelengths<N>& w) const {
    const auto l = static_cast<float>(length_m);
    if (mode_ == SpectralMode::full) {
      const SubBinValues<N>& sigma = sub_[static_cast<std::size_t>(id)];
      if (w.secondary_terminated())
        return only_bin(w.single, kept_bin_mean(w.single, [&](int k, std::size_t j) { return sigma[k][j] * l; }));
      return sub_bin_transmittance(sigma, l);
    }
    return beer_lambert_transmittance(at(id, w), l);
  }
  // exp(−Σ_k σ_k·l_k) for several absorbers on one segment (each term: an absorption spectrum id
  // and a length, or an ε id and a column density). Full mode sums the exponents at each sub-bin
  // point before the mean, as for one absorber.
  SampledSpectrum<N> transmittance(std::span<const OpticalDepthTerm> terms, const SampledWavelengths<N>& w) const {
    if (mode_ == SpectralMode::full) {
      if (w.secondary_terminated()) return only_bin(w.single, kept_transmittance(terms, w));
      SubBinValues<N> sum{};
      for (const OpticalDepthTerm& t : terms) {
        const auto l = static_cast<float>(t.length);
        const SubBinValues<N>& sigma = sub_[static_cast<std::size_t>(t.id)];
        for (int k = 0; k < kSubBins; ++k) add_scaled(sum[k].v.data(), sigma[k].v.data(), l, N);
      }
      return sub_bin_transmittance(sum, 1.0f);
    }
    SampledSpectrum<N> sum{};
    for (const OpticalDepthTerm& t : terms) sum += at(t.id, w) * static_cast<float>(t.length);
    return beer_lambert_transmittance(sum, 1.0f);
  }

  // The same at the one wavelength a walk still carries (w.secondary_terminated()), bit for bit
  // that bin of transmittance(terms, w): a dense walk takes it at every collision, without the
  // spectrum of zeros around it.
  float kept_transmittance(std::span<const OpticalDepthTerm> terms, const SampledWavelengths<N>& w) const {
    if (mode_ == SpectralMode::full)
      return kept_bin_mean(w.single, [&](int k, std::size_t j) {
        float depth = 0.0f;  // the same sums, in the same order, as add_scaled's
        for (const OpticalDepthTerm& t : terms) depth += sub_[static_cast<std::size_t>(t.id)][k][j] * static_cast<float>(t.length);
        return depth;
      });
    return transmittance(terms, w)[static_cast<std::size_t>(w.single)];
  }

  // A new path's wavelengths: the mode's fixed set, or kHeroCount drawn from the stratified u.
  SampledWavelengths<N> wavelengths(double u) const;
  // The same into `w`, which a previous path used (cheaper: the fixed set is not copied again).
  // Inline, as is to_linear_rgb's rgb3 case: both run once per sample.
  void restart(SampledWavelengths<N>& w, double u) const {
    if (mode_ != SpectralMode::hero && w.mode == mode_) {
      w.single = -1;
      w.single_nm = 0.0;
      return;
    }
    w = wavelengths(u);
  }
  // The wavelength kept at a dispersive interface by carried index j (full: uniform in bin j).
  double kept_wavelength_nm(const SampledWavelengths<N>& w, int j, double u) const;
  // The radiance of an environment texel (environment.h): its RGB lifted to a spectrum times D65
  // at the wavelengths (full: D65's bin means; a walk of one wavelength gets its bin alone, zeros
  // elsewhere, as transmittance()); rgb3 takes the texel's RGB directly.
  SampledSpectrum<N> environment(const EnvironmentMap& map, int texel, const SampledWavelengths<N>& w) const;
  // Linear Rec.709 of one sample's spectrum at its wavelengths.
  Vec3 to_linear_rgb(const SampledSpectrum<N>& l, const SampledWavelengths<N>& w) const {
    if (mode_ == SpectralMode::rgb3) return {l[0], l[1], l[2]};
    return spectral_to_linear_rgb(l, w);
  }

  SpectralMode mode() const { return mode_; }
  const SpectralBasis<N>& basis() const { return basis_; }

 private:
  Vec3 spectral_to_linear_rgb(const SampledSpectrum<N>& l, const SampledWavelengths<N>& w) const;
  // Full mode, after a path has kept one wavelength (bin j): that bin's mean of exp(−depth(k, j))
  // over the sub-bin points; the arithmetic of mean_transmittance, so it is the same bit for bit.
  template <typename Depth>
  static float kept_bin_mean(int single, Depth depth) {
    const auto j = static_cast<std::size_t>(single);
    float sum = 0.0f;
    for (int k = 0; k < kSubBins; ++k) sum += exp_nonpositive(-depth(k, j));
    return sum * (1.0f / kSubBins);
  }
  // A spectrum of zeros but for bin j (the others carry nothing).
  static SampledSpectrum<N> only_bin(int j, float value) {
    SampledSpectrum<N> t{};
    t[static_cast<std::size_t>(j)] = value;
    return t;
  }

  SpectralMode mode_;
  SpectralBasis<N> basis_;
  std::vector<SampledSpectrum<N>> fixed_;
  std::vector<SubBinValues<N>> sub_;  // full mode, absorption spectra (others left zero)
  std::vector<float> dense_;          // kCmfCount values per spectrum
  std::array<std::array<float, N>, 3> rgb_weight_{};  // full: bin → linear Rec.709, per channel
  SampledSpectrum<N> env_white_;                      // full: D65 (luminance 1) per bin
};

}  // namespace bouguer
