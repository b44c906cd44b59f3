#pragma once
// Tracking through a scattering medium (#12): the null-scattering formulation of Miller, Georgiev
// and Jarosz 2019 ("A null-scattering path integral formulation of light transport"), with
// spectral MIS over the carried wavelengths.
//
// Only the scattering is tracked. The majorant is σ̄(λ) = σ_s(λ)·ρ̄ with ρ̄ a bound of the density
// on each piece of the segment (media/majorant.h: one piece in a homogeneous medium, one per cell
// the ray crosses in a voxel grid, 8 equal pieces through an analytic field), so a density that
// varies along the ray wastes few null collisions; the absorption's transmittance multiplies the
// throughput in closed form (media/medium.h). Since σ_s(x, λ) = ρ(x)·σ_s(λ), the chance that a
// tentative collision is real, ρ(x)/ρ̄, is the same at every wavelength.
//
// Distances are drawn with the majorant of one carried wavelength, the path's `hero` (uniform for
// each path; in the path tracer stratified over a pixel's samples: integrators/integrators.h).
// Every wavelength k keeps the ratio r_u[k] of the density with which its own majorant would have
// drawn the same events to the hero's, and r_l[k] the same for the ratio-tracking density a light
// connection would have used: a contribution divided by the mean ratio over the wavelengths is the
// one-sample balance combination of the N techniques (one per wavelength), so a strongly
// chromatic σ_s (Rayleigh, milk) converges at every wavelength, not only at those that happen to
// be sampled. Outside scattering media the ratios stay exactly 1.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "bouguer/media/majorant.h"
#include "bouguer/media/medium.h"
#include "bouguer/core/rng.h"

