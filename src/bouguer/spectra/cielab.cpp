#include "bouguer/spectra/cielab.h"

#include <cmath>
#include <numbers>

#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {
namespace {

double lab_f(double t) {
  constexpr double delta = 6.0 / 29.0;
  if (t > delta * delta * delta) return std::cbrt(t);
  return t / (3.0 * delta * delta) + 4.0 / 29.0;
}

double degrees(double radians) { return radians * 180.0 / std::numbers::pi; }
double radians(double degrees) { return degrees * std::numbers::pi / 180.0; }

// Hue angle in degrees in [0, 360); 0 for a neutral colour (a = b = 0), as Sharma et al. specify.
double hue_deg(double b, double a) {
  if (a == 0.0 && b == 0.0) return 0.0;
  const double h = degrees(std::atan2(b, a));
  return h < 0.0 ? h + 360.0 : h;
}

}  // namespace

Vec3 d65_white_xyz() { return xy_to_xyz(kD65White.x, kD65White.y); }

Lab xyz_to_lab(const Vec3& xyz, const Vec3& white_xyz) {
  const double fx = lab_f(xyz.x / white_xyz.x);
  const double fy = lab_f(xyz.y / white_xyz.y);
  const double fz = lab_f(xyz.z / white_xyz.z);
  return {116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)};
}

double ciede2000(const Lab& lab1, const Lab& lab2) {
  const double c1 = std::hypot(lab1.a, lab1.b);
  const double c2 = std::hypot(lab2.a, lab2.b);
  const double c_mean7 = std::pow((c1 + c2) / 2.0, 7.0);
  const double g = 0.5 * (1.0 - std::sqrt(c_mean7 / (c_mean7 + std::pow(25.0, 7.0))));
  const double a1p = (1.0 + g) * lab1.a;
  const double a2p = (1.0 + g) * lab2.a;
  const double c1p = std::hypot(a1p, lab1.b);
  const double c2p = std::hypot(a2p, lab2.b);
  const double h1p = hue_deg(lab1.b, a1p);
  const double h2p = hue_deg(lab2.b, a2p);

  const double dLp = lab2.L - lab1.L;
  const double dCp = c2p - c1p;
  double dhp = 0.0;
  if (c1p * c2p != 0.0) {
    dhp = h2p - h1p;
    if (dhp > 180.0) dhp -= 360.0;
    else if (dhp < -180.0) dhp += 360.0;
  }
  const double dHp = 2.0 * std::sqrt(c1p * c2p) * std::sin(radians(dhp / 2.0));

  const double Lp_mean = (lab1.L + lab2.L) / 2.0;
  const double Cp_mean = (c1p + c2p) / 2.0;
  double hp_mean = h1p + h2p;
  if (c1p * c2p != 0.0) {
    if (std::abs(h1p - h2p) <= 180.0) hp_mean /= 2.0;
    else hp_mean = (h1p + h2p < 360.0) ? (hp_mean + 360.0) / 2.0 : (hp_mean - 360.0) / 2.0;
  }

  const double t = 1.0 - 0.17 * std::cos(radians(hp_mean - 30.0)) + 0.24 * std::cos(radians(2.0 * hp_mean)) +
                   0.32 * std::cos(radians(3.0 * hp_mean + 6.0)) - 0.20 * std::cos(radians(4.0 * hp_mean - 63.0));
  const double d_theta = 30.0 * std::exp(-std::pow((hp_mean - 275.0) / 25.0, 2.0));
  const double cp_mean7 = std::pow(Cp_mean, 7.0);
  const double r_c = 2.0 * std::sqrt(cp_mean7 / (cp_mean7 + std::pow(25.0, 7.0)));
  const double l50 = (Lp_mean - 50.0) * (Lp_mean - 50.0);
  const double s_l = 1.0 + 0.015 * l50 / std::sqrt(20.0 + l50);
  const double s_c = 1.0 + 0.045 * Cp_mean;
  const double s_h = 1.0 + 0.015 * Cp_mean * t;
  const double r_t = -std::sin(radians(2.0 * d_theta)) * r_c;

  const double tl = dLp / s_l, tc = dCp / s_c, th = dHp / s_h;
  return std::sqrt(tl * tl + tc * tc + th * th + r_t * tc * th);
}

}  // namespace bouguer
