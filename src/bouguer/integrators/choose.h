#pragma once
// --integrator auto (#37): which estimator renders this scene to a given noise soonest, found by
// rendering it. Which one wins depends on the scene (the path tracer beats bdpt and vcm on a glass
// ball under a small lamp; bdpt wins on the coloured-caustics showcase), so each candidate renders
// a short trial of the image, and the one whose error predicted for the same cost is lowest renders
// the rest, on from its trial's samples (the image is then bit for bit that estimator's own).
//
// Deterministic for a seed: the cost is the trial's ray count times the estimator's measured cost
// per ray relative to the path tracer's (cost_per_ray), not its seconds, which depend on the
// machine and its load; the seconds are reported beside it.
//
// The noise: a trial is two halves of k samples each (samples [0, k) and [k, 2k) of the render),
// the image after each read from the same film (the second half's is 2·M − A, splats included).
// A pixel's standard deviation per channel is the root mean square of the half gaps (M − A) over
// its block of 8 × 8 pixels: a pixel's own gap reads as converged where an estimator's light comes
// as rare large samples that neither half of a short trial has met there (vcm's merges in a thin
// liquid behind glass, where its trial's own gaps said ΔE00 3.9 and its 4-spp image was 10 from
// the truth). The score is the mean pixel ΔE00, on the display colour, between the mean and the
// mean moved one standard deviation up and down, the deviation scaled to what the cheapest
// candidate's render_spp samples cost spent on this one (vcm's at its merges' slower rate), read
// at the render's noise, since the distance is far from linear at a short trial's.
//
// Noise cannot tell an estimator that misses light: the path tracer leaves black the caustic a
// point lamp casts through a glass mesh, without noise. So where a delta lamp shines and a specular
// surface it cannot connect through is in the scene (path_misses_light), the path tracer is
// trialled with its light paths where they make that light (light_paths_complete), and is no
// candidate otherwise; and where a short trial has not yet found light that another unbiased
// estimator's has (darker_somewhere), it is left out too.
#include <cstdint>
#include <optional>
#include <vector>

#include "bouguer/render/render.h"

namespace bouguer {

struct DisplayDesc;

struct EstimatorTrial {
  IntegratorType type = IntegratorType::path;
  double error_de00 = 0.0;  // mean pixel error estimate of the trial's image (its 2k samples)
  std::uint64_t rays = 0;
  double cost = 0.0;     // rays × cost_per_ray
  // The samples that render_spp samples of the cheapest candidate that may be chosen cost buy this one.
  double samples_at_equal_cost = 0.0;
  double score = 0.0;    // the mean pixel error estimate at those samples, ΔE00 (lower is better)
  double seconds = 0.0;  // measured, reported; the choice does not read it
  bool complete = true;  // false: not chosen, for one of two reasons (below)
  // Why not complete: false, it misses light in this scene (path_misses_light: no trial); true,
  // its trial was darker than another unbiased candidate's in some block (darker_somewhere), which
  // a heavy-tailed estimator's short trial can also be.
  bool darker = false;
  bool light_paths = false;  // path: trialled with its light paths (the scene's, or auto's where they make what it misses)
};

struct EstimatorChoice {
  IntegratorType chosen = IntegratorType::path;
  int trial_spp = 0;  // samples per pixel each candidate rendered (2k); the chosen film has them
  int render_spp = 0;  // the errors compared at what this many samples of the cheapest candidate cost
  bool light_paths = false;  // the path tracer chosen, rendering with its light paths (render.light_paths)
  std::vector<EstimatorTrial> trials;
  std::optional<FilmBuffer> film;  // the chosen candidate's film after its trial
};

// The estimators auto chooses among for this scene: path, and bdpt and vcm where they can render
// it (no rough interface). Whitted (biased: no diffuse interreflection) and the light tracer (blind
// to what is seen through glass) are not candidates.
std::vector<IntegratorType> auto_candidates(const RenderScene& scene);

// The samples per pixel of a trial (2k) for a render of `spp`: a sixteenth to a thirty-second of
// them, 2 to 32, so that each candidate's trial costs at most an eighth of the render; 0 below 16
// spp (no trial: the path tracer renders, or bdpt where the path tracer misses light). A render
// bounded by seconds alone (`seconds_only`: its spp stands for "as many as fit") has trials as for
// 64 spp.
int auto_trial_spp(int spp, bool seconds_only = false);
// The samples per pixel at which the candidates' errors are compared: the render's, 64 for one
// bounded by seconds alone.
int auto_render_spp(int spp, bool seconds_only = false);

// Whether the path tracer misses light in this scene: a delta lamp (point, spot, distant) and a
// specular surface that next-event estimation cannot connect through (a smooth interface that is
// not a manifold caster, a smooth mirror, a thin dielectric sheet), so that the light it carries
// onto diffuse surfaces (caustics) is found by no direction the walk draws.
bool path_misses_light(const RenderScene& scene, const RenderSettings& settings);

// Whether the path tracer's light paths (render.light_paths) make the light path_misses_light
// says it misses: a pinhole camera and `manifold` on (their connections through glass need both), and no smooth
// metallic surface (a narrow lobe, not a delta: the light paths end there). What is then still
// missing, light reflected on both sides of a vertex, the trials' comparison (darker_somewhere) is
// there for. Where it holds, the path tracer is trialled, and chosen, with its light paths.
bool light_paths_complete(const RenderScene& scene, const RenderSettings& settings);

// Whether one trial's image is darker than another's in some block of 8 × 8 pixels, by more than
// five standard errors of the two (from each trial's halves) and by more than a fifth of the
// brighter: light the first trial's estimator has not found (a rare caustic path), which it would
// find only with far more samples than its measured noise suggests. Each trial is given as the
// image of its first half and of both halves. choose_estimator leaves out path or bdpt (the
// unbiased candidates) where one is darker than the other so; vcm's first iterations blur light
// by their radius, so it is neither judged nor a judge.
bool darker_somewhere(const Film& dark_first, const Film& dark_mean, const Film& bright_first, const Film& bright_mean);

// The estimators' cost per ray relative to the path tracer's (docs/performance.md, "Choosing the
// estimator": seconds per ray of path, bdpt and vcm on four showcase scenes, geometric means,
// the mean of two runs).
double cost_per_ray(IntegratorType type);

// Renders the candidates' trials of `trial_spp` samples (auto_trial_spp; a render with a budget of
// seconds and no number of samples: seconds_only) into films of the scene's size (with spectra if
// `keep_spectra`) and chooses, their errors compared at what `render_spp` samples of the cheapest
// cost (auto_render_spp); `display` (null: exposure 1, no white balance) sets the
// colour the error is measured on. The stats get the trials' rays and seconds. `denoised`: the
// trials' films are made for a render denoised later (make_film: their halves kept).
EstimatorChoice choose_estimator(const RenderScene& scene, const RenderSettings& settings, int trial_spp,
                                 int render_spp, bool keep_spectra, const DisplayDesc* display,
                                 const RenderControl& control, RenderStats& stats, bool denoised = false);

}  // namespace bouguer
