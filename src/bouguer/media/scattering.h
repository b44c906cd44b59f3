#pragma once
// Tracking through a scattering medium (#12): the null-scattering formulation of Miller, Georgiev
// and Jarosz 2019 ("A null-scattering path integral formulation of light transport"), with
// spectral MIS over the carried wavelengths.
//
// Only the scattering is tracked. The majorant is σ̄(λ) = σ_s(λ)·ρ̄ with ρ̄ the largest density on
// a piece of the segment (kMajorantPieces pieces, each with its own bound, so a density that
// falls along the ray wastes few null collisions); the absorption's transmittance multiplies the
// throughput in closed form (media/medium.h). Since σ_s(x, λ) = ρ(x)·σ_s(λ), the chance that a
// tentative collision is real, ρ(x)/ρ̄, is the same at every wavelength.
//
// Distances are drawn with the majorant of one carried wavelength, the path's `hero` (drawn
// uniformly per path). Every wavelength k keeps the ratio r_u[k] of the density with which its
// own majorant would have drawn the same events to the hero's, and r_l[k] the same for the
// ratio-tracking density a light connection would have used: a contribution divided by the mean
// ratio over the wavelengths is the one-sample balance combination of the N techniques (one per
// wavelength), so a strongly chromatic σ_s (Rayleigh, milk) converges at every wavelength, not
// only at those that happen to be sampled. Outside scattering media the ratios stay exactly 1.
#include <algorithm>
#include <cmath>
#include <cstddef>

#include "bouguer/media/medium.h"
#include "bouguer/render/rng.h"

