#pragma once
// Shell transport (#37) for a scattering medium whose density and absorbers are constant: where a
// walk of one wavelength is more than a sphere's radius r from every surface and point lamp, the
// whole of its walk until it first leaves that sphere is drawn at once from a table of such walks,
// made before the render by the very tracking the walk would do (Moon, Walter & Marschner 2007,
// "Rendering discrete random media using precomputed scattering solutions"; Müller, Papas, Gross,
// Jarosz & Novák 2016, "Efficient rendering of heterogeneous polydisperse granular media": shell
// transport). In a homogeneous medium with one phase function the walk inside a sphere, measured
// in mean free paths, depends on nothing but the sphere's optical radius τ = σ_s·ρ·r, and given
// where it starts (the centre) and the direction it is flying in (+z), its outcome is the point and
// direction where it leaves, the length it travelled (the absorbers' transmittance, exp(−σ_a·l)
// in closed form, reads only that) and its count of collisions.
//
// Exact, not an approximation: a table's entries are walks drawn by the renderer's own sampling
// (the exponential flight of media/scattering.h, sample_phase), independent of one another and of
// every path; a path takes distinct entries of a class (walk.h: ShellUse), so those it takes are
// independent draws of the same distribution, and the image's expectation is the analog walk's. What
// the paths of one table share is a correlation between pixels (as the light subpaths a light
// tracer splats into many pixels share theirs), none within a pixel: each of a pixel's samples has
// a table of its own (integrators/shell_hops.h). A smaller sphere than the free one is as exact, so
// the radii are a geometric set of classes and a walk takes the largest that fits.
#include <array>
#include <cstdint>
#include <vector>

#include "bouguer/media/medium.h"
#include "bouguer/media/phase.h"

namespace bouguer {

// The classes' optical radii: kShellSmallestRadius·kShellRatio^k, k < kShellClasses (12 to 205
// mean free paths). Chosen on the glass of whole milk (docs/performance.md): smaller spheres and
// finer classes save time but cost colour, since the four walks of one wavelength a path splits
// into (dense_media.h) stay in step only while they take the same classes, and a class boundary
// between their bounds parts them; a ninth class costs more to make (about 0.07·τ² collisions a
// walk at g = 0.86) than it saves.
inline constexpr int kShellClasses = 8;
inline constexpr double kShellSmallestRadius = 12.0;
inline constexpr double kShellRatio = 1.5;
// The largest class a medium gets makes walks of at most this many mean free paths on average
// ((1 − g)·τ²/2, plus at most τ; about as many collisions): every class at g = 0.86, to τ = 61
// when isotropic.
inline constexpr double kShellMaxWalkLength = 4000.0;
// Walks per class in one table: a path takes at most this many spheres of one class (then walks on
// as before), and a table costs this many walks of each class to make.
inline constexpr int kShellEntries = 16;

double shell_radius(int k);
// The largest class whose radius is at most `optical_radius`; −1 if none.
int shell_class(double optical_radius);

// Where a walk from the centre of a sphere of optical radius τ, flying along +z, first leaves it:
// the point on the unit sphere (times τ: where it left), its direction of flight there, the optical
// length it travelled and its scattering events. collisions > kMaxShellCollisions: a walk that did
// not leave within that many (the renderer's kMaxScatterings would end it).
struct ShellExit {
  std::array<float, 3> position{};
  std::array<float, 3> direction{};
  float length = 0.0f;
  std::int32_t collisions = 0;
};
inline constexpr std::int32_t kMaxShellCollisions = 100000;

// One of a walk's collisions drawn uniformly (each of its `collisions` with probability 1/n): where
// it fell (in units of the sphere's radius: within the unit ball), the direction the walk arrived
// there along, the optical length travelled to it and which it was (1 to n). For scenes with
// point, spot or distant lamps, which only connections reach: n times the connection from this one
// collision has the expectation of the connections from all n (integrators/shell_hops.h).
struct ShellCollision {
  std::array<float, 3> position{};
  std::array<float, 3> direction{};
  float length = 0.0f;
  std::int32_t ordinal = 0;
};

struct ShellTable {
  std::vector<ShellExit> exits;  // classes × kShellEntries, class-major
  // The same walks' collisions drawn uniformly, where the table keeps them (else empty).
  std::vector<ShellCollision> kept;
  int classes = 0;               // the first `classes` of kShellClasses
  const ShellExit& at(int k, int entry) const { return exits[index(k, entry)]; }
  const ShellCollision& kept_at(int k, int entry) const { return kept[index(k, entry)]; }
  static std::size_t index(int k, int entry) {
    return static_cast<std::size_t>(k) * kShellEntries + static_cast<std::size_t>(entry);
  }
};

// One walk of a table: from the centre of the sphere of optical radius τ, flying along +z, until it
// leaves (the tests draw many). With `kept`, one of its collisions drawn uniformly by reservoir
// sampling from `pick`'s numbers (exactly: the c-th replaces the one kept with probability 1/c, an
// integer draw; the walk's own stream is not touched, so its walks are the same kept or not); left
// as it is where the walk made none.
class Rng;
ShellExit walk_out_of_sphere(double tau, const PhaseFunction& phase, Rng& rng, ShellCollision* kept = nullptr,
                             Rng* pick = nullptr);

// A table of walks for `phase` of the first `classes` classes (at most kShellClasses), drawn from
// the stream (seed, stream); with `keep_collisions`, each walk's uniformly drawn collision too
// (drawn from a stream of their own: the exits are the same either way).
ShellTable make_shell_table(const PhaseFunction& phase, std::uint64_t seed, std::uint64_t stream,
                            int classes = kShellClasses, bool keep_collisions = false);

// Whether a scattering medium's walks can be drawn so: a constant density and constant absorbers.
bool shell_transport_applies(const ScatteringMedium& m);

}  // namespace bouguer
