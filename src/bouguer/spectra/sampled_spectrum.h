#pragma once
#include <bit>
#include <cstdint>
// The values of a spectral quantity at the N wavelengths one path carries (N is fixed per
// spectral mode: a dense set of bins for `full`, 3 for `rgb3`). A plain float array whose
// element-wise loops the compiler vectorises; no virtual calls, no heap.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>

namespace bouguer {

template <std::size_t N>
struct SampledSpectrum {
  static constexpr std::size_t size() { return N; }

  alignas(16) std::array<float, N> v{};

  static SampledSpectrum constant(float c) {
    SampledSpectrum s;
    s.v.fill(c);
    return s;
  }

  float& operator[](std::size_t i) { return v[i]; }
  float operator[](std::size_t i) const { return v[i]; }

#define BOUGUER_SAMPLED_OP(op)                                                     \
  SampledSpectrum& operator op##=(const SampledSpectrum& o) {                     \
    for (std::size_t i = 0; i < N; ++i) v[i] op## = o.v[i];                        \
    return *this;                                                                  \
  }                                                                                \
  SampledSpectrum& operator op##=(float s) {                                      \
    for (std::size_t i = 0; i < N; ++i) v[i] op## = s;                             \
    return *this;                                                                  \
  }                                                                                \
  friend SampledSpectrum operator op(SampledSpectrum a, const SampledSpectrum& b) { \
    return a op## = b;                                                             \
  }                                                                                \
  friend SampledSpectrum operator op(SampledSpectrum a, float s) { return a op## = s; }
  BOUGUER_SAMPLED_OP(+)
  BOUGUER_SAMPLED_OP(-)
  BOUGUER_SAMPLED_OP(*)
  BOUGUER_SAMPLED_OP(/)
#undef BOUGUER_SAMPLED_OP

  friend SampledSpectrum operator*(float s, SampledSpectrum a) { return a *= s; }
  bool operator==(const SampledSpectrum&) const = default;

  float average() const {
    if constexpr (N % 8 == 0) {
      // Eight running sums, which the compiler keeps in vector registers (one running sum is a
      // chain of dependent additions it may not reorder): the MIS weights' spectral means over 96
      // bins were 5 % of a render of a scattering ball. A fixed order: the same spectrum, the same
      // value.
      std::array<float, 8> part{};
      for (std::size_t i = 0; i < N; i += 8)
        for (std::size_t k = 0; k < 8; ++k) part[k] += v[i + k];
      return (((part[0] + part[4]) + (part[1] + part[5])) + ((part[2] + part[6]) + (part[3] + part[7]))) /
             static_cast<float>(N);
    } else {
      float sum = 0.0f;
      for (float x : v) sum += x;
      return sum / static_cast<float>(N);
    }
  }
  float max_value() const { return *std::max_element(v.begin(), v.end()); }
  float min_value() const { return *std::min_element(v.begin(), v.end()); }
  bool is_zero() const {
    return std::all_of(v.begin(), v.end(), [](float x) { return x == 0.0f; });
  }
};

// e^x for x ≤ 0 (attenuation), written so that the compiler vectorises it: x = n ln 2 + r with
// |r| ≤ ln2/2, e^r by a degree-6 Taylor polynomial (relative error < 3e-7, tested against
// std::exp), 2^n from the exponent bits. Arguments under −87 give 0
// (e^−87 is below the smallest normal float anyway). std::exp does not vectorise without
// -ffast-math, and transmittance is evaluated for every bin of every segment; this does, given
// -fno-trapping-math (CMakeLists.txt), which lets the compiler turn the clamps into selects.
inline float exp_nonpositive(float x) {
  x = std::min(std::max(x, -87.0f), 0.0f);
  // Round to nearest by the 1.5·2^23 trick (vectorises; roundf does not).
  const float n = (x * 1.44269504f + 12582912.0f) - 12582912.0f;
  const float r = x - n * 0.693145752f - n * 1.42860677e-6f;  // ln 2 split in two for accuracy
  const float p =
      1.0f + r * (1.0f + r * (0.5f + r * (0.166666672f + r * (0.0416666679f + r * (0.00833333377f + r * 0.00138888892f)))));
  const auto bits = static_cast<std::uint32_t>(static_cast<std::int32_t>(n) + 127) << 23;
  return p * std::bit_cast<float>(bits);
}

// e^x for x in [−87, 80] (clamped there), by the same vectorising scheme: a ratio of two
// transmittances, which may exceed 1 (media/scattering.h).
inline float exp_limited(float x) {
  x = std::min(std::max(x, -87.0f), 80.0f);
  const float n = (x * 1.44269504f + 12582912.0f) - 12582912.0f;
  const float r = x - n * 0.693145752f - n * 1.42860677e-6f;
  const float p =
      1.0f + r * (1.0f + r * (0.5f + r * (0.166666672f + r * (0.0416666679f + r * (0.00833333377f + r * 0.00138888892f)))));
  const auto bits = static_cast<std::uint32_t>(static_cast<std::int32_t>(n) + 127) << 23;
  return p * std::bit_cast<float>(bits);
}

// ln x for x > 0 (normal floats), vectorising likewise: x = m·2^e with m in [√½, √2), and
// ln m = 2·atanh(s), s = (m − 1)/(m + 1), |s| ≤ 0.172, by its series to s^11 (error below 2e-7,
// float rounding; tested against std::log).
inline float log_positive(float x) {
  const auto bits = std::bit_cast<std::uint32_t>(x);
  int e = static_cast<int>((bits >> 23) & 0xffu) - 127;
  float m = std::bit_cast<float>((bits & 0x007fffffu) | 0x3f800000u);  // in [1, 2)
  const bool high = m > 1.41421356f;
  m = high ? m * 0.5f : m;
  e = high ? e + 1 : e;
  const float t = (m - 1.0f) / (m + 1.0f), t2 = t * t;
  const float series = t * (2.0f + t2 * (0.666666667f + t2 * (0.4f + t2 * (0.285714286f + t2 * (0.222222222f + t2 * 0.181818182f)))));
  return series + static_cast<float>(e) * 0.693147181f;
}

template <std::size_t N>
SampledSpectrum<N> exp(SampledSpectrum<N> s) {
  for (float& x : s.v) x = std::exp(x);
  return s;
}

// exp(-sigma·l) for every wavelength: Bouguer-Lambert transmittance of a path of length_m through
// a medium whose natural-log attenuation coefficient is sigma_a_per_m.
template <std::size_t N>
SampledSpectrum<N> beer_lambert_transmittance(const SampledSpectrum<N>& sigma_a_per_m, float length_m) {
  SampledSpectrum<N> t;
  for (std::size_t i = 0; i < N; ++i) t.v[i] = exp_nonpositive(-sigma_a_per_m.v[i] * length_m);
  return t;
}

template <std::size_t N>
SampledSpectrum<N> clamp_zero(SampledSpectrum<N> s) {
  for (float& x : s.v) x = std::max(x, 0.0f);
  return s;
}

}  // namespace bouguer
