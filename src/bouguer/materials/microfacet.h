#pragma once
// The GGX (Trowbridge–Reitz) microfacet distribution, isotropic, in the local shading frame
// (z = the surface normal). Sampling draws visible normals (Heitz 2018, "Sampling the GGX
// Distribution of Visible Normals", JCGT 7(4)), so no sample is wasted on back-facing microfacets.
#include "bouguer/core/math.h"

namespace bouguer {

struct GgxDistribution {
  double alpha = 0.1;  // roughness: the slope's standard deviation / √2; 0 < alpha

  double D(const Vec3& wm) const;                 // normal distribution, ∫ D cosθm dωm = 1
  double lambda(const Vec3& w) const;             // Smith's Λ
  double G1(const Vec3& w) const { return 1.0 / (1.0 + lambda(w)); }
  double G(const Vec3& wo, const Vec3& wi) const { return 1.0 / (1.0 + lambda(wo) + lambda(wi)); }  // height-correlated
  // Density of visible normals seen from wo: G1(wo) max(0, wo·wm) D(wm) / |cos θo|.
  double D_visible(const Vec3& wo, const Vec3& wm) const;
  // A visible normal for wo (wo.z > 0), from two uniform numbers.
  Vec3 sample_visible_normal(const Vec3& wo, double u1, double u2) const;
};

}  // namespace bouguer
