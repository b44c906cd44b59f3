#pragma once
// Surface scattering as a closed set: one plain struct per kind, built once per hit from the
// surface, the media on its two sides and the path's wavelengths (integrators/events.h), with
// the same three verbs. Directions are in the local frame (z = the frame's normal), both pointing
// away from the surface: wo towards where the path came from, wi the other one.
//
// Transport mode. A path from the camera carries radiance: wo looks back at the camera and wi is
// drawn towards the light. A path from a light carries importance: wo looks back at the light
// and wi is drawn towards the camera. In importance mode every verb gives the adjoint BSDF,
// f*(wo, wi) = f(wi, wo), so every estimator sums the same path integral. Radiance is the physical
// quantity, n² larger inside a medium of index n for the same flux (pbrt-v4's convention,
// docs/rendering.md): in radiance mode a refraction scales it by (η_o/η_i)², the indices on wo's
// and wi's sides; in importance mode, which carries flux, a refraction has no such factor. So an
// emitter's radiance and a light's intensity are given in the medium they sit in, and a lamp
// inside glass sends out the flux it emits. The adjoint of the rough interface's energy
// compensation divides by E(wi) instead of E(wo).
//
// Contracts (as in Mitsuba): eval is f(wo, wi)·|cos θi| and 0 for a delta lobe; pdf is the
// solid-angle density with which sample draws wi, 0 for a delta lobe; sample returns wi, its pdf
// (0 when specular) and weight = f·|cos θi| / pdf (for a delta lobe the factor it carries).
#include <algorithm>
#include <cmath>
#include <optional>
#include <variant>

#include "bouguer/materials/bsdf.h"
#include "bouguer/materials/fresnel.h"
#include "bouguer/spectra/sampled_spectrum.h"

namespace bouguer {

enum class TransportMode { radiance, importance };

// Lambertian reflection with a spectral reflectance, the same on both sides of an opaque surface.
template <std::size_t N>
struct DiffuseReflection {
  SampledSpectrum<N> reflectance;
};

// A metal seen from a medium of index eta: spectral Fresnel of n + ik; GGX alpha, 0 for a mirror.
template <std::size_t N>
struct ConductorReflection {
  SampledSpectrum<N> n, k;
  double eta = 1.0;
  double alpha = 0.0;
};

// glTF 2.0's metallic-roughness BRDF (the specification's appendix B), per hit from its texels:
// mix(dielectric, metal, metalness) with both on one GGX lobe of alpha = roughness² (height-
// correlated Smith), the metal's Fresnel Schlick's on F0 = base colour, the dielectric's Schlick's on
// F0 = 0.04 over a Lambertian base colour weighted by 1 − F; F at the half vector. Reciprocal, so
// both transport modes give the same values. Sampling is one mixture over the two lobes (GGX visible
// normals, cosine) with a choice that depends on wo only, and pdf is that mixture's density, so
// eval, pdf and sample agree (docs/assets.md).
template <std::size_t N>
struct MetallicRoughness {
  SampledSpectrum<N> base_colour;  // a reflectance in [0, 1]
  double metalness = 1.0;          // [0, 1]
  double alpha = 1.0;              // GGX, at least kMinMetallicRoughnessAlpha
};
// glTF's roughness 0 is a mirror; the mixture keeps a continuous lobe this narrow instead.
inline constexpr double kMinMetallicRoughnessAlpha = 1e-3;

// A smooth boundary between two media (front: the side z > 0): reflects with probability F and
// refracts otherwise, so the Fresnel factor cancels in the weight. Delta in both lobes.
struct SmoothDielectric {
  double eta_front = 1.0, eta_behind = 1.5;
};

// A thin dielectric sheet with the same medium on both sides (a window pane, a bubble's film,
// glTF's thin-walled transmission): pbrt-v4's ThinDielectricBxDF. The light that bounces between its
// two faces is summed: with R the Fresnel reflectance of one face at the angle of incidence,
// R' = R + T²R/(1 − R²) (T = 1 − R) is reflected specularly about the normal and T' = 1 − R' passes
// undeviated, times `tint` (glTF's base colour; white: nothing absorbed, R' + T' = 1). Delta in
// both lobes; reflection is drawn with probability R', so a sample's weight is 1 or the tint. The ray
// leaves into the medium it came from, so neither transport mode has an η² factor, and the lobes are
// symmetric in wo and wi: both modes give the same values.
template <std::size_t N>
struct ThinDielectric {
  double eta = 1.5;  // the sheet's index over the surrounding medium's
  SampledSpectrum<N> tint = SampledSpectrum<N>::constant(1.0f);
};

// R' of a thin sheet of relative index eta at |cos θ| (1 under total internal reflection).
double thin_dielectric_reflectance(double cos_theta, double eta);

// A rough boundary (GGX), energy-compensated (materials/bsdf.h).
struct RoughDielectric {
  RoughDielectricBsdf lobe;
};

// Both continuations of a smooth boundary seen along wo: the Fresnel reflectance that splits
// them, the mirror direction and the refracted one (none under total internal reflection). The
// directions are computed when asked for: a path follows one, Whitted skips the faint ones.
struct DielectricSplit {
  Vec3 wo, n;  // n: the unit normal on wo's side
  double cos_o = 1.0;   // dot(wo, n) ≥ 0
  double cos_t = -1.0;  // cos θt on the other side; negative under total internal reflection
  double reflectance = 1.0;
  double eta_o = 1.0, eta_t = 1.0;  // the index on wo's side and on the other side
  bool from_front = true;           // wo lies on the front side (`front` in split())

