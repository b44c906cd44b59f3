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

// True with probability exactly 1/c (c ≥ 1): a 32-bit draw below the largest multiple of c, by
// rejection (a uniform double of 24 bits would favour large c by up to c·2⁻²⁴).
bool one_in(Rng& rng, std::uint32_t c) {
  const std::uint64_t span = ((std::uint64_t{1} << 32) / c) * c;
  std::uint32_t r;
  do r = rng.next_u32();
  while (r >= span);
  return r % c == 0;
}

// splitmix64's finaliser: the kept collisions' stream from the walks' seed and stream.
std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

// The renderer's walk in a unit medium (σ = 1): flights of detail::draw_optical_depth, directions
// of sample_phase.
ShellExit walk_out_of_sphere(double tau, const PhaseFunction& phase, Rng& rng, ShellCollision* kept, Rng* pick) {
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
    // (Reservoir sampling: the c-th collision replaces the one kept with probability 1/c.)
    if (kept && one_in(*pick, static_cast<std::uint32_t>(collisions))) {
      const Vec3 at = p / tau;
      *kept = ShellCollision{{static_cast<float>(at.x), static_cast<float>(at.y), static_cast<float>(at.z)},
                             {static_cast<float>(d.x), static_cast<float>(d.y), static_cast<float>(d.z)},
                             static_cast<float>(length), collisions};
    }
    const double u1 = rng.next_double(), u2 = rng.next_double();
    d = sample_phase(phase, d, u1, u2).out;
  }
}

ShellTable make_shell_table(const PhaseFunction& phase, std::uint64_t seed, std::uint64_t stream, int classes,
                            bool keep_collisions) {
  Rng rng(seed, stream);
  // (A state and a stream of their own, hashed from the walks': not the walks' own sequence shifted.)
  Rng pick(mix(seed ^ mix(stream)), mix(stream) | (std::uint64_t{1} << 32));
  ShellTable table;
  table.classes = std::clamp(classes, 0, kShellClasses);
  const std::size_t count = static_cast<std::size_t>(table.classes) * kShellEntries;
  table.exits.reserve(count);
  if (keep_collisions) table.kept.resize(count);
  for (int k = 0; k < table.classes; ++k)
    for (int i = 0; i < kShellEntries; ++i)
      table.exits.push_back(walk_out_of_sphere(shell_radius(k), phase, rng,
                                               keep_collisions ? &table.kept[ShellTable::index(k, i)] : nullptr, &pick));
  return table;
}

bool shell_transport_applies(const ScatteringMedium& m) {
  if (!constant(m.density)) return false;
  for (const FieldAbsorber& a : m.absorbers)
    if (!constant(a.field)) return false;
  return true;
}

}  // namespace bouguer
