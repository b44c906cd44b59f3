#pragma once
// Shell transport in the path tracer's walks (#37; the tables and why they are exact:
// media/shell_walks.h). ShellSet holds the tables of one render call's samples, one per sample
// index and phase function, made before its tiles start from the seed and the sample index alone,
// so a render split into threads, passes or processes reads the very same tables. hop_shell takes
// one sphere for a walk of one wavelength deep in a homogeneous medium: the walk.h loop calls it
// before each ray of a visitor that hops (walk.h: HopsShells).
//
// What a hop leaves out: the vertices inside the sphere, and with them the connections the path
// tracer makes there (next-event estimation, the exit guide, the connections through glass). The
// path after a hop is weighted as one whose last vertex makes no connection (its direction's
// density 0): whatever it meets is found by the walk's own direction alone, with weight 1, so the
// estimate stays unbiased (the strategies at a vertex may be any set, chosen from the path so far,
// as long as the weights of those chosen sum to 1). That holds for every light the walk's own
// directions can reach (area and spherical lamps, the map, the background), not for point, spot
// and distant lamps, which only a connection reaches. In a scene with any, the tables keep one
// collision of each walk drawn uniformly (media/shell_walks.h: ShellCollision), and the path
// tracer connects to those lamps from it alone, times the walk's count of collisions n: its
// expectation is the sum of the n connections the sphere's vertices would have made
// (Radiance::hopped). So that none of those n is worth much (the estimate's variance), the
// spheres stay kShellLampMargin inside the free radius there: every collision lies where the
// analog walk thins its own connections to their floor (dense_media.h): each is worth at most
// e^−7.2 of a lamp's unshadowed light. A walk that crossed its sphere without a collision (about e^−12 of them at
// the smallest) is a flight like any other: its last vertex keeps its connections.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <optional>
#include <numbers>
#include <vector>

#include "bouguer/core/frame.h"
#include "bouguer/integrators/dense_media.h"
#include "bouguer/integrators/media_travel.h"
#include "bouguer/media/shell_walks.h"
#include "bouguer/render/integrator.h"

namespace bouguer {

// The samples a render call makes tables for at once (render_camera_paths walks a longer range in
// chunks): 4 MiB of tables a phase function (8 MiB where they keep collisions).
inline constexpr int kShellChunkSamples = 1024;
// The samples a distributed render makes tables for once a rank and hands to every piece
// (distributed.cpp): 64 MiB a phase function (128 MiB where they keep collisions).
inline constexpr int kShellPrebuiltSamples = 16384;
// The optical depth at which next-event estimation deep in a medium reaches its floor
// (dense_media.h: exp(kNeeFullDepth − τ) = kNeeFloor, τ = 3 + ln 64): in a scene with point, spot
// or distant lamps a sphere keeps this far, at the walk's wavelength, inside the free radius.
inline const double kShellLampMargin = kNeeFullDepth - std::log(kNeeFloor);

class ShellSet {
 public:
  // Shell transport for a render of `scene` with `seed`: which media get tables (keeping a
  // collision of each walk where the scene has a point, spot or distant lamp: see above), those that can hold a sphere of the
  // smallest class (shell_transport_applies, enclosed by some object, and σ_s·ρ at its largest
  // over the wavelengths times the largest sphere in the box of a surface it borders at least
  // kShellSmallestRadius), with the classes that can fit there. A render of a thin medium gets
  // none, and one of a small ball no large walks. No tables yet: make() makes them.
  ShellSet(const RenderScene& scene, std::uint64_t seed);
  // Whether no medium gets tables.
  bool empty() const { return slots_ == 0; }
  // Whether the tables keep a collision of each walk (the scene has a point, spot or distant lamp).
  bool keeps_collisions() const { return keep_collisions_; }
  // The tables of samples [range.begin, range.end) (those of any range before dropped), on
  // `threads` threads (0: all).
  void make(SampleRange range, int threads);
  // Whether these are the tables of a render of `scene` with `seed` over `r`.
  bool covers(const RenderScene& scene, std::uint64_t seed, SampleRange r) const {
    return &scene == scene_ && seed == seed_ && range_.begin <= r.begin && r.end <= range_.end;
  }
  // Sample s's table for `medium`, or null where the medium has none.
  const ShellTable* table(int sample, int medium) const;

