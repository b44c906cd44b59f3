#pragma once
// Phase functions of scattering media (#12): how light scattered at a point in a medium spreads
// over directions, normalised over the sphere (per steradian). Directions are directions of
// travel: θ is the angle between the light's direction before and after the event, so g > 0
// scatters forward (milk, most colloids) and g < 0 back. Sampling is exact (weight 1).
#include <variant>

#include "bouguer/core/math.h"

namespace bouguer {

struct IsotropicPhase {};

// Henyey & Greenstein 1941: p(θ) = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2}), −1 < g < 1, whose mean
// cosine is g.
struct HenyeyGreensteinPhase {
  double g = 0.0;
};

using PhaseFunction = std::variant<IsotropicPhase, HenyeyGreensteinPhase>;

// p for light travelling along `in` scattered into `out` (both unit), per steradian.
double phase_value(const PhaseFunction& phase, const Vec3& in, const Vec3& out);

struct PhaseSample {
  Vec3 out;  // the new direction of travel
  double pdf = 0.0;  // equals phase_value(in, out)
};

// A direction drawn with density phase_value(in, ·) from two uniform numbers in [0, 1).
PhaseSample sample_phase(const PhaseFunction& phase, const Vec3& in, double u1, double u2);

// The mean cosine <cos θ> (g of Henyey-Greenstein, 0 when isotropic).
double mean_cosine(const PhaseFunction& phase);

}  // namespace bouguer
