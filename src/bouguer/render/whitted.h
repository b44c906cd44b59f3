#pragma once
// The spectral Whitted integrator (the paper's ray tracer, done right): at each interface the
// exact unpolarised Fresnel reflectance between the two media, total internal reflection, and
// recursion into both the reflected and the refracted ray; every segment inside a medium is
// attenuated by exp(−σ_a(λ)·l). Emitters are seen directly. Diffuse surfaces take direct light from
// emitters by shadow rays; a shadow ray that meets any other surface, glass included, is blocked
// (light through glass is the path tracer's job). Smooth conductors reflect like mirrors with their
// spectral Fresnel reflectance; rough conductors take direct light only, like diffuse surfaces.
// Rough dielectric interfaces need the path tracer.
// A branch stops at max_depth or when its weight (the largest throughput over wavelengths from the
// camera) falls below kMinPathWeight: the light it could still add is below 1e-4 of what an
// unattenuated path would.
#include <cstdint>

#include "bouguer/geometry/ray_scene.h"
#include "bouguer/render/rng.h"
#include "bouguer/render/spectral_scene.h"
#include "bouguer/scene/compile.h"

namespace bouguer {

inline constexpr float kMinPathWeight = 1e-4f;

template <std::size_t N>
class WhittedIntegrator {
 public:
  WhittedIntegrator(const RenderScene& scene, const SpectralScene<N>& spectral) : scene_(scene), s_(spectral) {}

  // Radiance arriving along `ray`, which travels in `medium`. `rays` counts rays traced.
  SampledSpectrum<N> radiance(const Ray& ray, int medium, int depth, float weight, Rng& rng,
                              std::uint64_t& rays) const;

 private:
  SampledSpectrum<N> interface(const Ray& ray, const Hit& hit, const Surface& surface, int depth, float weight,
                               Rng& rng, std::uint64_t& rays) const;
  SampledSpectrum<N> opaque(const Ray& ray, const Hit& hit, const Surface& surface, int medium, int depth,
                            float weight, Rng& rng, std::uint64_t& rays) const;
  SampledSpectrum<N> direct_light(const Hit& hit, const Vec3& wo, int medium, const SampledMaterial<N>& material,
                                  Rng& rng, std::uint64_t& rays) const;

  const RenderScene& scene_;
  const SpectralScene<N>& s_;
};

}  // namespace bouguer