 private:
  const RenderScene* scene_;
  std::uint64_t seed_;
  std::vector<int> slot_of_medium_;  // −1: no table
  int slots_ = 0;
  bool keep_collisions_ = false;
  std::vector<int> classes_;  // by slot
  std::vector<const PhaseFunction*> phases_;  // by slot
  SampleRange range_;
  std::vector<ShellTable> tables_;  // (sample − range.begin) × slots_ + slot
};

// Which entries of each class a walk has taken: the first drawn once per walk (−1: not yet), then
// consecutive ones, so that no entry serves one path twice (a walk splits with its state: its
// walks of one wavelength take the same entries, and stay in step as dense_media.h's split wants).
struct ShellUse {
  int first = -1;
  std::array<std::uint8_t, kShellClasses> taken{};
};

// A sphere taken: where the walk entered it (its centre) and left it (its direction of flight in
// state.ray), the length it travelled and its collisions; where the table keeps collisions, the
// one kept (its point, the direction the walk arrived along, the throughput there at the walk's
// wavelength and which of the collisions it was: the connections to point, spot and distant lamps
// start from it).
struct ShellHop {
  Vec3 centre, exit;
  double length_m = 0.0;
  int collisions = 0;
  bool kept = false;
  Vec3 kept_point, kept_direction;
  float kept_beta = 0.0f;
  int kept_ordinal = 0;
};
// A table's walk cut short is one that kMaxScatterings would end (its collisions say so).
static_assert(kMaxShellCollisions >= kMaxScatterings);

// The largest sphere about the walk's position (state.start, flying along state.ray.direction) that
// `near` (the visitor's bound on the distance to every surface) shows to hold no
// surface, when it is of a class the walk still has entries of; a fresh point query (as far as the
// largest class reaches) where the bound is stale and the position may be deep. On a hop: the
// state's ray leaves the exit along the direction the walk left with, its throughput times the
// absorbers' transmittance over the length travelled. Nothing otherwise (no tables, several
// wavelengths carried, a medium without a table or not enclosed, too near a surface).
template <std::size_t N, typename State>
std::optional<ShellHop> hop_shell(const SceneView<N>& v, const ShellTable* table, State& state,
                                  ShellUse& use, SurfaceDistance& near, const SampledWavelengths<N>& w, Rng& rng) {
  if (!table || !w.secondary_terminated()) return std::nullopt;
  const double sigma_per_m = walk_sigma_min_per_m(v, state.medium, w, near);
  if (!(sigma_per_m > 0.0)) return std::nullopt;
  const Vec3 p = state.start;
  const bool keeps = !table->kept.empty();
  const double margin_m = keeps ? kShellLampMargin / sigma_per_m : 0.0;
  const double smallest_m = kShellSmallestRadius / sigma_per_m + margin_m;
  double safe_m = free_radius_m(v.scene.rays, near, p);
  if (safe_m < smallest_m) {
    // A fresh query, unless the last one (exact below its cap) shows the position shallow: within
    // twice the smallest radius of a surface, where most queries would find no sphere.
    if (near.radius_m >= 0.0 && near.radius_m < near.cap_m &&
        near.radius_m + length(p - near.centre) < 2.0 * smallest_m)
      return std::nullopt;
    query_surface_distance(v, p, sigma_per_m, near, shell_radius(kShellClasses - 1) / sigma_per_m + margin_m);
    safe_m = free_radius_m(v.scene.rays, near, p);
  }
  const int k = std::min(shell_class(sigma_per_m * (safe_m - margin_m)), table->classes - 1);
  if (k < 0 || use.taken[static_cast<std::size_t>(k)] >= kShellEntries) return std::nullopt;
  if (use.first < 0) use.first = static_cast<int>(rng.next_u32() % kShellEntries);
  const int entry = (use.first + use.taken[static_cast<std::size_t>(k)]++) % kShellEntries;
  const ShellExit& e = table->at(k, entry);
  // The table's walk flew along +z; the path's flies along d, turned about it by a uniform angle
  // (the walk's distribution is symmetric about its first direction).
  const double phi = 2.0 * std::numbers::pi * rng.next_double();
  const double c = std::cos(phi), s = std::sin(phi);
  auto turned = [&](const std::array<float, 3>& a) {
    return Vec3{c * a[0] - s * a[1], s * a[0] + c * a[1], static_cast<double>(a[2])};
  };
  const Frame frame(state.ray.direction);
  const double radius_m = shell_radius(k) / sigma_per_m;
  const Vec3 exit = p + frame.to_world(turned(e.position)) * radius_m;
  const Vec3 d = normalize(frame.to_world(turned(e.direction)));
  const double length_m = static_cast<double>(e.length) / sigma_per_m;
  const ScatteringMedium& sm = *scattering_medium(v.scene, state.medium);
  const auto single = static_cast<std::size_t>(w.single);
  ShellHop hop;
  hop.centre = p, hop.exit = exit, hop.length_m = length_m, hop.collisions = e.collisions;
  if (keeps && e.collisions > 0) {
    const ShellCollision& kept = table->kept_at(k, entry);
    const double kept_m = static_cast<double>(kept.length) / sigma_per_m;
    hop.kept = true;
    hop.kept_point = p + frame.to_world(turned(kept.position)) * radius_m;
    hop.kept_direction = normalize(frame.to_world(turned(kept.direction)));
    hop.kept_beta = state.beta[single];
    hop.kept_ordinal = kept.ordinal;
    if (!sm.absorbers.empty())
      hop.kept_beta *= absorbers_kept_transmittance(sm.absorbers, v.tables, Ray{p, d}, 0.0, kept_m, w);
  }
  if (!sm.absorbers.empty())
    state.beta[single] *= absorbers_kept_transmittance(sm.absorbers, v.tables, Ray{p, d}, 0.0, length_m, w);
  state.ray = Ray{exit, d};
  state.start = exit;
  state.cone_width_m += state.cone_spread_rad * length_m;
  return hop;
}

}  // namespace bouguer
