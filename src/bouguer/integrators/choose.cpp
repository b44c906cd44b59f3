#include "bouguer/integrators/choose.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "bouguer/core/error.h"
#include "bouguer/integrators/bidirectional.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/render/adaptive.h"
#include "bouguer/scene/display_white.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {
namespace {

Vec3 rgb_of(const Film& f, int x, int y) {
  const Vec3f v = f.rgb_at(x, y);
  return {v.x, v.y, v.z};
}

double luminance(const Vec3& c) { return rec709_luminance(c.x, c.y, c.z); }

// A trial's image by blocks of kBlockPx² pixels: each block's mean luminance and the variance of
// that mean, from the pixels' two halves (((Y_A − Y_B)/2)² estimates the variance of (A + B)/2),
// and per channel the mean over the block of the pixels' squared half gaps (what
// predicted_error_de00 reads, with the colours of the trial's mean image).
constexpr int kBlockPx = 8;
struct Blocks {
  int nx = 0, ny = 0, width = 0, height = 0;
  std::vector<double> mean, var;
  std::vector<Vec3> square;  // by block
  std::vector<Vec3> rgb;     // M by pixel, row-major

  std::size_t at(int x, int y) const {
    return static_cast<std::size_t>(y / kBlockPx) * static_cast<std::size_t>(nx) +
           static_cast<std::size_t>(x / kBlockPx);
  }
};

Blocks blocks_of(const Film& a, const Film& m) {
  Blocks b;
  b.nx = (m.width + kBlockPx - 1) / kBlockPx;
  b.ny = (m.height + kBlockPx - 1) / kBlockPx;
  b.width = m.width;
  b.height = m.height;
  const std::size_t n = static_cast<std::size_t>(b.nx) * static_cast<std::size_t>(b.ny);
  b.mean.assign(n, 0.0);
  b.var.assign(n, 0.0);
  b.square.assign(n, Vec3{});
  b.rgb.reserve(static_cast<std::size_t>(m.width) * static_cast<std::size_t>(m.height));
  std::vector<double> count(n, 0.0);
  for (int y = 0; y < m.height; ++y)
    for (int x = 0; x < m.width; ++x) {
      const std::size_t k = b.at(x, y);
      const Vec3 first = rgb_of(a, x, y), both = rgb_of(m, x, y);
      const Vec3 gap = both - first;  // ((2·M − A) − A)/2
      const double half_gap = luminance(gap);  // (luminance is linear)
      b.mean[k] += luminance(both);
      b.var[k] += half_gap * half_gap;
      b.square[k] += Vec3{gap.x * gap.x, gap.y * gap.y, gap.z * gap.z};
      b.rgb.push_back(both);
      count[k] += 1.0;
    }
  for (std::size_t k = 0; k < n; ++k) {
    b.mean[k] /= count[k];
    b.var[k] /= count[k] * count[k];
    b.square[k] = b.square[k] / count[k];
  }
  return b;
}

// Whether image `dark` is darker than image `bright` in some block beyond kMissedSigmas of their
// combined standard error and by more than kMissedFraction of `bright`'s mean there: light the
// estimator of `dark` has not found in its trial (a rare caustic path) and would find only with
// far more samples than its noise suggests.
constexpr double kMissedSigmas = 5.0;
constexpr double kMissedFraction = 0.2;
bool darker_blocks(const Blocks& dark, const Blocks& bright) {
  for (std::size_t k = 0; k < dark.mean.size(); ++k) {
    const double gap = bright.mean[k] - dark.mean[k];
    if (gap > kMissedSigmas * std::sqrt(dark.var[k] + bright.var[k]) && gap > kMissedFraction * bright.mean[k])
      return true;
  }
  return false;
}

// A trial's mean pixel error, ΔE00 on the display colour, predicted for a render whose mean has
// `scale` times the standard deviation of the trial's (√(2k / n) for n samples). Each pixel's
// standard deviation per channel is the root mean square of its block's half gaps (M − A: the
// mean's deviation, as |A − B|/2 estimates it), not its own gap: where an estimator's light comes
// as rare large samples (vcm's merges in a thin medium behind glass), most of a trial's pixels have
// none in either half, their halves agree, and a pixel's own gap reads them as converged; the
// block's mean square counts the rare samples at their weight. The error of a pixel is the mean of
// the colour distances from its mean to the mean moved one standard deviation up and down (down
// stops at black); it is read at the render's noise, not the trial's, since the distance is not
// linear in the deviation: far from linear at a trial's noise, so the trial's own ΔE00 scaled by
// √(2k / n) would misjudge the render's.
double predicted_error_de00(const Blocks& b, double scale, const DisplayTransform& shown) {
  double error = 0.0;
  for (int y = 0; y < b.height; ++y)
    for (int x = 0; x < b.width; ++x) {
      const Vec3& s = b.square[b.at(x, y)];
      const Vec3 sd = scale * Vec3{std::sqrt(s.x), std::sqrt(s.y), std::sqrt(s.z)};
      const Vec3& mean =
          b.rgb[static_cast<std::size_t>(y) * static_cast<std::size_t>(b.width) + static_cast<std::size_t>(x)];
      // (down stops at black, or at the mean where a channel is below black: out of gamut)
      const Vec3 low{std::min(mean.x, std::max(mean.x - sd.x, 0.0)), std::min(mean.y, std::max(mean.y - sd.y, 0.0)),
                     std::min(mean.z, std::max(mean.z - sd.z, 0.0))};
      // halves_error_de00 is half the distance between its two colours
      error += halves_error_de00(mean, mean + sd, shown) + halves_error_de00(mean, low, shown);
    }
  return error / (static_cast<double>(b.width) * b.height);
}

}  // namespace

