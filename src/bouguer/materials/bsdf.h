#pragma once
// Scattering functions in the local shading frame (z = the surface normal, pointing into the
// medium on the "outside"). Directions wo and wi point away from the surface. The wavelength
// enters only through Fresnel factors, which callers evaluate per wavelength; everything here is
// the geometric part, shared by all wavelengths of a path.
//
// Contracts, as in Mitsuba: `eval` is f(wo, wi)·|cos θi|; `pdf` is the solid-angle density that
// `sample` draws wi with; `sample` returns wi, pdf and weight = eval / pdf.
#include <array>
#include <complex>
#include <optional>

#include "bouguer/core/math.h"
#include "bouguer/core/warp.h"
#include "bouguer/materials/microfacet.h"

namespace bouguer {

struct BsdfSample {
  Vec3 wi;
  double pdf = 0.0;
  double weight = 0.0;  // eval / pdf (Fresnel excluded for conductors, see ConductorBsdf)
  bool transmitted = false;
};

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

struct DielectricAlbedo;

// Rough dielectric interface (GGX, Walter et al. 2007): reflection and transmission between the
// outside (z > 0, index eta_outside) and the inside (index eta_inside). eval is the lobe without the
// η² factor of radiance at a refraction, which the spectral Bsdf set adds in radiance mode
// (materials/surface_bsdf.h); without that factor it is reciprocal.
//
// The single-scattering model loses the light that would bounce between microfacets (3 % in a
// furnace at alpha 0.1, more when rougher). With `compensation` set, eval and the sample weight
// are divided by the tabulated directional albedo E(wo) of the single-scattering model, so that
// reflection plus transmission keeps all energy from every direction, as a clear interface must
// (the energy-compensation idea of Turquin 2019 taken to its limit for a lossless dielectric;
// Cycles does the same for its glass). This makes eval slightly non-reciprocal: E(wo) ≠ E(wi).
struct RoughDielectricBsdf {
  GgxDistribution ggx;
  double eta_outside = 1.0, eta_inside = 1.5;
  const DielectricAlbedo* compensation = nullptr;

  double eval(const Vec3& wo, const Vec3& wi) const;
  double pdf(const Vec3& wo, const Vec3& wi) const;
  // uc chooses reflection or transmission (by Fresnel), u1, u2 the microfacet normal.
  std::optional<BsdfSample> sample(const Vec3& wo, double uc, double u1, double u2) const;
};

// Directional albedo (reflection + transmission) of the single-scattering rough dielectric, for
// light leaving towards wo, tabulated over |cos θo| on each side. Computed by jittered quadrature
// (fixed seeds) over the visible-normal sample space and both Fresnel branches, so a table is the
// same in every run.
struct DielectricAlbedo {
  static constexpr int kCosines = 64, kGrid = 64;
  std::array<float, kCosines> outside{}, inside{};

  double at(bool from_outside, double cos_theta) const;
  static DielectricAlbedo compute(double alpha, double eta_outside, double eta_inside);
};

// Unpolarised reflectance of a conductor with complex index n + ik, from a dielectric of index
// eta_i, at cos θi.
double fresnel_conductor(double cos_theta_i, double eta_i, std::complex<double> n_t);

}  // namespace bouguer
