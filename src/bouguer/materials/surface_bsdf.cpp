#include "bouguer/materials/surface_bsdf.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bouguer/materials/fresnel.h"
#include "bouguer/spectra/spectral_sampling.h"

namespace bouguer {
namespace {

template <std::size_t N>
using Spec = SampledSpectrum<N>;

template <std::size_t N>
Spec<N> constant(double v) {
  return Spec<N>::constant(static_cast<float>(v));
}

// The factor radiance picks up across a refraction, (η_o/η_i)² with the indices on wo's and
// wi's sides: radiance is carried as the physical quantity, so it is n² larger inside a medium of
// index n than the flux it stands for (pbrt-v4's convention). Importance (flux) carries none.
double radiance_refraction_factor(double eta_o, double eta_i) { return (eta_o * eta_o) / (eta_i * eta_i); }

double rough_refraction_factor(const RoughDielectric& r, const Vec3& wo, const Vec3& wi) {
  if (wo.z * wi.z >= 0.0) return 1.0;
  const double eta_o = wo.z > 0.0 ? r.lobe.eta_outside : r.lobe.eta_inside;
  const double eta_i = wi.z > 0.0 ? r.lobe.eta_outside : r.lobe.eta_inside;
  return radiance_refraction_factor(eta_o, eta_i);
}

// The rough interface in radiance mode: the compensated lobe times the η² factor of a refraction.
// Its adjoint (importance mode): the uncompensated lobe divided by the compensation of the
// direction the light arrives from, E(wi) instead of E(wo), and no η² factor (see the header).
double rough_radiance_eval(const RoughDielectric& r, const Vec3& wo, const Vec3& wi) {
  return r.lobe.eval(wo, wi) * rough_refraction_factor(r, wo, wi);
}

double rough_importance_eval(const RoughDielectric& r, const Vec3& wo, const Vec3& wi) {
  RoughDielectricBsdf plain = r.lobe;
  plain.compensation = nullptr;
  double f = plain.eval(wo, wi);
  if (r.lobe.compensation) f /= r.lobe.compensation->at(wi.z > 0.0, std::abs(wi.z));
  return f;
}

// ---- glTF metallic-roughness -------------------------------------------------------------------

double schlick_weight(double cos_theta) {
  const double m = std::clamp(1.0 - cos_theta, 0.0, 1.0);
  return (m * m) * (m * m) * m;
}

constexpr double kDielectricF0 = 0.04;  // glTF's dielectric: ior 1.5

// f·cos θi of the mix; 0 unless both directions lie above the surface.
template <std::size_t N>
Spec<N> metallic_roughness_eval(const MetallicRoughness<N>& g, const Vec3& wo, const Vec3& wi) {
  if (wo.z <= 0.0 || wi.z <= 0.0) return {};
  const double specular = ConductorBsdf{{g.alpha}}.eval(wo, wi);  // D·G/(4 cos θo), no Fresnel
  const double s5 = schlick_weight(dot(wo, normalize(wo + wi)));
  const double f_dielectric = kDielectricF0 + (1.0 - kDielectricF0) * s5;
  const auto m = static_cast<float>(g.metalness);
  const Spec<N> f_metal = g.base_colour + (constant<N>(1.0) - g.base_colour) * static_cast<float>(s5);
  const Spec<N> diffuse = g.base_colour * static_cast<float>((1.0 - f_dielectric) * wi.z / std::numbers::pi);
  return f_metal * static_cast<float>(m * specular) +
         (constant<N>(f_dielectric * specular) + diffuse) * (1.0f - m);
}

// The probability of drawing the GGX lobe for wo: its share of the two lobes' weights, Schlick's
// factors taken at cos θo; within [0.1, 0.9] while the diffuse lobe gives anything. Any choice that
// depends on wo alone keeps the mixture's density exact; this one only sets the variance.
template <std::size_t N>
double metallic_roughness_specular_probability(const MetallicRoughness<N>& g, const Vec3& wo) {
  const double s5 = schlick_weight(wo.z), base = std::clamp(double(g.base_colour.average()), 0.0, 1.0);
  const double f_dielectric = kDielectricF0 + (1.0 - kDielectricF0) * s5;
  const double specular = g.metalness * (base + (1.0 - base) * s5) + (1.0 - g.metalness) * f_dielectric;
  const double diffuse = (1.0 - g.metalness) * (1.0 - f_dielectric) * base;
  if (!(diffuse > 0.0)) return 1.0;
  return std::clamp(specular / (specular + diffuse), 0.1, 0.9);
}

template <std::size_t N>
double metallic_roughness_pdf(const MetallicRoughness<N>& g, const Vec3& wo, const Vec3& wi) {
  if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
  const double p = metallic_roughness_specular_probability(g, wo);
  return p * ConductorBsdf{{g.alpha}}.pdf(wo, wi) + (1.0 - p) * DiffuseBsdf{}.pdf(wo, wi);
}

template <std::size_t N>
std::optional<BsdfSampleN<N>> metallic_roughness_sample(const MetallicRoughness<N>& g, const Vec3& wo, double uc,
                                                        double u1, double u2) {
  if (wo.z <= 0.0) return std::nullopt;
  const bool specular = uc < metallic_roughness_specular_probability(g, wo);
  const auto s = specular ? ConductorBsdf{{g.alpha}}.sample(wo, u1, u2) : DiffuseBsdf{}.sample(wo, u1, u2);
  if (!s) return std::nullopt;
  const double p = metallic_roughness_pdf(g, wo, s->wi);
  if (!(p > 0.0)) return std::nullopt;
  return BsdfSampleN<N>{s->wi, metallic_roughness_eval(g, wo, s->wi) * static_cast<float>(1.0 / p), p, false};
}

// ---- thin dielectric sheet -----------------------------------------------------------------------

template <std::size_t N>
std::optional<BsdfSampleN<N>> thin_dielectric_sample(const ThinDielectric<N>& t, const Vec3& wo, double uc) {
  if (wo.z == 0.0) return std::nullopt;
  if (uc < thin_dielectric_reflectance(std::abs(wo.z), t.eta))
    return BsdfSampleN<N>{{-wo.x, -wo.y, wo.z}, constant<N>(1.0), 0.0, false};
  return BsdfSampleN<N>{-wo, t.tint, 0.0, true};
}

}  // namespace

double thin_dielectric_reflectance(double cos_theta, double eta) {
  const double r = fresnel_dielectric(std::min(1.0, cos_theta), 1.0, eta);
  if (!(r < 1.0)) return 1.0;
  const double t = 1.0 - r;
  return r + t * t * r / (1.0 - r * r);
}

template <std::size_t N>
Spec<N> conductor_fresnel(double cos_theta_i, double eta, const Spec<N>& n, const Spec<N>& k) {
  Spec<N> f;
  for (std::size_t i = 0; i < N; ++i)
    f[i] = static_cast<float>(fresnel_conductor(cos_theta_i, eta, {double(n[i]), double(k[i])}));
  return f;
}

template <std::size_t N>
Spec<N> eval(const Bsdf<N>& b, const Vec3& wo, const Vec3& wi, TransportMode mode) {
  if (const auto* d = std::get_if<DiffuseReflection<N>>(&b))
    return d->reflectance * static_cast<float>(DiffuseBsdf{}.eval(wo, wi));
  if (const auto* c = std::get_if<ConductorReflection<N>>(&b)) {
    if (c->alpha == 0.0) return {};
    const double g = ConductorBsdf{{c->alpha}}.eval(wo, wi);
    if (g == 0.0) return {};
    return conductor_fresnel(std::min(1.0, dot(wi, normalize(wi + wo))), c->eta, c->n, c->k) * static_cast<float>(g);
  }
  if (const auto* r = std::get_if<RoughDielectric>(&b))
    return constant<N>(mode == TransportMode::radiance ? rough_radiance_eval(*r, wo, wi) : rough_importance_eval(*r, wo, wi));
  if (const auto* g = std::get_if<MetallicRoughness<N>>(&b)) return metallic_roughness_eval(*g, wo, wi);  // reciprocal
  return {};  // smooth dielectric, thin sheet: delta lobes only
}

template <std::size_t N>
double pdf(const Bsdf<N>& b, const Vec3& wo, const Vec3& wi) {
  if (std::holds_alternative<DiffuseReflection<N>>(b)) return DiffuseBsdf{}.pdf(wo, wi);
  if (const auto* c = std::get_if<ConductorReflection<N>>(&b))
    return c->alpha == 0.0 ? 0.0 : ConductorBsdf{{c->alpha}}.pdf(wo, wi);
  if (const auto* r = std::get_if<RoughDielectric>(&b)) return r->lobe.pdf(wo, wi);
  if (const auto* g = std::get_if<MetallicRoughness<N>>(&b)) return metallic_roughness_pdf(*g, wo, wi);
  return 0.0;
}

template <std::size_t N>
std::optional<BsdfSampleN<N>> sample(const Bsdf<N>& b, const Vec3& wo, double uc, double u1, double u2,
                                     TransportMode mode) {
  if (const auto* d = std::get_if<DiffuseReflection<N>>(&b)) {
    const auto s = DiffuseBsdf{}.sample(wo, u1, u2);
    if (!s) return std::nullopt;
    return BsdfSampleN<N>{s->wi, d->reflectance * static_cast<float>(s->weight), s->pdf, false};
  }
  if (const auto* c = std::get_if<ConductorReflection<N>>(&b)) {
    if (c->alpha == 0.0) {
      if (wo.z == 0.0) return std::nullopt;
      const Vec3 wi{-wo.x, -wo.y, wo.z};
      return BsdfSampleN<N>{wi, conductor_fresnel(std::min(1.0, std::abs(wo.z)), c->eta, c->n, c->k), 0.0, false};
    }
    const auto s = ConductorBsdf{{c->alpha}}.sample(wo, u1, u2);
    if (!s) return std::nullopt;
    const Spec<N> f = conductor_fresnel(std::min(1.0, dot(s->wi, normalize(s->wi + wo))), c->eta, c->n, c->k);
    return BsdfSampleN<N>{s->wi, f * static_cast<float>(s->weight), s->pdf, false};
  }
  if (const auto* r = std::get_if<RoughDielectric>(&b)) {
    const auto s = r->lobe.sample(wo, uc, u1, u2);
    if (!s) return std::nullopt;
    const double weight = mode == TransportMode::radiance ? s->weight * rough_refraction_factor(*r, wo, s->wi)
                                                           : rough_importance_eval(*r, wo, s->wi) / s->pdf;
    return BsdfSampleN<N>{s->wi, constant<N>(weight), s->pdf, s->transmitted};
  }
  if (const auto* g = std::get_if<MetallicRoughness<N>>(&b)) return metallic_roughness_sample(*g, wo, uc, u1, u2);
  if (const auto* t = std::get_if<ThinDielectric<N>>(&b)) return thin_dielectric_sample(*t, wo, uc);  // reciprocal
  if (wo.z == 0.0) return std::nullopt;
  const DielectricSplit d = split(std::get<SmoothDielectric>(b), wo);
  if (uc < d.reflectance) return BsdfSampleN<N>{d.reflected(), constant<N>(1.0), 0.0, false};
  const auto refracted = d.refracted();
  if (!refracted) return std::nullopt;  // cannot happen: F = 1 under total internal reflection
  const double weight = mode == TransportMode::radiance ? radiance_refraction_factor(d.eta_o, d.eta_t) : 1.0;
  return BsdfSampleN<N>{*refracted, constant<N>(weight), 0.0, true};
}

#define BOUGUER_BSDF_INSTANTIATE(N)                                                                          \
  template Spec<N> conductor_fresnel(double, double, const Spec<N>&, const Spec<N>&);                        \
  template Spec<N> eval(const Bsdf<N>&, const Vec3&, const Vec3&, TransportMode);                            \
  template double pdf(const Bsdf<N>&, const Vec3&, const Vec3&);                                             \
  template std::optional<BsdfSampleN<N>> sample(const Bsdf<N>&, const Vec3&, double, double, double, TransportMode);
BOUGUER_BSDF_INSTANTIATE(kFullBins)
BOUGUER_BSDF_INSTANTIATE(3)
BOUGUER_BSDF_INSTANTIATE(kHeroCount)
#undef BOUGUER_BSDF_INSTANTIATE

}  // namespace bouguer