namespace bouguer {

// A path's unidirectional and light-connection density ratios (r_u, r_l above).
template <std::size_t N>
struct SpectralMis {
  SampledSpectrum<N> r_u = SampledSpectrum<N>::constant(1.0f);
  SampledSpectrum<N> r_l = SampledSpectrum<N>::constant(1.0f);
};

// ∫ρ dt over [t0, t1] (finite) along the ray: the exact column density of the medium's scattering
// density (concentration_field.h), so that σ_s(λ)·ρ(x(t))·exp(−σ_s(λ)·∫₀ᵗρ) is the analog
// density of a scattering distance and exp(−σ_s(λ)·∫ρ) the probability of passing through, as a
// bidirectional estimator's MIS needs them. Not the integral of the majorant, which the tracking
// draws with (detail::MajorantWalk::rho_length_m).
template <typename Ray>
double scattering_column_density(const ScatteringMedium& m, const Ray& ray, double t0, double t1) {
  return column_density(m.density, ray.origin, ray.direction, t0, t1);
}

namespace detail {

// An exponentially distributed optical depth from the stream: u at the middle of its 2⁻²⁴ cell,
// never 0. A draw of exactly 0 (one in 2²⁴, so several in a long render) put a collision at the
// segment's start, a vertex on top of the last, and a bidirectional MIS weight of 0/0 (#20).
inline double draw_optical_depth(Rng& rng) { return -std::log1p(-(rng.next_double() + 0x1p-25)); }

// A walk along a segment drawing tentative collisions with the hero's majorant σ_s,hero·ρ̄: how
// many it drew (n) and M = ∫ρ̄ dt over the part it walked.
struct MajorantWalk {
  double rho_length_m = 0.0;
  int collisions = 0;
};

// Walks the majorant's pieces of [0, t_max] along `ray` (media/majorant.h); at each tentative
// collision calls on_collision(t, ρ(x)/ρ̄), which returns false to stop the walk there. Each
// tentative collision is where the optical depth of the hero's majorant since the last one reaches
// an exponential draw τ. Through a grid the τ left at a cell's end carries into the next cell (one
// logarithm per collision, not per cell: the same distribution, since the process is memoryless);
// the homogeneous and analytic walks draw τ afresh in each piece, as they did before the grid had
// its own pieces, so that their images stay bit for bit. Pieces with ρ̄ = 0 draw nothing.
template <typename Ray, typename OnCollision>
MajorantWalk walk_majorant(const ScatteringMedium& m, double sigma_hero, const Ray& ray, double t_max, Rng& rng,
                           OnCollision on_collision) {
  const bool carry = std::holds_alternative<GridField>(m.density);
  auto draw = [&] { return draw_optical_depth(rng); };
  MajorantWalk walk;
  DensityMajorant majorant(m.density, ray.origin, ray.direction, t_max);
  double tau = carry ? draw() : 0.0;
  for (MajorantSegment piece; majorant.next(piece);) {
    const double a = piece.t0, b = piece.t1, rho_bar = piece.density;
    if (!(rho_bar > 0.0)) continue;
    const double rate = sigma_hero * rho_bar;
    if (!carry) tau = draw();
    double t = a;
    for (;;) {
      const double dt = rate > 0.0 ? tau / rate : b - t;
      if (t + dt >= b) {
        walk.rho_length_m += rho_bar * (b - t);
        tau = std::max(0.0, tau - rate * (b - t));
        break;
      }
      t += dt;
      walk.rho_length_m += rho_bar * dt;
      ++walk.collisions;
      const double real = concentration_at(m.density, ray.origin + ray.direction * t) / rho_bar;
      if (!on_collision(t, std::min(1.0, real))) return walk;
      tau = draw();
    }
  }
  return walk;
}

// What a walk multiplies every wavelength's weight by, relative to the hero's: the product over
// its collisions of T_maj,k/T_maj,hero · σ_s,k/σ_s,hero (the ratio of the two majorants' densities
// for each collision, the wavelength-independent ρ/ρ̄ or 1 − ρ/ρ̄ left out) and the ratio of the
// pass-through probabilities to its end. The majorant is constant within a piece and σ̄ = σ_s·ρ̄,
// so this is one exponential per wavelength for the whole walk, whatever the pieces (M sums
// ρ̄·length over the very pieces the walk drew with):
//   exp(−(σ_s,k − σ_s,hero)·M) · (σ_s,k/σ_s,hero)^n.
// After a dispersive interface (`single`) only the hero is carried: all ones.
// The loop of walk_factor over n wavelengths, out of line for its AVX2 clone (scattering.cpp).
void walk_factor_wide(const float* sigma_s, std::size_t n, float h, float m, float collisions, float* out);

template <std::size_t N>
SampledSpectrum<N> walk_factor(const SampledSpectrum<N>& sigma_s, std::size_t hero, bool single,
                               const MajorantWalk& walk) {
  if (single) return SampledSpectrum<N>::constant(1.0f);
  const float h = sigma_s[hero], m = static_cast<float>(walk.rho_length_m);
  SampledSpectrum<N> f;
  if constexpr (N > 8) {  // full mode: the same arithmetic, 8 wide where the CPU has AVX2
    walk_factor_wide(sigma_s.v.data(), N, h, m, static_cast<float>(walk.collisions), f.v.data());
    return f;
  }
  if (walk.collisions == 0) {
    for (std::size_t k = 0; k < N; ++k) f[k] = exp_limited(-(sigma_s[k] - h) * m);
    return f;
  }
  // n ≥ 1 only when h > 0; a wavelength that does not scatter cannot have drawn a collision.
  const auto n = static_cast<float>(walk.collisions);
  const float log_h = log_positive(h);
  for (std::size_t k = 0; k < N; ++k) {
    const float s = sigma_s[k];
    const float log_ratio = s > 0.0f ? n * (log_positive(std::max(s, 1e-30f)) - log_h) : -1e30f;
    f[k] = exp_limited(-(s - h) * m + log_ratio);
  }
  return f;
}

}  // namespace detail

// Delta tracking from ray.origin over [0, t_max] (t_max finite: the next surface): the first
// real scattering event, or nothing when the path reaches t_max. beta and the ratios are updated
// (and beta multiplied by the absorption up to where the path stops). Distances follow the
// majorant of w.hero; after a dispersive interface, of the kept wavelength.
struct MediumEvent {
  bool scattered = false;
  double t = 0.0;
};

template <typename Tables, typename Ray, std::size_t N>
MediumEvent sample_scattering(const ScatteringMedium& m, const Tables& tables, const Ray& ray, double t_max,
                              const SampledWavelengths<N>& w, Rng& rng, SampledSpectrum<N>& beta,
                              SpectralMis<N>& mis) {
  const bool single = w.secondary_terminated();
  const auto hero = static_cast<std::size_t>(single ? w.single : w.hero);
  MediumEvent event;
  double null_ratio = 1.0;  // Π 1/(1 − ρ/ρ̄) over the null collisions: a light connection's density is T_maj·σ̄
  auto on_collision = [&](double t, double real) {
    if (rng.next_double() < real) {  // real: density T_maj·σ_s at the hero
      event = {true, t};
      return false;
    }
    null_ratio /= 1.0 - real;  // null: density T_maj·σ_n, σ_n = σ_s·(ρ̄ − ρ)
    return true;
  };
  if (single) {
    // One wavelength carried (after a dispersive interface or a split): the walk factor is 1 and
    // every other wavelength's throughput is 0, so only the kept one is touched (the same values
    // bit for bit as the full update).
    detail::walk_majorant(m, tables.at_index(m.sigma_s, w, hero), ray, t_max, rng, on_collision);
    if (null_ratio != 1.0) mis.r_l *= static_cast<float>(null_ratio);
    if (!m.absorbers.empty())
      beta[hero] *= absorbers_kept_transmittance(m.absorbers, tables, ray, 0.0, event.scattered ? event.t : t_max, w);
    return event;
  }
  const SampledSpectrum<N> sigma_s = tables.at(m.sigma_s, w);
  const detail::MajorantWalk walk = detail::walk_majorant(m, sigma_s[hero], ray, t_max, rng, on_collision);
  const SampledSpectrum<N> f = detail::walk_factor(sigma_s, hero, single, walk);
  beta *= f;
  mis.r_u *= f;
  mis.r_l *= f * static_cast<float>(null_ratio);
  beta *= absorbers_transmittance(m.absorbers, tables, ray, 0.0, event.scattered ? event.t : t_max, w);
  return event;
}

// Where sample_scattering would stop in a homogeneous medium (constant density) if no surface
// were in the way: its first tentative collision, which is real there, at carried wavelength
// `hero`, from a copy of the stream (the walk's own stream is not advanced): walk_majorant's
// arithmetic for the one piece of a constant density. Infinite for any other density.
// (the same from σ_s,hero·ρ already read: the walk keeps it, dense_media.h)
inline double first_collision_at_rate_m(double rate_per_m, Rng rng) {
  if (!(rate_per_m > 0.0)) return std::numeric_limits<double>::infinity();
  return detail::draw_optical_depth(rng) / rate_per_m;
}
template <typename Tables, std::size_t N>
double first_collision_m(const ScatteringMedium& m, const Tables& tables, const SampledWavelengths<N>& w,
                         std::size_t hero, Rng rng) {
  const auto* constant = std::get_if<ConstantField>(&m.density);
  if (!constant || !(constant->value > 0.0)) return std::numeric_limits<double>::infinity();
  const double sigma_hero = tables.at_index(m.sigma_s, w, hero);
  return first_collision_at_rate_m(sigma_hero * constant->value, rng);
}

// sample_scattering's outcome for one wavelength carried (`hero` = w.single) in a constant density,
// where first_collision_m found the collision at t below the segment's end: the stream moved past
// the same two draws (the optical depth, and the test of the collision, which a constant density
// always passes), the kept wavelength's throughput times the absorbers' transmittance to t, the
// ratios unchanged (no null collision). Bit for bit sample_scattering's (test_scattering.cpp), one
// logarithm and no majorant walk fewer: walk_deep's every collision deep in whole milk.
template <typename Tables, typename Ray, std::size_t N>
void take_first_collision(const ScatteringMedium& m, const Tables& tables, const Ray& ray, double t,
                          const SampledWavelengths<N>& w, std::size_t hero, Rng& rng, SampledSpectrum<N>& beta) {
  rng.next_double();
  rng.next_double();
  if (!m.absorbers.empty()) beta[hero] *= absorbers_kept_transmittance(m.absorbers, tables, ray, 0.0, t, w);
}

// Ratio tracking over [0, t_max] for a connection (to a light or the camera): multiplies tr by an
// unbiased estimate of the transmittance (times the absorption, exact), and the ratios by the
// densities of the two strategies for the same tentative collisions (drawn with density T_maj·σ̄
// at the hero; the estimate keeps σ_n/σ̄ = 1 − ρ/ρ̄ at each). A faint estimate plays Russian
// roulette.
template <typename Tables, typename Ray, std::size_t N>
void ratio_track(const ScatteringMedium& m, const Tables& tables, const Ray& ray, double t_max,
                 const SampledWavelengths<N>& w, Rng& rng, SampledSpectrum<N>& tr, SpectralMis<N>& mis) {
  if (std::isinf(t_max)) {
    tr = {};
    return;
  }
  const SampledSpectrum<N> sigma_s = tables.at(m.sigma_s, w);
  const bool single = w.secondary_terminated();
  const auto hero = static_cast<std::size_t>(single ? w.single : w.hero);
  // A constant density is its own majorant: every tentative collision is real and ends the
  // estimate at 0, so it is 1 with the probability exp(−σ_hero·ρ·t) of none (a coin toss, noisy
  // where the optical depth is 1 or more) times the walk factor of none. Its expectation given the
  // ray is taken instead: exp(−σ_k·ρ·t) at each wavelength, the ratios those of a walk with no
  // collision (the only ones a non-zero estimate ever had, so every weight computed from them is
  // unchanged and the contribution's expectation too; the ratios are the densities the walks that
  // pass here have). At an optical depth of 1.5 the toss's relative variance is e^1.5 − 1 = 3.5.
  if (const auto* constant = std::get_if<ConstantField>(&m.density)) {
    const double rho_length_m = std::max(0.0, constant->value) * t_max;
    const SampledSpectrum<N> f = detail::walk_factor(sigma_s, hero, single, detail::MajorantWalk{rho_length_m, 0});
    tr *= f * static_cast<float>(std::exp(-static_cast<double>(sigma_s[hero]) * rho_length_m));
    mis.r_u *= f;
    mis.r_l *= f;
    tr *= absorbers_transmittance(m.absorbers, tables, ray, 0.0, t_max, w);
    return;
  }
  double kept = 1.0, roulette = 1.0;  // Π (1 − ρ/ρ̄): the hero's own estimate; the roulette's 1/survival
  bool killed = false;
  const detail::MajorantWalk walk = detail::walk_majorant(m, sigma_s[hero], ray, t_max, rng, [&](double, double real) {
    kept *= 1.0 - real;
    if (kept == 0.0) return false;
    if (kept * roulette < 0.1) {
      if (rng.next_double() < 0.75) {
        killed = true;
        return false;
      }
      roulette *= 4.0;
    }
    return true;
  });
  if (killed || kept == 0.0) {
    tr = {};
    return;
  }
  const SampledSpectrum<N> f = detail::walk_factor(sigma_s, hero, single, walk);
  tr *= f * static_cast<float>(kept * roulette);
  mis.r_u *= f * static_cast<float>(kept);
  mis.r_l *= f;
  tr *= absorbers_transmittance(m.absorbers, tables, ray, 0.0, t_max, w);
}

}  // namespace bouguer
