#pragma once
// Smooth dielectric interfaces: Fresnel reflectance, reflection and refraction directions.
// Directions point away from the surface (wi, wo) as in pbrt; n is the unit normal on the side of wi.
#include <optional>

#include "bouguer/core/math.h"

namespace bouguer {

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
