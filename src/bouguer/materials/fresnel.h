#pragma once
// Smooth dielectric interfaces: Fresnel reflectance, reflection and refraction directions.
// Directions point away from the surface (wi, wo) as in pbrt; n is the unit normal on the side of wi.
#include <algorithm>
#include <cmath>
#include <optional>

#include "bouguer/core/math.h"

namespace bouguer {

// cos θt by Snell's law for light arriving at cos_theta_i (≥ 0) from eta_i into eta_t; negative
// under total internal reflection. Inline, with the two functions after it: every interface a
// path meets runs them, and computing cos θt once serves both the reflectance and the direction.
inline double cos_theta_transmitted(double cos_theta_i, double eta_i, double eta_t) {
  const double sin2_theta_i = std::max(0.0, 1.0 - cos_theta_i * cos_theta_i);
  const double sin2_theta_t = sin2_theta_i * (eta_i / eta_t) * (eta_i / eta_t);
  if (sin2_theta_t >= 1.0) return -1.0;
  return std::sqrt(1.0 - sin2_theta_t);
}

// Unpolarised reflectance (the mean of s and p) for a known cos θt ≥ 0.
inline double fresnel_dielectric(double cos_theta_i, double cos_theta_t, double eta_i, double eta_t) {
  const double rs = (eta_i * cos_theta_i - eta_t * cos_theta_t) / (eta_i * cos_theta_i + eta_t * cos_theta_t);
  const double rp = (eta_t * cos_theta_i - eta_i * cos_theta_t) / (eta_t * cos_theta_i + eta_i * cos_theta_t);
  return 0.5 * (rs * rs + rp * rp);
}

// The refracted direction of wi (on n's side, cos_theta_i = dot(wi, n)) for a known cos θt ≥ 0 and
// eta_i / eta_t.
inline Vec3 refract(const Vec3& wi, const Vec3& n, double cos_theta_i, double cos_theta_t, double eta_ratio) {
  return normalize(-wi * eta_ratio + n * (eta_ratio * cos_theta_i - cos_theta_t));
}

// Reflectance for s- and p-polarised light arriving at cos_theta_i (> 0) from a medium of index
// eta_i into eta_t. 1 under total internal reflection.
double fresnel_dielectric_s(double cos_theta_i, double eta_i, double eta_t);
double fresnel_dielectric_p(double cos_theta_i, double eta_i, double eta_t);

// Unpolarised reflectance: the mean of s and p.
double fresnel_dielectric(double cos_theta_i, double eta_i, double eta_t);

// Mirror direction of w about n.
Vec3 reflect(const Vec3& w, const Vec3& n);

// Refracted direction (pointing away from the surface into the other medium) of wi, which lies on
// n's side, going from eta_i to eta_t; nullopt under total internal reflection.
std::optional<Vec3> refract(const Vec3& wi, const Vec3& n, double eta_i, double eta_t);

}  // namespace bouguer
