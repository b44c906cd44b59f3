#include "bouguer/media/mie.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>
#include <vector>

namespace bouguer {
namespace {

using Complex = std::complex<double>;

// D_n(y) = ψ_n'(y)/ψ_n(y) for n = 0..n_max, by the downward recurrence
// D_{n-1} = n/y − 1/(D_n + n/y), started at zero well above the terms needed: the upward
// recurrence is unstable when |Im y| is large.
std::vector<Complex> log_derivative(Complex y, int n_terms) {
  const int n_start = std::max(n_terms, static_cast<int>(std::ceil(std::abs(y)))) + 15;
  std::vector<Complex> d(static_cast<std::size_t>(n_start) + 1, Complex{0.0, 0.0});
  for (int n = n_start; n > 0; --n) {
    const Complex n_over_y = static_cast<double>(n) / y;
    d[static_cast<std::size_t>(n - 1)] = n_over_y - 1.0 / (d[static_cast<std::size_t>(n)] + n_over_y);
  }
  return d;
}

}  // namespace

int mie_terms(double size_parameter) {
  return static_cast<int>(size_parameter + 4.0 * std::cbrt(size_parameter) + 2.0);
}

MieEfficiencies mie_sphere(double x, Complex m) {
  assert(x > 0.0);
  const int n_terms = mie_terms(x);
  const std::vector<Complex> d = log_derivative(m * x, n_terms);
  // Riccati-Bessel ψ_n(x) = x j_n(x) and χ_n(x) = −x y_n(x), upward from n = −1 and 0;
  // ξ_n = ψ_n − i χ_n.
  double psi_prev = std::cos(x), psi = std::sin(x);
  double chi_prev = -std::sin(x), chi = std::cos(x);
  Complex xi = {psi, -chi};
  Complex a_prev, b_prev;
  double sum_sca = 0.0, sum_ext = 0.0, sum_g = 0.0;
  for (int n = 1; n <= n_terms; ++n) {
    const double dn = static_cast<double>(n);
    const double psi_next = (2.0 * dn - 1.0) / x * psi - psi_prev;
    const double chi_next = (2.0 * dn - 1.0) / x * chi - chi_prev;
    psi_prev = psi, psi = psi_next, chi_prev = chi, chi = chi_next;
    const Complex xi_prev = xi;
    xi = {psi, -chi};
    const Complex dm = d[static_cast<std::size_t>(n)];
    const Complex ta = dm / m + dn / x, tb = m * dm + dn / x;
    const Complex a = (ta * psi - psi_prev) / (ta * xi - xi_prev);
    const Complex b = (tb * psi - psi_prev) / (tb * xi - xi_prev);
    sum_sca += (2.0 * dn + 1.0) * (std::norm(a) + std::norm(b));
    sum_ext += (2.0 * dn + 1.0) * (a.real() + b.real());
    // <cos θ> (Bohren & Huffman eq. 4.62), the cross terms of n − 1 and n gathered at n.
    sum_g += (2.0 * dn + 1.0) / (dn * (dn + 1.0)) * (a * std::conj(b)).real();
    if (n > 1)
      sum_g += (dn - 1.0) * (dn + 1.0) / dn * (a_prev * std::conj(a) + b_prev * std::conj(b)).real();
    a_prev = a, b_prev = b;
  }
  const double k = 2.0 / (x * x);
  MieEfficiencies e;
  e.q_sca = k * sum_sca;
  e.q_ext = k * sum_ext;
  e.g = e.q_sca > 0.0 ? 2.0 * k * sum_g / e.q_sca : 0.0;
  return e;
}

double integrate_log_simpson(const std::function<double(double)>& f, double a, double b, int intervals) {
  assert(a > 0.0 && b > a && intervals >= 2 && intervals % 2 == 0);
  const double la = std::log(a), h = (std::log(b) - la) / intervals;
  double sum = 0.0;
  for (int i = 0; i <= intervals; ++i) {
    const double r = std::exp(la + i * h);
    const double w = (i == 0 || i == intervals) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    sum += w * f(r) * r;  // dr = r d(ln r)
  }
  return sum * h / 3.0;
}

MieBulk mie_bulk(const SphereSuspension& s, double host_index, double wavelength_nm, int intervals) {
  const double wavelength_m = wavelength_nm * 1e-9;
  const Complex m = s.particle_index / host_index;
  double sca = 0.0, abs = 0.0, sca_g = 0.0;
  // One pass over the nodes, the three integrals side by side.
  const double la = std::log(s.r_min_m), h = (std::log(s.r_max_m) - la) / intervals;
  for (int i = 0; i <= intervals; ++i) {
    const double r = std::exp(la + i * h);
    const double w = (i == 0 || i == intervals) ? 1.0 : (i % 2 == 1 ? 4.0 : 2.0);
    const double n = s.number_density_per_m3_per_m(r);
    if (!(n > 0.0)) continue;
    const MieEfficiencies e = mie_sphere(2.0 * std::numbers::pi * host_index * r / wavelength_m, m);
    const double weight = w * n * std::numbers::pi * r * r * r;  // N π r² · r d(ln r)
    sca += weight * e.q_sca;
    abs += weight * e.q_abs();
    sca_g += weight * e.q_sca * e.g;
  }
  MieBulk out;
  out.sigma_s_per_m = sca * h / 3.0;
  out.sigma_a_per_m = abs * h / 3.0;
  out.g = sca > 0.0 ? sca_g / sca : 0.0;
  return out;
}

}  // namespace bouguer
