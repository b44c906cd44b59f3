#pragma once
// The unidirectional spectral path tracer. Next-event estimation to area emitters, combined with
// BSDF sampling by multiple importance sampling (power heuristic). At a smooth interface the path
// reflects with probability F and refracts otherwise (weight 1: the Fresnel factor cancels), so
// the same interface and medium model and the same Bouguer–Lambert attenuation as the Whitted
// integrator hold, and both converge to the same image. Shadow rays are blocked by any surface;
// light reaches diffuse surfaces through glass along BSDF-sampled paths (caustics, coloured
// shadows).
// Russian roulette starts at depth 4 and is never applied while the path is inside an absorbing
// medium, where the throughput falls because of absorption the estimator must follow to the end;
// the survival probability is the largest throughput over wavelengths, at least 5 %.
#include <cstdint>

#include "bouguer/geometry/ray_scene.h"
#include "bouguer/core/frame.h"
#include "bouguer/render/spectral_scene.h"

namespace bouguer {

template <std::size_t N>
class PathIntegrator {
 public:
  PathIntegrator(const RenderScene& scene, const SpectralScene<N>& spectral) : scene_(scene), s_(spectral) {}

  // Radiance arriving along `ray`, which travels in `medium`; `rays` counts rays traced.
  SampledSpectrum<N> radiance(Ray ray, int medium, Rng& rng, std::uint64_t& rays) const;

 private:
  struct Scatter {
    Vec3 wi;
    SampledSpectrum<N> weight;
    double pdf = 0.0;  // solid angle; 0 for a specular event
    int medium = -1;   // the medium wi travels into
  };
  std::optional<Scatter> scatter(const Ray& ray, const Hit& hit, const Surface& surface, int medium, Rng& rng,
                                 SampledSpectrum<N>& light, const SampledSpectrum<N>& beta, std::uint64_t& rays) const;
  SampledSpectrum<N> next_event(const Hit& hit, const Vec3& wo, const Frame& frame, int medium_behind,
                                int medium_front, const Surface& surface, Rng& rng, std::uint64_t& rays) const;
  SampledSpectrum<N> eval_bsdf(const Surface& surface, const Frame& frame, const Vec3& wo, const Vec3& wi,
                               int medium, double& pdf) const;

  const RenderScene& scene_;
  const SpectralScene<N>& s_;
};

}  // namespace bouguer
