#include "bouguer/materials/fresnel.h"

#include <algorithm>
#include <cmath>

namespace bouguer {
namespace {
// cos θt from Snell's law, or nullopt under total internal reflection.
std::optional<double> cos_theta_t(double cos_theta_i, double eta_i, double eta_t) {
  const double sin2_theta_i = std::max(0.0, 1.0 - cos_theta_i * cos_theta_i);
  const double sin2_theta_t = sin2_theta_i * (eta_i / eta_t) * (eta_i / eta_t);
  if (sin2_theta_t >= 1.0) return std::nullopt;
  return std::sqrt(1.0 - sin2_theta_t);
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

// cos θt once for both polarisations (it runs at every interface a path meets).
double fresnel_dielectric(double cos_theta_i, double eta_i, double eta_t) {
  const auto ct = cos_theta_t(cos_theta_i, eta_i, eta_t);
  if (!ct) return 1.0;
  return 0.5 * (reflectance_s(cos_theta_i, *ct, eta_i, eta_t) + reflectance_p(cos_theta_i, *ct, eta_i, eta_t));
}

Vec3 reflect(const Vec3& w, const Vec3& n) { return n * (2.0 * dot(w, n)) - w; }

std::optional<Vec3> refract(const Vec3& wi, const Vec3& n, double eta_i, double eta_t) {
  const double cos_i = dot(wi, n);
  const auto ct = cos_theta_t(cos_i, eta_i, eta_t);
  if (!ct) return std::nullopt;
  const double eta = eta_i / eta_t;
  return normalize(-wi * eta + n * (eta * cos_i - *ct));
}

}  // namespace bouguer