namespace {

// A glTF metal of roughness 0 (untextured): its lobe is narrow, not a delta.
bool smooth_metal(const SurfaceMaterial& m) {
  const auto* r = std::get_if<MetallicRoughnessMaterial>(&m);
  return r && r->roughness == 0.0 && r->metalness > 0.0 && r->metallic_roughness_texture < 0;
}

}  // namespace

bool path_misses_light(const RenderScene& scene, const RenderSettings& settings) {
  if (scene.delta_lights.empty()) return false;
  for (std::size_t g = 0; g < scene.surfaces.size(); ++g) {
    const Surface& f = scene.surfaces[g];
    if (f.kind == SurfaceKind::interface && f.roughness == 0.0 && !f.index_matched &&
        !(settings.manifold && find_caster(scene, static_cast<std::uint32_t>(g))))
      return true;
    if (f.kind != SurfaceKind::opaque || f.material < 0) continue;
    const SurfaceMaterial& m = scene.materials[static_cast<std::size_t>(f.material)];
    if (const auto* c = std::get_if<ConductorMaterial>(&m); c && c->alpha == 0.0 && c->alpha_texture < 0) return true;
    if (smooth_metal(m)) return true;
    if (std::holds_alternative<ThinDielectricMaterial>(m)) return true;
  }
  return false;
}

bool light_paths_complete(const RenderScene& scene, const RenderSettings& settings) {
  if (!settings.manifold || scene.camera.type != CameraType::pinhole) return false;
  // (A smooth metallic surface's lobe is narrow, not a delta: a light path ends there as at any
  // surface, and the light it reflects on stays as rare to the path tracer as before.)
  return std::none_of(scene.materials.begin(), scene.materials.end(), smooth_metal);
}

bool darker_somewhere(const Film& dark_first, const Film& dark_mean, const Film& bright_first,
                      const Film& bright_mean) {
  return darker_blocks(blocks_of(dark_first, dark_mean), blocks_of(bright_first, bright_mean));
}

std::vector<IntegratorType> auto_candidates(const RenderScene& scene) {
  std::vector<IntegratorType> out;
  for (const IntegratorType type : {IntegratorType::path, IntegratorType::bdpt, IntegratorType::vcm}) {
    RenderSettings s;
    s.integrator = type;
    try {
      check_settings(scene, s, false);  // what each estimator can render: its one list
      out.push_back(type);
    } catch (const Error&) {
    }
  }
  return out;
}

int auto_render_spp(int spp, bool seconds_only) { return seconds_only ? 64 : spp; }

int auto_trial_spp(int spp, bool seconds_only) {
  spp = auto_render_spp(spp, seconds_only);
  return spp < 16 ? 0 : 2 * std::clamp(spp / 32, 1, 16);
}

double cost_per_ray(IntegratorType type) {
  switch (type) {
    case IntegratorType::bdpt:
      return 1.35;
    case IntegratorType::vcm:
      return 1.59;
    default:
      return 1.0;
  }
}

