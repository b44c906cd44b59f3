#include "bouguer/media/phase.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bouguer/core/frame.h"

namespace bouguer {
namespace {

constexpr double kInv4Pi = 1.0 / (4.0 * std::numbers::pi);

double hg(double g, double cos_theta) {
  const double denom = 1.0 + g * g - 2.0 * g * cos_theta;
  return kInv4Pi * (1.0 - g * g) / (denom * std::sqrt(denom));
}

// cos θ with density ∝ hg(g, ·) by inverting its CDF; near g = 0 the inversion loses precision
// (it divides by g: relative error about 1e-16 / g), and the function is isotropic to 3e-6 there.
double sample_hg_cos(double g, double u) {
  if (std::abs(g) < 1e-6) return 1.0 - 2.0 * u;
  const double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
  return std::clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
}

}  // namespace

double phase_value(const PhaseFunction& phase, const Vec3& in, const Vec3& out) {
  if (const auto* h = std::get_if<HenyeyGreensteinPhase>(&phase)) return hg(h->g, std::clamp(dot(in, out), -1.0, 1.0));
  return kInv4Pi;
}

PhaseSample sample_phase(const PhaseFunction& phase, const Vec3& in, double u1, double u2) {
  const auto* h = std::get_if<HenyeyGreensteinPhase>(&phase);
  const double cos_theta = h ? sample_hg_cos(h->g, u1) : 1.0 - 2.0 * u1;
  const double sin_theta = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  const double phi = 2.0 * std::numbers::pi * u2;
  const Frame frame(in);
  const Vec3 out = normalize(frame.to_world({sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta}));
  // The density of the direction actually returned (after rounding), so pdf and value agree.
  return {out, phase_value(phase, in, out)};
}

double mean_cosine(const PhaseFunction& phase) {
  if (const auto* h = std::get_if<HenyeyGreensteinPhase>(&phase)) return h->g;
  return 0.0;
}

}  // namespace bouguer