  Vec3 reflected() const { return n * (2.0 * cos_o) - wo; }
  std::optional<Vec3> refracted() const {
    if (cos_t < 0.0) return std::nullopt;
    return refract(wo, n, cos_o, cos_t, eta_o / eta_t);
  }
};
// In any frame: `front` is the unit normal on the eta_front side (the local frame's +z). Inline:
// Whitted calls it at every interface.
inline DielectricSplit split(const SmoothDielectric& d, const Vec3& wo, const Vec3& front = {0.0, 0.0, 1.0}) {
  const double cos_front = dot(wo, front);
  DielectricSplit s;
  s.from_front = cos_front > 0.0;
  s.wo = wo;
  s.n = s.from_front ? front : -front;
  s.cos_o = std::abs(cos_front);
  s.eta_o = s.from_front ? d.eta_front : d.eta_behind;
  s.eta_t = s.from_front ? d.eta_behind : d.eta_front;
  const double cos_i = std::min(1.0, s.cos_o);
  s.cos_t = cos_theta_transmitted(cos_i, s.eta_o, s.eta_t);
  s.reflectance = s.cos_t < 0.0 ? 1.0 : fresnel_dielectric(cos_i, s.cos_t, s.eta_o, s.eta_t);
  return s;
}

template <std::size_t N>
using Bsdf = std::variant<DiffuseReflection<N>, ConductorReflection<N>, SmoothDielectric, RoughDielectric,
                          MetallicRoughness<N>, ThinDielectric<N>>;

template <std::size_t N>
struct BsdfSampleN {
  Vec3 wi;
  SampledSpectrum<N> weight;
  double pdf = 0.0;  // 0: specular
  bool transmitted = false;
};

// Whether every lobe is a delta: such a surface is never connected to a light or the camera.
template <std::size_t N>
bool is_specular(const Bsdf<N>& b) {
  if (std::holds_alternative<SmoothDielectric>(b) || std::holds_alternative<ThinDielectric<N>>(b)) return true;
  if (const auto* c = std::get_if<ConductorReflection<N>>(&b)) return c->alpha == 0.0;
  return false;
}

template <std::size_t N>
SampledSpectrum<N> eval(const Bsdf<N>& b, const Vec3& wo, const Vec3& wi, TransportMode mode);

template <std::size_t N>
double pdf(const Bsdf<N>& b, const Vec3& wo, const Vec3& wi);

// uc chooses the lobe, u1 and u2 the direction within it.
template <std::size_t N>
std::optional<BsdfSampleN<N>> sample(const Bsdf<N>& b, const Vec3& wo, double uc, double u1, double u2,
                                     TransportMode mode);

// Fresnel reflectance of a conductor for each wavelength, from a dielectric of index eta.
template <std::size_t N>
SampledSpectrum<N> conductor_fresnel(double cos_theta_i, double eta, const SampledSpectrum<N>& n,
                                     const SampledSpectrum<N>& k);

}  // namespace bouguer