EstimatorChoice choose_estimator(const RenderScene& scene, const RenderSettings& settings, int trial_spp,
                                 int render_spp, bool keep_spectra, const DisplayDesc* display,
                                 const RenderControl& control, RenderStats& stats, bool denoised) {
  EstimatorChoice choice;
  choice.trial_spp = std::min(trial_spp - trial_spp % 2, settings.spp);
  const std::vector<IntegratorType> candidates = auto_candidates(scene);
  if (choice.trial_spp < 2 || candidates.size() < 2) {
    // Without trials: the path tracer, which renders every scene, with its light paths where it
    // misses light here that they make; otherwise there bdpt, where it can render the scene
    // (unbiased, as the path tracer; vcm's first iterations blur).
    choice.trial_spp = 0;
    if (path_misses_light(scene, settings)) {
      if (light_paths_complete(scene, settings))
        choice.light_paths = true;
      else if (candidates.size() > 1)
        choice.chosen = IntegratorType::bdpt;
    }
    choice.light_paths = choice.chosen == IntegratorType::path && (choice.light_paths || settings.light_paths);
    return choice;
  }
  const int k = choice.trial_spp / 2;
  choice.render_spp = std::max(render_spp, choice.trial_spp);
  // A trial is short (an eighth of the render at most): it is not cancelled, nor reported as
  // progress; a Ctrl-C takes effect in the render's first pass.
  RenderControl trial_control;
  trial_control.threads = control.threads;
  std::vector<std::optional<FilmBuffer>> films(candidates.size());  // by trial
  std::vector<std::optional<Blocks>> blocks(candidates.size());  // by trial, where it ran
  DisplayTransform shown;
  bool displayed = false;
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    const IntegratorType type = candidates[i];
    EstimatorTrial t;
    t.type = type;
    const bool misses = type == IntegratorType::path && path_misses_light(scene, settings);
    const bool completed = misses && light_paths_complete(scene, settings);
    t.complete = !misses || completed;
    t.light_paths = type == IntegratorType::path && (completed || settings.light_paths);
    if (!t.complete) {  // no trial: its noise would say nothing of the light it leaves out
      choice.trials.push_back(t);
      continue;
    }
    RenderSettings s = settings;
    s.integrator = type;
    s.light_paths = t.light_paths;
    FilmBuffer& film = films[i].emplace(make_film(scene, keep_spectra, denoised));
    RenderStats st;
    render_into(scene, s, film, PixelRegion::whole(scene.camera), {0, k}, trial_control, st);
    const Film a = film.resolve(1.0 / k);
    render_into(scene, s, film, PixelRegion::whole(scene.camera), {k, 2 * k}, trial_control, st);
    const Film m = film.resolve(1.0 / (2 * k));
    // The colour the error is read on: the display's, as the first trial's image sets it
    // (an automatic exposure is measured on it), the same for all.
    if (!displayed && display) shown = display_transform(scene, *display, m);
    displayed = true;
    t.error_de00 = predicted_error_de00(blocks[i].emplace(blocks_of(a, m)), 1.0, shown);
    t.rays = st.rays;
    t.cost = static_cast<double>(st.rays) * cost_per_ray(type);
    t.seconds = st.seconds;
    choice.trials.push_back(t);
    stats.rays += st.rays;
    stats.seconds += st.seconds;
  }
  // The two unbiased candidates, path and bdpt, each left out where it is darker than the other
  // somewhere (vcm's first iterations blur the light by their radius: no reference for this).
  for (std::size_t i = 0; i < choice.trials.size(); ++i)
    for (std::size_t j = 0; j < choice.trials.size(); ++j) {
      EstimatorTrial& t = choice.trials[i];
      const EstimatorTrial& u = choice.trials[j];
      if (i == j || t.type == IntegratorType::vcm || u.type == IntegratorType::vcm || !t.complete || !u.complete)
        continue;
      if (darker_blocks(*blocks[i], *blocks[j])) t.complete = false, t.darker = true;
    }
  // Each trialled candidate's error predicted for the same cost: what the cheapest of those that
  // may be chosen spends on the render's samples (`render_spp`) buys the others fewer samples. Its
  // mean's deviation falls as one over the square root of its samples (2k in the trial), vcm's
  // slower: its smaller radii make each iteration's merges noisier (bidirectional.h). Where a
  // medium scatters, vcm's whole variance is taken to fall at the rate of its merges in media,
  // the slower one.
  double cheapest = std::numeric_limits<double>::infinity();  // cost of a sample
  for (std::size_t i = 0; i < choice.trials.size(); ++i)
    if (blocks[i] && choice.trials[i].complete && choice.trials[i].cost > 0.0)
      cheapest = std::min(cheapest, choice.trials[i].cost / (2 * k));
  const bool media_merges = std::any_of(scene.media.begin(), scene.media.end(),
                                        [](const SceneMedium& m) { return scattering(m.medium) != nullptr; });
  std::size_t best = choice.trials.size();
  for (std::size_t i = 0; i < choice.trials.size(); ++i) {
    EstimatorTrial& t = choice.trials[i];
    if (!blocks[i] || t.cost <= 0.0 || !std::isfinite(cheapest)) continue;
    t.samples_at_equal_cost = choice.render_spp * cheapest / (t.cost / (2 * k));
    const double rate = t.type != IntegratorType::vcm ? 1.0 : media_merges ? bidir::kVcmMediumRate : bidir::kVcmAlpha;
    t.score = predicted_error_de00(*blocks[i], std::pow(2.0 * k / t.samples_at_equal_cost, 0.5 * rate), shown);
    if (t.complete && (best == choice.trials.size() || t.score < choice.trials[best].score)) best = i;
  }
  // (Every trialled candidate left out cannot happen: vcm is never judged, and the darkness test
  // leaves out at most one of path and bdpt. The first trialled one, should it.)
  for (std::size_t i = 0; best == choice.trials.size() && i < choice.trials.size(); ++i)
    if (blocks[i]) best = i;
  choice.chosen = choice.trials[best].type;
  choice.light_paths = choice.trials[best].light_paths;
  choice.film.emplace(std::move(*films[best]));
  return choice;
}

}  // namespace bouguer
