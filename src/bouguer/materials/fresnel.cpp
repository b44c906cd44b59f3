#include "bouguer/materials/fresnel.h"

#include <algorithm>
#include <cmath>

namespace bouguer {
namespace {
std::optional<double> cos_theta_t(double cos_theta_i, double eta_i, double eta_t) {
  const double c = cos_theta_transmitted(cos_theta_i, eta_i, eta_t);
  if (c < 0.0) return std::nullopt;
  return c;
}

// The s and p reflectances for a given cos θt.
double reflectance_s(double cos_theta_i, double cos_t, double eta_i, double eta_t) {
  const double r = (eta_i * cos_theta_i - eta_t * cos_t) / (eta_i * cos_theta_i + eta_t * cos_t);
  return r * r;
}
double reflectance_p(double cos_theta_i, double cos_t, double eta_i, double eta_t) {
  const double r = (eta_t * cos_theta_i - eta_i * cos_t) / (eta_t * cos_theta_i + eta_i * cos_t);
  return r * r;
}
}  // namespace

double fresnel_dielectric_s(double cos_theta_i, double eta_i, double eta_t) {
  const auto ct = cos_theta_t(cos_theta_i, eta_i, eta_t);
  return ct ? reflectance_s(cos_theta_i, *ct, eta_i, eta_t) : 1.0;
}

double fresnel_dielectric_p(double cos_theta_i, double eta_i, double eta_t) {
  const auto ct = cos_theta_t(cos_theta_i, eta_i, eta_t);
  return ct ? reflectance_p(cos_theta_i, *ct, eta_i, eta_t) : 1.0;
}

double fresnel_dielectric(double cos_theta_i, double eta_i, double eta_t) {
  const double ct = cos_theta_transmitted(cos_theta_i, eta_i, eta_t);
  return ct < 0.0 ? 1.0 : fresnel_dielectric(cos_theta_i, ct, eta_i, eta_t);
}

Vec3 reflect(const Vec3& w, const Vec3& n) { return n * (2.0 * dot(w, n)) - w; }

std::optional<Vec3> refract(const Vec3& wi, const Vec3& n, double eta_i, double eta_t) {
  const double cos_i = dot(wi, n);
  const double ct = cos_theta_transmitted(cos_i, eta_i, eta_t);
  if (ct < 0.0) return std::nullopt;
  return refract(wi, n, cos_i, ct, eta_i / eta_t);
}

}  // namespace bouguer
