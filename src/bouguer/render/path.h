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
// Dispersion: while no dispersive interface has been met, all carried wavelengths share the path.
// At the first one, a single wavelength j is chosen uniformly (stratified over the pixel's samples
// by the caller; in full mode a wavelength uniform within bin j) and kept with weight N, the others
// are terminated (their throughput becomes 0); from there on the path follows n(λ_j). Each
// wavelength's expected contribution is unchanged, so the estimator stays unbiased for every bin
// (full) and every hero wavelength (hero).
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
  // `wavelength_u` in [0, 1) picks the wavelength kept at a dispersive interface; callers stratify
  // it over a pixel's samples (each value must be uniform on its own, so the choice stays unbiased).
  SampledSpectrum<N> radiance(Ray ray, int medium, double wavelength_u, Rng& rng, std::uint64_t& rays) const;

 private:
  struct Scatter {
    Vec3 wi;
    SampledSpectrum<N> weight;
    double pdf = 0.0;  // solid angle; 0 for a specular event
    int medium = -1;   // the medium wi travels into
  };
  // The index of medium m for this path. Before a dispersive interface, dispersive media are never
  // met, so the reference index serves; after it, the index at the kept wavelength.
  double eta(int medium, int single) const {
    if (single < 0 || !s_.dispersive[medium]) return s_.ior[medium];
    return ior_at(scene_.media[medium].ior, single_nm_);
  }
  std::optional<Scatter> scatter(const Ray& ray, const Hit& hit, const Surface& surface, int medium, int single,
                                 Rng& rng, SampledSpectrum<N>& light, const SampledSpectrum<N>& beta,
                                 std::uint64_t& rays) const;
  SampledSpectrum<N> next_event(const Hit& hit, const Vec3& wo, const Frame& frame, int medium_behind,
                                int medium_front, const Surface& surface, int single, Rng& rng,
                                std::uint64_t& rays) const;
  SampledSpectrum<N> environment_light(const Hit& hit, const Vec3& wo, const Frame& frame, int medium_behind,
                                       int medium_front, const Surface& surface, int single, Rng& rng,
                                       std::uint64_t& rays) const;
  SampledSpectrum<N> area_light(const Hit& hit, const Vec3& wo, const Frame& frame, int medium_behind,
                                int medium_front, const Surface& surface, int single, Rng& rng,
                                std::uint64_t& rays) const;
  SampledSpectrum<N> delta_lights(const Hit& hit, const Vec3& wo, const Frame& frame, int medium_behind,
                                  int medium_front, const Surface& surface, int single, std::uint64_t& rays) const;
  SampledSpectrum<N> eval_bsdf(const Surface& surface, const Frame& frame, const Vec3& wo, const Vec3& wi,
                               int medium, int single, double& pdf) const;

  const RenderScene& scene_;
  const SpectralScene<N>& s_;
  // The wavelength kept after a dispersive interface: in full mode drawn uniformly within the
  // kept bin (each bin stands for all its wavelengths, as its emission mean and CMF sum do), else
  // the carried wavelength itself. One integrator object traces one path at a time.
  mutable double single_nm_ = 0.0;
};

}  // namespace bouguer
