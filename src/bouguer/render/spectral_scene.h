#pragma once
// Every spectrum of a compiled scene sampled once for the chosen spectral mode, and the light
// sampling both integrators share.
#include <optional>
#include <vector>

#include "bouguer/core/frame.h"
#include "bouguer/render/rng.h"
#include "bouguer/render/spectral_sampling.h"
#include "bouguer/scene/compile.h"

namespace bouguer {

template <std::size_t N>
struct SampledMaterial {
  bool conductor = false;
  SampledSpectrum<N> reflectance;  // diffuse
  SampledSpectrum<N> n, k;         // conductor
  double alpha = 0.0;              // conductor roughness
};

template <std::size_t N>
struct SpectralScene {
  SpectralBasis<N> basis;
  std::vector<SampledSpectrum<N>> sigma_a_per_m;  // per medium
  std::vector<bool> absorbing;
  std::vector<double> ior;                        // per medium, at kReferenceWavelengthNm
  std::vector<SampledSpectrum<N>> ior_at;         // per medium, at the carried wavelengths
  std::vector<bool> dispersive;                   // per medium: n varies over 360–830 nm
  std::vector<SampledSpectrum<N>> emission;       // per emission
  std::vector<SampledMaterial<N>> materials;      // per opaque material
  std::vector<SampledSpectrum<N>> delta_intensity;  // per point, spot or distant light
  SampledSpectrum<N> background;
  // The environment map, when the scene has one (it replaces `background`): texel spectra are
  // evaluated at env_nm and multiplied by D65 there (env_white: bin means in full mode); rgb3
  // takes the texels' RGB directly.
  const EnvironmentMap* environment = nullptr;
  std::array<double, N> env_nm{};
  SampledSpectrum<N> env_white;

  SampledSpectrum<N> environment_radiance(int texel) const {
    SampledSpectrum<N> l;
    if (basis.mode == SpectralMode::rgb3) {
      const Vec3f& c = environment->rgb[texel];
      for (std::size_t i = 0; i < N && i < 3; ++i) l[i] = std::array{c.x, c.y, c.z}[i];
      return l;
    }
    const RgbIlluminantSpectrum& s = environment->spectra[texel];
    for (std::size_t i = 0; i < N; ++i) l[i] = static_cast<float>(s.scale * s.poly(env_nm[i])) * env_white[i];
    return l;
  }
  // What a ray leaving the scene in direction d sees.
  SampledSpectrum<N> background_radiance(const Vec3& d) const {
    return environment ? environment_radiance(environment->texel(d)) : background;
  }

  // Full mode: σ_a at kSubBins points inside each bin, per medium (spectral_sampling.h). Empty
  // in the other modes, which carry exact wavelengths.
  std::vector<SubBinValues<N>> sigma_sub;

  SampledSpectrum<N> transmittance(int medium, double length_m) const {
    if (medium < 0 || !absorbing[medium]) return SampledSpectrum<N>::constant(1.0f);
    const auto l = static_cast<float>(length_m);
    if (sigma_sub.empty()) return beer_lambert_transmittance(sigma_a_per_m[medium], l);
    return sub_bin_transmittance(sigma_sub[medium], l);
  }
};

template <std::size_t N>
SpectralScene<N> make_spectral_scene(const RenderScene& scene, const SpectralBasis<N>& basis);

// Every spectrum of the scene at 1 nm, for modes whose wavelengths change per sample (hero).
struct SpectralTables {
  struct Table {
    std::vector<float> v;  // kLambdaMinNm .. kLambdaMaxNm at 1 nm
    float at(double nm) const;
  };
  std::vector<Table> sigma_a, ior, emission, reflectance, n, k;  // per medium / emission / material
  std::vector<Table> delta_intensity;                            // per delta light
  std::vector<bool> absorbing, dispersive, conductor;
  std::vector<double> ior_reference, alpha;
  Table background;
  const EnvironmentMap* environment = nullptr;
};

SpectralTables make_spectral_tables(const RenderScene& scene);

// `out` set to the scene at the given wavelengths; its vectors are reused between calls.
template <std::size_t N>
void fill_spectral_scene(const SpectralTables& tables, const std::array<double, N>& nm, SpectralScene<N>& out);

// Fresnel reflectance of a conductor for each wavelength.
template <std::size_t N>
SampledSpectrum<N> conductor_fresnel(double cos_theta_i, double eta_i, const SampledMaterial<N>& m);

// A point, spot or distant light seen from `point`: the direction towards it, the distance
// (infinite for distant lights), and the factor on its intensity spectrum that gives the incident
// radiance-times-solid-angle: falloff / distance² (point, spot) or 1 (distant).
struct DeltaLightSample {
  Vec3 wi;
  double distance_m = 0.0;
  double factor = 0.0;
};
std::optional<DeltaLightSample> sample_delta_light(const DeltaLightDesc& light, const Vec3& point);

// A spot's smooth falloff: 1 within falloff_deg of the axis, smoothstep to 0 at cone_deg (as pbrt).
double spot_falloff(double cos_theta, double cone_deg, double falloff_deg);

// The factor on an emitter's radiance for light leaving it in `direction` (1 but for spot disks).
inline double emitted_factor(const EmissionDesc& e, const Vec3& direction) {
  return e.spot ? spot_falloff(dot(direction, e.spot->axis), e.spot->cone_deg, e.spot->falloff_deg) : 1.0;
}

// Light from delta light i arriving through `medium`: intensity × falloff / d² × transmittance;
// zero when a distant light would have to cross an infinite absorber.
template <std::size_t N>
SampledSpectrum<N> delta_light_incident(const SpectralScene<N>& s, std::size_t i, const DeltaLightSample& light,
                                        int medium);

// Whether nothing lies between the hit and a light `distance_m` away along wi (infinite: a distant
// light); traces one shadow ray from the offset origin, counted in `rays`.
bool unoccluded(const RenderScene& scene, const Hit& hit, const Vec3& wi, double distance_m, std::uint64_t& rays);

// f·|cos θi| of an opaque material (frame.n on wo's side), in world directions, and the density its
// own sampling draws wi with. `eta` is the index of the medium around it (for conductor Fresnel).
template <std::size_t N>
SampledSpectrum<N> eval_opaque(const SampledMaterial<N>& m, const Frame& frame, const Vec3& wo, const Vec3& wi,
                               double eta, double& pdf);

// A point on the emitters, uniform by area.
struct LightSample {
  Vec3 point, normal;  // unit geometric normal of the emitting triangle
  std::uint32_t geometry = 0;
};
std::optional<LightSample> sample_emitter_point(const RenderScene& scene, Rng& rng);

// Solid-angle density of reaching an emitter point by sample_emitter_point from `from`.
double emitter_pdf_solid_angle(const RenderScene& scene, const Vec3& from, const Vec3& point, const Vec3& normal);

}  // namespace bouguer
