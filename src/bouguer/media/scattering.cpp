#include "bouguer/media/scattering.h"

namespace bouguer::detail {

// Compiled twice, for AVX2 and for the baseline, like the transmittance loop
// (render/spectral_sampling.cpp): in full mode this runs at every scattering event, 96 wide.
__attribute__((target_clones("avx2", "default"))) void walk_factor_wide(const float* sigma_s, std::size_t n, float h,
                                                                           float m, float collisions, float* out) {
  if (collisions == 0.0f) {
    for (std::size_t k = 0; k < n; ++k) out[k] = exp_limited(-(sigma_s[k] - h) * m);
    return;
  }
  const float log_h = log_positive(h);
  for (std::size_t k = 0; k < n; ++k) {
    const float s = sigma_s[k];
    const float log_ratio = s > 0.0f ? collisions * (log_positive(std::max(s, 1e-30f)) - log_h) : -1e30f;
    out[k] = exp_limited(-(s - h) * m + log_ratio);
  }
}

}  // namespace bouguer::detail
