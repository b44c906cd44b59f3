#include "bouguer/integrators/shell_hops.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "bouguer/core/memory.h"
#include "bouguer/spectra/spectrum.h"
#include "bouguer/render/sampling.h"

namespace bouguer {
namespace {

// The tables' streams (render/sampling.h: sample_rng): a "pixel" index beyond any film's, apart
// from every pixel's stream, one per phase function.
constexpr std::uint64_t kShellSalt = 9;
constexpr std::uint64_t kShellPixelBase = std::uint64_t{1} << 40;

bool same_phase(const PhaseFunction& a, const PhaseFunction& b) {
  if (a.index() != b.index()) return false;
  if (const auto* h = std::get_if<HenyeyGreensteinPhase>(&a)) return h->g == std::get<HenyeyGreensteinPhase>(b).g;
  return true;
}

// How many classes fit in the medium `medium` somewhere in the scene: σ_s·ρ at its largest (over
// 360–830 nm) times the largest sphere in the box of any surface it lies on either side of (the
// box's half depth: the surfaces that enclose it bound every sphere in it; a surface it lies
// around, a marble in milk, only adds a class or two to make). Too many classes cost only the
// making of their walks, too few only spheres not taken: neither changes the image's expectation.
int classes_that_fit(const RenderScene& scene, int medium, const ScatteringMedium& m) {
  double radius_m = 0.0;
  for (std::size_t g = 0; g < scene.surfaces.size(); ++g) {
    if (scene.surfaces[g].medium_behind != medium && scene.surfaces[g].medium_front != medium) continue;
    const auto box = scene.rays.bounds(static_cast<std::uint32_t>(g));
    const Vec3 extent = box[1] - box[0];
    radius_m = std::max(radius_m, 0.5 * std::min({extent.x, extent.y, extent.z}));
  }
  const double rho = std::get<ConstantField>(m.density).value;
  const auto* sigma_s = std::get_if<Spectrum>(&scene.spectra[static_cast<std::size_t>(m.sigma_s)].source);
  if (!sigma_s) return 0;
  int classes = shell_class(max_value(*sigma_s) * rho * radius_m) + 1;
  // Nor more than a walk of kShellMaxWalkLength can make: the walk out of a sphere travels
  // (1 − g)·τ²/2 + τ·E[p·d] mean free paths (test_shell_transport.cpp's martingale), so an isotropic
  // or backward medium's largest spheres would cost far more to make than a forward one's.
  const double g = mean_cosine(m.phase);
  while (classes > 0 && (1.0 - g) * shell_radius(classes - 1) * shell_radius(classes - 1) / 2.0 > kShellMaxWalkLength)
    --classes;
  return classes;
}

}  // namespace

ShellSet::ShellSet(const RenderScene& scene, std::uint64_t seed) : scene_(&scene), seed_(seed) {
  slot_of_medium_.assign(scene.media.size(), -1);
  keep_collisions_ = !scene.delta_lights.empty();  // (their light comes only by connections: shell_hops.h)
  for (std::size_t i = 0; i < scene.media.size(); ++i) {
    const ScatteringMedium* m = scattering(scene.media[i].medium);
    if (!m || !scene.media[i].enclosed || !shell_transport_applies(*m)) continue;
    const int classes = classes_that_fit(scene, static_cast<int>(i), *m);
    if (classes == 0) continue;
    const auto same = std::find_if(phases_.begin(), phases_.end(), [&](const PhaseFunction* p) { return same_phase(*p, m->phase); });
    const auto slot = static_cast<std::size_t>(same - phases_.begin());
    slot_of_medium_[i] = static_cast<int>(slot);
    if (same == phases_.end()) {
      phases_.push_back(&m->phase);
      classes_.push_back(classes);
    } else {
      classes_[slot] = std::max(classes_[slot], classes);
    }
  }
  slots_ = static_cast<int>(phases_.size());
}

void ShellSet::make(SampleRange range, int threads) {
  range_ = range;
  tables_.clear();
  const int samples = std::max(0, range.end - range.begin);
  if (slots_ == 0 || samples == 0) return;
  const std::size_t count = static_cast<std::size_t>(samples) * static_cast<std::size_t>(slots_);
  require_memory(count * (sizeof(ShellTable) + (sizeof(ShellExit) + (keep_collisions_ ? sizeof(ShellCollision) : 0)) *
                                                  kShellClasses * kShellEntries),
                 "shell transport's tables");
  tables_.resize(count);
  // Each table from its own stream (the sample index and the phase function's slot), so the
  // order they are made in changes nothing.
  tbb::task_arena arena(threads > 0 ? threads : tbb::this_task_arena::max_concurrency());
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tables_.size(), 1), [&](const tbb::blocked_range<std::size_t>& r) {
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const int s = range.begin + static_cast<int>(i / static_cast<std::size_t>(slots_));
        const auto slot = i % static_cast<std::size_t>(slots_);
        Rng stream = sample_rng(seed_, kShellPixelBase + slot, s, kShellSalt);
        tables_[i] = make_shell_table(*phases_[slot], stream.next_u32() | (std::uint64_t{stream.next_u32()} << 32),
                                      stream.next_u32(), classes_[slot], keep_collisions_);
      }
    });
  });
}

const ShellTable* ShellSet::table(int sample, int medium) const {
  if (medium < 0 || static_cast<std::size_t>(medium) >= slot_of_medium_.size()) return nullptr;
  const int slot = slot_of_medium_[static_cast<std::size_t>(medium)];
  if (slot < 0 || sample < range_.begin || sample >= range_.end) return nullptr;
  return &tables_[static_cast<std::size_t>(sample - range_.begin) * static_cast<std::size_t>(slots_) +
                  static_cast<std::size_t>(slot)];
}

}  // namespace bouguer
