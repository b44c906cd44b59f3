#include "bouguer/materials/bsdf.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

#include "bouguer/materials/fresnel.h"

namespace bouguer {
namespace {

constexpr double kPi = std::numbers::pi;

bool same_hemisphere(const Vec3& a, const Vec3& b) { return a.z * b.z > 0.0; }

// Both directions mirrored to put wo in the upper hemisphere, with the indices that go with it.
struct Oriented {
  Vec3 wo, wi;
  double eta_o, eta_i;  // index on wo's side, and on the other side
};

Oriented orient(const RoughDielectricBsdf& b, const Vec3& wo, const Vec3& wi) {
  if (wo.z > 0.0) return {wo, wi, b.eta_outside, b.eta_inside};
  return {-wo, -wi, b.eta_inside, b.eta_outside};
}

// The generalized half vector of a transmission (Walter et al. eq. 16), facing +z; nullopt when
// either direction sees the microfacet from behind.
std::optional<Vec3> transmission_half_vector(const Oriented& o) {
  Vec3 wm = o.wo * o.eta_o + o.wi * o.eta_i;
  if (length(wm) == 0.0) return std::nullopt;
  wm = normalize(wm);
  if (wm.z < 0.0) wm = -wm;
  if (dot(wm, o.wo) <= 0.0 || dot(wm, o.wi) >= 0.0) return std::nullopt;
  return wm;
}

}  // namespace

// ---- diffuse -----------------------------------------------------------------------------------

double DiffuseBsdf::eval(const Vec3& wo, const Vec3& wi) const {
  return same_hemisphere(wo, wi) ? std::abs(wi.z) / kPi : 0.0;
}

double DiffuseBsdf::pdf(const Vec3& wo, const Vec3& wi) const { return eval(wo, wi); }

std::optional<BsdfSample> DiffuseBsdf::sample(const Vec3& wo, double u1, double u2) const {
  if (wo.z == 0.0) return std::nullopt;
  Vec3 wi = sample_cosine_hemisphere(u1, u2);
  if (wo.z < 0.0) wi.z = -wi.z;
  if (wi.z == 0.0) return std::nullopt;
  return BsdfSample{wi, std::abs(wi.z) / kPi, 1.0, false};
}

// ---- conductor ---------------------------------------------------------------------------------

double ConductorBsdf::eval(const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
  const Vec3 wm = normalize(wo + wi);
  return ggx.D(wm) * ggx.G(wo, wi) / (4.0 * wo.z);
}

double ConductorBsdf::pdf(const Vec3& wo, const Vec3& wi) const {
  if (wo.z <= 0.0 || wi.z <= 0.0) return 0.0;
  const Vec3 wm = normalize(wo + wi);
  return ggx.D_visible(wo, wm) / (4.0 * dot(wo, wm));
}

std::optional<BsdfSample> ConductorBsdf::sample(const Vec3& wo, double u1, double u2) const {
  if (wo.z <= 0.0) return std::nullopt;
  const Vec3 wm = ggx.sample_visible_normal(wo, u1, u2);
  const Vec3 wi = reflect(wo, wm);
  if (wi.z <= 0.0) return std::nullopt;
  const double p = pdf(wo, wi);
  if (!(p > 0.0)) return std::nullopt;
  return BsdfSample{wi, p, eval(wo, wi) / p, false};
}

// ---- rough dielectric --------------------------------------------------------------------------

namespace {
// What eval and pdf share: the microfacet normal that connects wo and wi, the Fresnel factor of
// the event (F for reflection, 1 − F for transmission), and for transmission the two cosines and
// the denominator of the half-vector Jacobian.
struct DielectricEvent {
  Oriented o;
  Vec3 wm;
  double fresnel = 0.0;
  bool reflection = true;
  double cos_om = 0.0, cos_im = 0.0, denom = 0.0;
};

std::optional<DielectricEvent> dielectric_event(const RoughDielectricBsdf& b, const Vec3& wo, const Vec3& wi) {
  if (wo.z == 0.0 || wi.z == 0.0) return std::nullopt;
  DielectricEvent e{orient(b, wo, wi), {}};
  if (e.o.wi.z > 0.0) {
    e.wm = normalize(e.o.wo + e.o.wi);
    e.fresnel = fresnel_dielectric(dot(e.o.wo, e.wm), e.o.eta_o, e.o.eta_i);
    return e;
  }
  const auto wm = transmission_half_vector(e.o);
  if (!wm) return std::nullopt;
  e.wm = *wm;
  e.reflection = false;
  e.cos_om = dot(e.o.wo, e.wm);
  e.cos_im = dot(e.o.wi, e.wm);
  e.fresnel = 1.0 - fresnel_dielectric(e.cos_om, e.o.eta_o, e.o.eta_i);
  e.denom = e.o.eta_i * e.cos_im + e.o.eta_o * e.cos_om;
  return e;
}
}  // namespace

double RoughDielectricBsdf::eval(const Vec3& wo, const Vec3& wi) const {
  const auto e = dielectric_event(*this, wo, wi);
  if (!e) return 0.0;
  const double dg = ggx.D(e->wm) * ggx.G(e->o.wo, e->o.wi);
  const double scale = compensation ? 1.0 / compensation->at(wo.z > 0.0, std::abs(wo.z)) : 1.0;
  if (e->reflection) return scale * e->fresnel * dg / (4.0 * e->o.wo.z);
  return scale * e->fresnel * dg * std::abs(e->cos_im * e->cos_om) * e->o.eta_i * e->o.eta_i /
         (e->o.wo.z * e->denom * e->denom);
}

double RoughDielectricBsdf::pdf(const Vec3& wo, const Vec3& wi) const {
  const auto e = dielectric_event(*this, wo, wi);
  if (!e) return 0.0;
  const double visible = ggx.D_visible(e->o.wo, e->wm);
  if (e->reflection) return e->fresnel * visible / (4.0 * dot(e->o.wo, e->wm));
  return e->fresnel * visible * e->o.eta_i * e->o.eta_i * std::abs(e->cos_im) / (e->denom * e->denom);
}

std::optional<BsdfSample> RoughDielectricBsdf::sample(const Vec3& wo_in, double uc, double u1, double u2) const {
  if (wo_in.z == 0.0) return std::nullopt;
  const bool flip = wo_in.z < 0.0;
  const Vec3 wo = flip ? -wo_in : wo_in;
  const double eta_o = flip ? eta_inside : eta_outside, eta_i = flip ? eta_outside : eta_inside;
  const Vec3 wm = ggx.sample_visible_normal(wo, u1, u2);
  const double f = fresnel_dielectric(dot(wo, wm), eta_o, eta_i);
  Vec3 wi;
  bool transmitted = false;
  if (uc < f) {
    wi = reflect(wo, wm);
    if (wi.z <= 0.0) return std::nullopt;
  } else {
    const auto t = refract(wo, wm, eta_o, eta_i);
    if (!t || t->z >= 0.0) return std::nullopt;
    wi = *t;
    transmitted = true;
  }
  if (flip) wi = -wi;
  const double p = pdf(wo_in, wi);
  if (!(p > 0.0)) return std::nullopt;
  return BsdfSample{wi, p, eval(wo_in, wi) / p, transmitted};
}

double DielectricAlbedo::at(bool from_outside, double cos_theta) const {
  const auto& table = from_outside ? outside : inside;
  // Entries sit at cosines (i + 0.5) / kCosines; clamp beyond the first and the last.
  const double x = std::clamp(cos_theta * kCosines - 0.5, 0.0, kCosines - 1.0);
  const int i = std::min(static_cast<int>(x), kCosines - 2);
  const double t = x - i;
  return (1.0 - t) * table[i] + t * table[i + 1];
}

DielectricAlbedo DielectricAlbedo::compute(double alpha, double eta_outside, double eta_inside) {
  DielectricAlbedo out;
  const RoughDielectricBsdf bsdf{{alpha}, eta_outside, eta_inside};
  for (int side = 0; side < 2; ++side) {
    for (int c = 0; c < kCosines; ++c) {
      const double mu = (c + 0.5) / kCosines;
      const Vec3 up{std::sqrt(1.0 - mu * mu), 0.0, mu};
      const Vec3 wo = side == 0 ? up : Vec3{up.x, 0.0, -mu};
      const double eta_o = side == 0 ? eta_outside : eta_inside, eta_i = side == 0 ? eta_inside : eta_outside;
      double sum = 0.0;
      // Jittered strata rather than cell midpoints: the last cells in u1 hold GGX's long tail of
      // steep microfacets, where most of the loss is, and midpoints would miss it.
      std::mt19937_64 rng(static_cast<std::uint64_t>(side * kCosines + c));
      auto jitter = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
      for (int a = 0; a < kGrid; ++a) {
        for (int b = 0; b < kGrid; ++b) {
          const double u1 = (a + jitter()) / kGrid, u2 = (b + jitter()) / kGrid;
          // Both branches at once, each weighted by its Fresnel probability: uc = 0 reflects
          // whenever F > 0, uc = 1 transmits whenever F < 1.
          const Vec3 up_wo = side == 0 ? wo : -wo;
          const double f = fresnel_dielectric(dot(up_wo, bsdf.ggx.sample_visible_normal(up_wo, u1, u2)), eta_o, eta_i);
          if (const auto r = bsdf.sample(wo, 0.0, u1, u2); r && !r->transmitted) sum += f * r->weight;
          if (const auto t = bsdf.sample(wo, 1.0, u1, u2); t && t->transmitted) sum += (1.0 - f) * t->weight;
        }
      }
      (side == 0 ? out.outside : out.inside)[c] = static_cast<float>(sum / (kGrid * kGrid));
    }
  }
  return out;
}

double fresnel_conductor(double cos_theta_i, double eta_i, std::complex<double> n_t) {
  const std::complex<double> eta = n_t / eta_i;
  const double ci = std::clamp(cos_theta_i, 0.0, 1.0);
  const std::complex<double> sin2_t = (1.0 - ci * ci) / (eta * eta);
  const std::complex<double> ct = std::sqrt(1.0 - sin2_t);
  const std::complex<double> r_parl = (eta * ci - ct) / (eta * ci + ct);
  const std::complex<double> r_perp = (ci - eta * ct) / (ci + eta * ct);
  return 0.5 * (std::norm(r_parl) + std::norm(r_perp));
}

}  // namespace bouguer
