#pragma once
// Scattering functions in the local shading frame (z = the surface normal, pointing into the
// medium on the "outside"). Directions wo and wi point away from the surface. The wavelength
// enters only through Fresnel factors, which callers evaluate per wavelength; everything here is
// the geometric part, shared by all wavelengths of a path.
//
// Contracts, as in Mitsuba: `eval` is f(wo, wi)·|cos θi|; `pdf` is the solid-angle density that
// `sample` draws wi with; `sample` returns wi, pdf and weight = eval / pdf.
#include <complex>
#include <optional>

#include "bouguer/core/math.h"
#include "bouguer/materials/microfacet.h"

namespace bouguer {

struct BsdfSample {
  Vec3 wi;
  double pdf = 0.0;
  double weight = 0.0;  // eval / pdf (Fresnel excluded for conductors, see ConductorBsdf)
  bool transmitted = false;
};

// Cosine-weighted hemisphere (Malley's method) and its density.
Vec3 sample_cosine_hemisphere(double u1, double u2);

// Lambertian: eval = R/π |cos θi| with R = 1 here (callers multiply the spectral reflectance).
struct DiffuseBsdf {
  double eval(const Vec3& wo, const Vec3& wi) const;
  double pdf(const Vec3& wo, const Vec3& wi) const;
  std::optional<BsdfSample> sample(const Vec3& wo, double u1, double u2) const;
};

// Rough conductor (GGX, Walter et al. 2007): eval = D G F / (4 |cos θo|), with F = 1 here; the
// caller multiplies fresnel_conductor at the half vector for each wavelength.
struct ConductorBsdf {
  GgxDistribution ggx;
  double eval(const Vec3& wo, const Vec3& wi) const;
  double pdf(const Vec3& wo, const Vec3& wi) const;
  std::optional<BsdfSample> sample(const Vec3& wo, double u1, double u2) const;
};

// Rough dielectric interface (GGX, Walter et al. 2007): reflection and transmission between the
// outside (z > 0, index eta_outside) and the inside (index eta_inside). Radiance is not scaled by
// η² at transmission (see docs/rendering.md), so eval is reciprocal up to that factor.
struct RoughDielectricBsdf {
  GgxDistribution ggx;
  double eta_outside = 1.0, eta_inside = 1.5;

  double eval(const Vec3& wo, const Vec3& wi) const;
  double pdf(const Vec3& wo, const Vec3& wi) const;
  // uc chooses reflection or transmission (by Fresnel), u1, u2 the microfacet normal.
  std::optional<BsdfSample> sample(const Vec3& wo, double uc, double u1, double u2) const;
};

// Unpolarised reflectance of a conductor with complex index n + ik, from a dielectric of index
// eta_i, at cos θi.
double fresnel_conductor(double cos_theta_i, double eta_i, std::complex<double> n_t);

}  // namespace bouguer
