#include "bouguer/media/shell_walks.h"

#include <algorithm>
#include <cmath>

#include "bouguer/core/rng.h"
#include "bouguer/media/scattering.h"

namespace bouguer {

double shell_radius(int k) { return kShellSmallestRadius * std::pow(kShellRatio, k); }

int shell_class(double optical_radius) {
  if (!(optical_radius >= kShellSmallestRadius)) return -1;
  int k = 0;
  while (k + 1 < kShellClasses && shell_radius(k + 1) <= optical_radius) ++k;
  return k;
}

namespace {

bool constant(const ConcentrationField& f) { return std::holds_alternative<ConstantField>(f); }

}  // namespace

// The renderer's walk in a unit medium (σ = 1): flights of detail::draw_optical_depth, directions
// of sample_phase.
ShellExit walk_out_of_sphere(double tau, const PhaseFunction& phase, Rng& rng) {
  Vec3 p{0.0, 0.0, 0.0}, d{0.0, 0.0, 1.0};
  double length = 0.0;
  std::int32_t collisions = 0;
  for (;;) {
    const double t = detail::draw_optical_depth(rng);
    // The distance to the sphere along d from p inside it (the far root).
    const double b = dot(p, d), c = dot(p, p) - tau * tau;
    const double out = -b + std::sqrt(std::max(0.0, b * b - c));
    if (t >= out || collisions > kMaxShellCollisions) {
      const Vec3 q = normalize(p + d * out);
      length += out;
      return ShellExit{{static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z)},
                       {static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z)},
                       static_cast<float>(length),
                       collisions};
    }
    p = p + d * t;
    length += t;
    ++collisions;
    const double u1 = rng.next_double(), u2 = rng.next_double();
    d = sample_phase(phase, d, u1, u2).out;
  }
}

ShellTable make_shell_table(const PhaseFunction& phase, std::uint64_t seed, std::uint64_t stream, int classes) {
  Rng rng(seed, stream);
  ShellTable table;
  table.classes = std::clamp(classes, 0, kShellClasses);
  table.exits.reserve(static_cast<std::size_t>(table.classes) * kShellEntries);
  for (int k = 0; k < table.classes; ++k)
    for (int i = 0; i < kShellEntries; ++i) table.exits.push_back(walk_out_of_sphere(shell_radius(k), phase, rng));
  return table;
}

bool shell_transport_applies(const ScatteringMedium& m) {
  if (!constant(m.density)) return false;
  for (const FieldAbsorber& a : m.absorbers)
    if (!constant(a.field)) return false;
  return true;
}

}  // namespace bouguer