namespace bouguer {

// A path's unidirectional and light-connection density ratios (r_u, r_l above).
template <std::size_t N>
struct SpectralMis {
  SampledSpectrum<N> r_u = SampledSpectrum<N>::constant(1.0f);
  SampledSpectrum<N> r_l = SampledSpectrum<N>::constant(1.0f);
};

// The density bound is taken per piece; a homogeneous medium needs one.
inline constexpr int kMajorantPieces = 8;

namespace detail {

// exp(−(σ̄_k − σ̄_hero)·dt) for every k: T_maj over the hero's T_maj, in one exponent (their ratio
// can exceed any float where T_maj underflows). Capped at e^80: a weight that large has a chance
// below e^−80 of being drawn.
template <std::size_t N>
SampledSpectrum<N> majorant_ratio(const SampledSpectrum<N>& sigma_bar, std::size_t hero, double dt) {
  SampledSpectrum<N> r;
  const double h = sigma_bar[hero];
  for (std::size_t k = 0; k < N; ++k) r[k] = static_cast<float>(std::exp(std::min(80.0, -(sigma_bar[k] - h) * dt)));
  return r;
}

// Walks the pieces of [0, t_max] along `ray`, drawing tentative collisions with the hero's
// majorant. At each: on_collision(t, ρ/ρ̄, factor, sigma_ratio) where factor = T_maj/T_maj,hero
// and sigma_ratio = σ_s/σ_s,hero (per wavelength); it returns false to stop the walk. When a
// piece is passed, on_pass(factor). Returns whether the walk was stopped.
// After a dispersive interface (`single`) only the hero is carried: every ratio is 1.
template <std::size_t N, typename Ray, typename OnCollision, typename OnPass>
bool walk_majorant(const ScatteringMedium& m, const SampledSpectrum<N>& sigma_s, const Ray& ray, double t_max,
                   std::size_t hero, bool single, Rng& rng, OnCollision on_collision, OnPass on_pass) {
  const bool homogeneous = std::holds_alternative<ConstantField>(m.density);
  const int pieces = homogeneous ? 1 : kMajorantPieces;
  const float sigma_hero = sigma_s[hero];
  SampledSpectrum<N> sigma_ratio = SampledSpectrum<N>::constant(1.0f);
  if (sigma_hero > 0.0f && !single)
    for (std::size_t k = 0; k < N; ++k) sigma_ratio[k] = sigma_s[k] / sigma_hero;
  auto ratio = [&](const SampledSpectrum<N>& sigma_bar, double dt) {
    return single ? SampledSpectrum<N>::constant(1.0f) : majorant_ratio(sigma_bar, hero, dt);
  };
  for (int p = 0; p < pieces; ++p) {
    const double a = t_max * p / pieces, b = p + 1 == pieces ? t_max : t_max * (p + 1) / pieces;
    const double rho_bar = max_concentration_on(m.density, ray.origin, ray.direction, a, b);
    if (!(rho_bar > 0.0)) continue;
    const SampledSpectrum<N> sigma_bar = sigma_s * static_cast<float>(rho_bar);
    const double rate = sigma_bar[hero];
    double t = a;
    for (;;) {
      if (!(rate > 0.0)) {  // the hero does not scatter here: it passes with certainty
        on_pass(ratio(sigma_bar, b - t));
        break;
      }
      const double dt = -std::log1p(-rng.next_double()) / rate;
      if (t + dt >= b) {
        on_pass(ratio(sigma_bar, b - t));
        break;
      }
      t += dt;
      const double real = concentration_at(m.density, ray.origin + ray.direction * t) / rho_bar;
      if (!on_collision(t, std::min(1.0, real), ratio(sigma_bar, dt), sigma_ratio)) return true;
    }
  }
  return false;
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
  const SampledSpectrum<N> sigma_s = tables.at(m.sigma_s, w);
  const bool single = w.secondary_terminated();
  MediumEvent event;
  detail::walk_majorant<N>(
      m, sigma_s, ray, t_max, static_cast<std::size_t>(single ? w.single : w.hero), single, rng,
      [&](double t, double real, const SampledSpectrum<N>& factor, const SampledSpectrum<N>& sigma_ratio) {
        if (rng.next_double() < real) {
          // Real: density T_maj·σ_s at the hero. σ_s(x) = ρ(x)·σ_s, so ρ cancels in the ratio.
          const SampledSpectrum<N> f = factor * sigma_ratio;
          beta *= f;
          mis.r_u *= f;
          event = {true, t};
          return false;
        }
        // Null: density T_maj·σ_n at the hero, σ_n = σ_s·(ρ̄ − ρ); a light connection would have
        // drawn the same point with T_maj·σ̄.
        const SampledSpectrum<N> f = factor * sigma_ratio;
        beta *= f;
        mis.r_u *= f;
        mis.r_l *= f * static_cast<float>(1.0 / (1.0 - real));
        return true;
      },
      [&](const SampledSpectrum<N>& factor) {
        beta *= factor;
        mis.r_u *= factor;
        mis.r_l *= factor;
      });
  beta *= absorbers_transmittance(m.absorbers, tables, ray, 0.0, event.scattered ? event.t : t_max, w);
  return event;
}

// Ratio tracking over [0, t_max] for a connection (to a light or the camera): multiplies tr by an
// unbiased estimate of the transmittance (times the absorption, exact), and the ratios by the
// densities of the two strategies for the same tentative collisions. A faint estimate plays
// Russian roulette.
template <typename Tables, typename Ray, std::size_t N>
void ratio_track(const ScatteringMedium& m, const Tables& tables, const Ray& ray, double t_max,
                 const SampledWavelengths<N>& w, Rng& rng, SampledSpectrum<N>& tr, SpectralMis<N>& mis) {
  if (std::isinf(t_max)) {
    tr = {};
    return;
  }
  const SampledSpectrum<N> sigma_s = tables.at(m.sigma_s, w);
  const bool single = w.secondary_terminated();
  int collisions = 0;
  detail::walk_majorant<N>(
      m, sigma_s, ray, t_max, static_cast<std::size_t>(single ? w.single : w.hero), single, rng,
      [&](double, double real, const SampledSpectrum<N>& factor, const SampledSpectrum<N>& sigma_ratio) {
        // Drawn with density T_maj·σ̄ at the hero; the estimate keeps σ_n/σ̄ = 1 − ρ/ρ̄.
        const SampledSpectrum<N> f = factor * sigma_ratio;
        const SampledSpectrum<N> kept = f * static_cast<float>(1.0 - real);
        tr *= kept;
        mis.r_u *= kept;
        mis.r_l *= f;
        if (++collisions >= 8 && tr.max_value() < 0.1f) {
          if (rng.next_double() < 0.75) {
            tr = {};
            return false;
          }
          tr *= 4.0f;
        }
        return !tr.is_zero();
      },
      [&](const SampledSpectrum<N>& factor) {
        tr *= factor;
        mis.r_u *= factor;
        mis.r_l *= factor;
      });
  if (!tr.is_zero()) tr *= absorbers_transmittance(m.absorbers, tables, ray, 0.0, t_max, w);
}

}  // namespace bouguer
