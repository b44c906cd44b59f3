#pragma once
// Lorenz-Mie theory (#12): how one homogeneous sphere scatters and absorbs a plane wave, and the
// bulk coefficients of a suspension of such spheres. The sphere algorithm follows Bohren & Huffman
// (1983), "Absorption and Scattering of Light by Small Particles", chapter 4 and appendix A
// (BHMIE): the logarithmic derivative D_n(mx) by downward recurrence, the Riccati-Bessel functions
// upward, x + 4x^{1/3} + 2 terms. The host is non-absorbing (real index); a host that absorbs a
// little (water) adds its own σ_a outside this module.
#include <complex>
#include <functional>

namespace bouguer {

struct MieEfficiencies {
  double q_ext = 0.0;  // extinction cross-section over π r²
  double q_sca = 0.0;  // scattering cross-section over π r²
  double g = 0.0;      // asymmetry parameter <cos θ> of the scattered light
  double q_abs() const { return q_ext - q_sca; }
};

// A sphere of size parameter x = 2π n_host r / λ and relative index m = n_particle / n_host
// (Im m ≥ 0 absorbs). x > 0.
MieEfficiencies mie_sphere(double size_parameter, std::complex<double> relative_index);

// The number of terms of the series: x + 4x^{1/3} + 2 (Bohren & Huffman's criterion).
int mie_terms(double size_parameter);

struct MieBulk {
  double sigma_s_per_m = 0.0;
  double sigma_a_per_m = 0.0;  // of the particles only
  double g = 0.0;              // mean cosine of the scattered light, weighted by σ_s
};

// A polydisperse suspension: σ_s = ∫ N(r) π r² Q_sca dr, σ_a = ∫ N(r) π r² Q_abs dr and
// g = ∫ N π r² Q_sca g dr / σ_s, with N(r) the number of particles per m³ per m of radius.
// Quadrature: composite Simpson in ln r over [r_min_m, r_max_m] with `intervals` (even) pieces,
// since the size distributions of colloids are close to log-normal.
struct SphereSuspension {
  std::function<double(double radius_m)> number_density_per_m3_per_m;
  double r_min_m = 0.0, r_max_m = 0.0;
  std::complex<double> particle_index;  // absolute complex index at the wavelength
};
MieBulk mie_bulk(const SphereSuspension& s, double host_index, double wavelength_nm, int intervals);

// ∫ f(r) dr over [a, b] (0 < a < b) by the same quadrature (for normalising a distribution).
double integrate_log_simpson(const std::function<double(double)>& f, double a, double b, int intervals);

}  // namespace bouguer
