#include "bouguer/integrators/surface_events.h"

#include <algorithm>

namespace bouguer {

template <std::size_t N>
int keep_wavelength(const SceneView<N>& v, SampledWavelengths<N>& w, double u, Rng& rng) {
  const int j = std::min(static_cast<int>(u * N), static_cast<int>(N) - 1);
  w.terminate_secondary(j, v.tables.kept_wavelength_nm(w, j, rng.next_double()));
  return j;
}

template <std::size_t N>
bool keep_one_wavelength(const SceneView<N>& v, const SurfaceSeen& seen, SampledWavelengths<N>& w,
                         SampledSpectrum<N>& beta, double u, Rng& rng) {
  if (N == 1 || w.secondary_terminated() || !is_dispersive(v.scene, seen)) return false;
  const int j = keep_wavelength(v, w, u, rng);
  const float kept = beta[static_cast<std::size_t>(j)] * static_cast<float>(N);
  beta = SampledSpectrum<N>{};
  beta[static_cast<std::size_t>(j)] = kept;
  return true;
}

#define BOUGUER_SURFACE_EVENTS_INSTANTIATE(N) \
  template int keep_wavelength(const SceneView<N>&, SampledWavelengths<N>&, double, Rng&); \
  template bool keep_one_wavelength(const SceneView<N>&, const SurfaceSeen&, SampledWavelengths<N>&, \
      SampledSpectrum<N>&, double, Rng&);
BOUGUER_SURFACE_EVENTS_INSTANTIATE(kFullBins)
BOUGUER_SURFACE_EVENTS_INSTANTIATE(3)
BOUGUER_SURFACE_EVENTS_INSTANTIATE(kHeroCount)
#undef BOUGUER_SURFACE_EVENTS_INSTANTIATE

}  // namespace bouguer
