// Micro-benchmarks of the colour pipeline's inner pieces. They report; they assert nothing.
#include <benchmark/benchmark.h>

#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"
#include "bouguer/spectra/sampled_spectrum.h"

namespace bouguer {
namespace {

// A spectrum to XYZ at 1 nm (471 evaluations of a 1 nm table plus the sums).
void BM_SpectrumToXyz(benchmark::State& state) {
  const Spectrum d65 = named_illuminant("D65");
  for (auto _ : state) benchmark::DoNotOptimize(spectrum_to_xyz(d65));
}
BENCHMARK(BM_SpectrumToXyz);

void BM_Ciede2000(benchmark::State& state) {
  const Lab a{50.0, 2.6772, -79.7751}, b{50.0, 0.0, -82.7485};
  for (auto _ : state) benchmark::DoNotOptimize(ciede2000(a, b));
}
BENCHMARK(BM_Ciede2000);

void BM_XyzToLab(benchmark::State& state) {
  Vec3 xyz{0.3, 0.4, 0.5};
  for (auto _ : state) {
    benchmark::DoNotOptimize(xyz_to_lab(xyz));
    xyz.x += 1e-9;
  }
}
BENCHMARK(BM_XyzToLab);

// Bouguer–Lambert transmittance of one path segment for N wavelengths: the renderer's inner loop.
template <std::size_t N>
void BM_BeerLambert(benchmark::State& state) {
  SampledSpectrum<N> sigma;
  for (std::size_t i = 0; i < N; ++i) sigma[i] = 10.0f + static_cast<float>(i);
  float length_m = 0.01f;
  for (auto _ : state) {
    benchmark::DoNotOptimize(beer_lambert_transmittance(sigma, length_m));
    length_m += 1e-7f;
  }
  state.SetItemsProcessed(state.iterations() * static_cast<long>(N));
}
BENCHMARK(BM_BeerLambert<3>);
BENCHMARK(BM_BeerLambert<32>);
BENCHMARK(BM_BeerLambert<64>);

}  // namespace
}  // namespace bouguer
