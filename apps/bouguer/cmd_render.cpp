// bouguer render SCENE: load -> compile -> render -> write.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <mutex>
#include <optional>
#include <vector>
#include <nlohmann/json.hpp>

#include "bouguer/core/error.h"
#include "bouguer/core/memory.h"
#include "bouguer/distributed/distributed.h"
#include "bouguer/io/atomic_file.h"
#include "bouguer/io/image_io.h"
#include "bouguer/io/output_set.h"
#include "bouguer/integrators/choose.h"
#include "bouguer/integrators/guiding.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/render/adaptive.h"
#include "bouguer/render/denoise.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/display_white.h"
#include "bouguer/scene/gltf.h"
#include "bouguer/scene/loader.h"
#include "commands.h"

namespace bouguer::cli {
namespace {

struct RenderCli {
  std::vector<std::string> outputs = {"render.png"};
  std::string scene, spectral_exr, stats_json, spp_map, noisy_output;
  SceneOverrides overrides;
  int threads = 0;
  double time_s = 0.0;  // --time: a budget of seconds (0: none)
  double noise = 0.0;   // --noise: adaptive sampling's target, ΔE00 (0: none)
  bool denoise = false;  // --denoise: the image filtered from its two half buffers (render/denoise.h)
  bool quiet = false;
};

// A bar on a terminal, a plain line every few seconds otherwise, nothing when quiet.
class Progress {
 public:
  explicit Progress(bool quiet) : quiet_(quiet), tty_(::isatty(STDERR_FILENO) != 0), start_(clock::now()) {}
  void update(double fraction) {
    if (quiet_) return;
    std::lock_guard lock(mutex_);
    const double elapsed = seconds_since(start_);
    const double interval = tty_ ? 0.1 : 5.0;
    if (fraction < 1.0 && elapsed - last_ < interval) return;
    last_ = elapsed;
    const double eta = fraction > 0.0 ? elapsed * (1.0 - fraction) / fraction : 0.0;
    if (tty_) {
      const int filled = static_cast<int>(fraction * 30);
      fmt::print(stderr, "\r[{}{}] {:3.0f}%  {:.1f} s  ETA {:.1f} s ", std::string(filled, '='),
                 std::string(30 - filled, ' '), fraction * 100, elapsed, eta);
      if (fraction >= 1.0) fmt::print(stderr, "\n");
    } else {
      fmt::print(stderr, "render: {:.0f}% ({:.1f} s, ETA {:.1f} s)\n", fraction * 100, elapsed, eta);
    }
  }

 private:
  using clock = std::chrono::steady_clock;
  static double seconds_since(clock::time_point t) { return std::chrono::duration<double>(clock::now() - t).count(); }
  bool quiet_, tty_;
  clock::time_point start_;
  double last_ = -1e9;
  std::mutex mutex_;
};

// Ctrl-C: the first stops the render after the tiles in flight (the image so far is written),
// the second exits at once.
std::atomic<bool> g_interrupted{false};

extern "C" void on_sigint(int) {
  if (g_interrupted.exchange(true)) std::_Exit(130);
}

struct InterruptGuard {
  struct sigaction previous {};
  InterruptGuard() {
    g_interrupted = false;
    struct sigaction action {};
    action.sa_handler = on_sigint;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous);
  }
  ~InterruptGuard() { sigaction(SIGINT, &previous, nullptr); }
};

// The render's passes (integrators/render_into.h: render_passes) with the progress line (by samples,
// or with a budget of seconds, by whichever ends the render first), and with a noise target
// (--noise: render/adaptive.h): after each pass the pixels whose error estimate is within it stop
// (their flags in `active` cleared), and the render ends when none is left; `complete` is then the
// samples of the pixels that took the most.
struct Adaptive {
  NoiseTarget target;
  const SceneDesc* desc = nullptr;  // its display block: the exposure the error is measured at
  std::vector<std::uint8_t> active;
  std::size_t left = 0;  // the pixels that had not reached the target
};

Passes render_in_passes(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, int threads,
                        Progress& progress, RenderStats& stats, double budget_s, Adaptive* adaptive, int first,
                        const PathGuide* guide) {
  const int spp = settings.spp;
  const auto start = std::chrono::steady_clock::now();
  RenderControl control;
  control.threads = threads;
  control.cancel = &g_interrupted;
  control.guide = guide;
  PassOptions options;
  options.first = first;
  options.budget_s = budget_s;
  options.progress = [&](int begin, int end, double f) {
    if (budget_s > 0.0)  // the budget ends the render first unless the samples do
      progress.update(std::min(1.0, std::max((begin + f * (end - begin)) / spp,
                                             std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() /
                                                 budget_s)));
    else
      progress.update((begin + f * (end - begin)) / spp);
  };
  if (adaptive) {
    control.active = &adaptive->active;
    adaptive->left = adaptive->active.size();
    options.after_pass = [&](int complete) {
      // The display as the film so far resolves it (an automatic exposure is measured on it).
      adaptive->target.display = display_transform(scene, adaptive->desc->display, film.resolve(0.0));
      adaptive->left = retire_converged(film, adaptive->target, complete, adaptive->active);
      return adaptive->left > 0;
    };
  }
  return render_passes(scene, settings, film, control, options, stats);
}

// Every file the command line asks for, checked before the scene is even read.
OutputSet checked_outputs(const RenderCli& o) {
  static constexpr std::string_view kExr[] = {".exr"};
  OutputSet outputs;
  for (const auto& output : o.outputs) outputs.add("-o", output, kImageExtensions);
  if (!o.spectral_exr.empty()) outputs.add("--spectral-exr", o.spectral_exr, kExr);
  if (!o.stats_json.empty()) outputs.add("--stats-json", o.stats_json);
  static constexpr std::string_view kFloatImages[] = {".exr", ".pfm"};
  if (!o.spp_map.empty()) {
    if (o.noise <= 0.0) fail_usage("--spp-map: only with --noise (adaptive sampling)");
    outputs.add("--spp-map", o.spp_map, kFloatImages);
  }
  if (!o.noisy_output.empty()) {
    if (!o.denoise) fail_usage("--noisy-output: only with --denoise (it is the image before denoising)");
    outputs.add("--noisy-output", o.noisy_output, kImageExtensions);
  }
  return outputs;
}

int run_render(const RenderCli& o) {
  const OutputSet outputs = checked_outputs(o);
  // A piece under mpirun is every sample of its pixels: a budget of seconds cannot end them together.
  if (o.time_s > 0.0 && distributed::launched_by_mpirun())
    fail_usage("--time: not under mpirun, whose pieces take every sample of their pixels; give --spp");
  const SceneDesc desc = load_scene_with(o.scene, o.overrides);
  RenderSettings settings = desc.render;
  if (o.noise > 0.0 && distributed::launched_by_mpirun())
    fail_usage("--noise: not under mpirun, whose pieces take every sample of their pixels");
  // The pieces' films are merged without their halves (render/film.h).
  if (o.denoise && distributed::launched_by_mpirun())
    fail_usage("--denoise: not under mpirun, whose merged film keeps no half buffers");
  // A budget of seconds without --spp: as many samples as the budget allows; a noise target without
  // --spp: at most kNoiseSpp (Cycles' default cap with adaptive sampling).
  constexpr int kTimedSpp = 1 << 20, kNoiseSpp = 4096;
  if (o.time_s > 0.0 && !o.overrides.spp) settings.spp = kTimedSpp;
  if (o.noise > 0.0 && !o.overrides.spp) settings.spp = o.time_s > 0.0 ? kTimedSpp : kNoiseSpp;
  // Adaptive sampling stops pixels, which only an estimator without splats allows: auto is the
  // path tracer there.
  if (o.noise > 0.0 && settings.integrator == IntegratorType::automatic) settings.integrator = IntegratorType::path;
  if (o.noise > 0.0 && integrator_info(settings.integrator).splats)
    fail_usage("--noise: adaptive sampling needs an estimator whose samples stay in their pixel (path or whitted); "
               "{} adds light paths' splats anywhere on the film",
               integrator_info(settings.integrator).name);
  if (o.noise > 0.0 && settings.integrator == IntegratorType::path && settings.light_paths)
    fail_usage("--noise: adaptive sampling needs an estimator whose samples stay in their pixel; the path tracer's "
               "light paths (render.light_paths) add splats anywhere on the film");
  if (o.denoise) check_denoisable(settings.integrator, "--denoise");
  if (settings.light_paths && settings.integrator != IntegratorType::path &&
      settings.integrator != IntegratorType::automatic)
    fmt::print(stderr, "bouguer: warning: light_paths: only the path tracer traces them; {} renders without\n",
               integrator_info(settings.integrator).name);
  const RenderScene scene = compile(desc);
  const bool keep_spectra = !o.spectral_exr.empty();
  check_settings(scene, settings, keep_spectra);
  Progress progress(o.quiet);
  RenderStats stats;
  // --integrator auto: the candidates' trials choose the estimator; its film, with the trial's
  // samples, goes on (integrators/choose.h). Deterministic, so every rank under mpirun makes the
  // same choice (each its own trial; the ranks then render their pixels from sample 0).
  std::optional<EstimatorChoice> choice;
  if (settings.integrator == IntegratorType::automatic) {
    if (!o.quiet) fmt::print(stderr, "auto: trials of the candidate estimators\n");
    RenderControl control;
    control.threads = o.threads;
    // A budget of seconds without --spp: trials as for 64 spp, not for the 2^20 that stand for "as
    // many as the budget allows".
    const bool seconds_only = o.time_s > 0.0 && !o.overrides.spp;
    choice.emplace(choose_estimator(scene, settings, auto_trial_spp(settings.spp, seconds_only),
                                    auto_render_spp(settings.spp, seconds_only), keep_spectra, &desc.display, control,
                                    stats, o.denoise));
    if (settings.light_paths && choice->chosen != IntegratorType::path)
      fmt::print(stderr, "bouguer: warning: light_paths: auto chose {}, which renders without them\n",
                 integrator_info(choice->chosen).name);
    settings.integrator = choice->chosen;
    settings.light_paths = settings.light_paths || choice->light_paths;
  }
  const bool mpi = distributed::launched_by_mpirun();
  FilmBuffer buffer =
      choice && choice->film && !mpi ? std::move(*choice->film) : make_film(scene, keep_spectra, o.denoise);
  if (choice) choice->film.reset();
  const int first = choice && !mpi ? choice->trial_spp : 0;
  // Path guiding (integrators/guiding.h): trained before the render, by every rank alike; with a
  // budget of seconds, in at most a quarter of what is left of it.
  GuideTraining training;
  std::unique_ptr<PathGuide> guide;
  if (settings.guiding && settings.integrator != IntegratorType::path)
    fmt::print(stderr, "bouguer: warning: guiding: only the path tracer is guided; {} renders unguided\n",
               integrator_info(settings.integrator).name);
  if (guiding_enabled(settings)) {
    if (!o.quiet) fmt::print(stderr, "guiding: training\n");
    RenderControl control;
    control.threads = o.threads;
    control.cancel = &g_interrupted;
    const double left_s = o.time_s > 0.0 ? std::max(o.time_s - stats.seconds, 1e-9) : 0.0;
    guide = prepare_guide(scene, settings, control, stats, training, left_s / 4.0);
    if (!o.quiet)
      fmt::print(stderr, "guiding: {} iteration{} ({} spp) in {:.2f} s, {} records, {} cells, {:.1f} MB\n",
                 training.iterations, training.iterations == 1 ? "" : "s", training.spp, training.seconds,
                 training.records, training.leaves, static_cast<double>(training.bytes) / 1e6);
  }
  Passes passes;
  std::optional<Adaptive> adaptive;
  if (mpi) {  // one rank of mpirun -np N: rank 0 writes (docs/distributed.md)
    if (!distributed::render_over_ranks(scene, settings, buffer, o.threads, o.quiet,
                                        [&](double f) { progress.update(f); }, stats, guide.get()))
      return 0;
    passes.complete = settings.spp;
  } else {
    const InterruptGuard guard;
    if (o.noise > 0.0) {
      buffer.keep_halves();
      adaptive.emplace();
      adaptive->target.delta_e00 = o.noise;
      adaptive->desc = &desc;
      adaptive->active.assign(static_cast<std::size_t>(buffer.width()) * static_cast<std::size_t>(buffer.height()), 1);
    }
    // A budget of seconds includes the trials.
    const double budget_s = o.time_s > 0.0 ? std::max(o.time_s - stats.seconds, 1e-9) : 0.0;
    passes = render_in_passes(scene, settings, buffer, o.threads, progress, stats, budget_s,
                              adaptive ? &*adaptive : nullptr, first, guide.get());
  }
  const bool interrupted = g_interrupted && passes.complete < settings.spp;
  // Light paths splat anywhere: their scale is the light paths traced per pixel.
  const double splat_spp = passes.complete + passes.partial * passes.partial_fraction;
  Film film = buffer.resolve(splat_spp > 0.0 ? 1.0 / splat_spp : 0.0);
  // Denoised from the half buffers (render/denoise.h); the spectra stay as rendered. The noisy
  // image's rgb is kept: --noisy-output writes it and the display is set on it, so that the noisy
  // output is the render without --denoise. Ctrl-C while denoising leaves the noisy image.
  std::optional<Film> noisy;
  std::optional<DenoiseStats> denoised;
  if (o.denoise) {
    noisy.emplace(film.width, film.height);
    noisy->rgb = film.rgb;
    DenoiseSettings ds;
    ds.threads = o.threads;
    const InterruptGuard guard;
    denoised = denoise(film, half_images(buffer, film), ds, &g_interrupted);
    if (denoised->cancelled)
      fmt::print(stderr, "bouguer: interrupted while denoising: the images are the noisy render's\n");
  }
  // Finite out: an image with NaN or infinite pixels replaces no earlier output.
  if (const NonFinitePixels bad = find_non_finite(film); bad.count > 0)
    fail("{}: {} of {} pixels came out not finite (the first at ({}, {})), so no output was written; likely cause: "
         "a value near the limits of floating point that the scene checks let through (an extreme size, scale or "
         "concentration); if the scene is ordinary, please report it",
         o.scene, bad.count, static_cast<std::size_t>(film.width) * static_cast<std::size_t>(film.height), bad.first_x,
         bad.first_y);
  if (buffer.saturated_splats() > 0)
    fmt::print(stderr, "bouguer: warning: {} light-path splats were not finite or beyond the film's range and were dropped\n",
               buffer.saturated_splats());
  // Exposure, white balance and the display curve, from the finished film (the film stays linear).
  const DisplayTransform display = display_transform(scene, desc.display, noisy ? *noisy : film);
  const double rays_per_second = stats.seconds > 0 ? static_cast<double>(stats.rays) / stats.seconds : 0.0;
  const std::string_view mode = spectral_mode_name(settings.spectral);
  std::string stats_text;
  if (!o.stats_json.empty()) {
    const nlohmann::json j = {{"seconds", stats.seconds},
                              {"rays", stats.rays},
                              {"rays_per_second", rays_per_second},
                              {"spp", passes.complete},
                              {"resolution", {film.width, film.height}},
                              {"spectral", mode},
                              {"integrator", integrator_info(settings.integrator).name},
                              {"threads", o.threads},
                              {"exposure_scale", display.scale}};
    nlohmann::json jv = j;
    if (settings.integrator == IntegratorType::path) jv["path_light_paths"] = settings.light_paths;
    if (denoised)
      jv["denoise"] = {{"seconds", denoised->seconds},
                       {"pixels_left_as_rendered", denoised->pixels_left},
                       {"interrupted", denoised->cancelled}};
    if (o.noise > 0.0) {
      double samples = 0.0;
      for (int y = 0; y < buffer.height(); ++y)
        for (int x = 0; x < buffer.width(); ++x) samples += buffer.weight_at(x, y);
      jv["adaptive"] = {{"noise_delta_e00", o.noise},
                        {"mean_spp", samples / (static_cast<double>(buffer.width()) * buffer.height())},
                        {"pixels_above_target", adaptive->left}};
    }
    if (choice) {
      nlohmann::json trials = nlohmann::json::array();
      for (const EstimatorTrial& t : choice->trials)
        trials.push_back({{"integrator", integrator_info(t.type).name},
                          {"error_delta_e00", t.error_de00},
                          {"rays", t.rays},
                          {"cost", t.cost},
                          {"samples_at_equal_cost", t.samples_at_equal_cost},
                          {"score", t.score},
                          {"seconds", t.seconds},
                          {"complete", t.complete},
                          {"darker", t.darker},
                          {"light_paths", t.light_paths}});
      jv["auto"] = {{"chosen", integrator_info(choice->chosen).name},
                    {"light_paths", choice->light_paths},
                    {"trial_spp", choice->trial_spp},
                    {"render_spp", choice->render_spp},
                    {"trials", trials}};
    }
    if (guide)
      jv["guiding"] = {{"iterations", training.iterations}, {"spp", training.spp}, {"seconds", training.seconds},
                       {"records", training.records}, {"cells", training.leaves}, {"bytes", training.bytes}};
    if (stats.iterations > 0)
      jv["vcm"] = {{"iterations", stats.iterations}, {"light_paths", stats.light_paths}, {"photons", stats.photons},
                   {"merges", stats.merges}, {"last_radius_m", stats.radius_m},
                   {"light_subpath_bytes", stats.light_subpath_bytes}};
    stats_text = jv.dump(2) + "\n";
  }
  // All or nothing: no file is replaced unless every output was written.
  using Path = std::filesystem::path;
  outputs.write_all({{"-o", [&](const Path& p) { write_image(p, film, display); }},
                     {"--spectral-exr",
                      [&](const Path& p) {
                        if (display.leaves_floats()) write_spectral_exr(p, film);  // no copy of the spectra
                        else write_spectral_exr(p, exposed(film, display));
                      }},
                     {"--stats-json", [&](const Path& p) { write_bytes_atomically(p, stats_text); }},
                     {"--spp-map", [&](const Path& p) { write_image(p, samples_map(buffer), DisplayTransform{}); }},
                     {"--noisy-output", [&](const Path& p) { write_image(p, *noisy, display); }}});
  if (interrupted) {
    fmt::print(stderr, "bouguer: interrupted: wrote the image after {} of {} samples per pixel{} -> {}\n",
               passes.complete, settings.spp,
               passes.partial > 0 ? fmt::format(" ({} more in the pixels the last pass reached)", passes.partial) : "",
               fmt::join(o.outputs, ", "));
    return 130;
  }
  if (!o.quiet) {
    fmt::print("{}: {}x{}, {} spp, {}, {}, {:.2f} s, {} rays, {:.3g} rays/s -> {}\n", o.scene, film.width, film.height,
               passes.complete, integrator_info(settings.integrator).name, mode, stats.seconds, stats.rays,
               rays_per_second, fmt::join(o.outputs, ", "));
    if (choice) {
      const char* with = choice->light_paths ? " with its light paths" : "";
      if (choice->trials.empty())
        fmt::print("  auto: {}{}, without trials ({} spp; trials need 16)\n", integrator_info(choice->chosen).name,
                   with, settings.spp);
      else {
        std::string rows;
        for (const EstimatorTrial& t : choice->trials) {
          rows += fmt::format("{}{}{}", rows.empty() ? "" : "; ", integrator_info(t.type).name,
                              t.light_paths ? " with light paths" : "");
          if (t.rays == 0) {  // not trialled
            rows += " (misses light here: not chosen)";
            continue;
          }
          rows += fmt::format(" ΔE00 {:.3g}, cost {:.3g}, ΔE00 {:.3g} at {:.3g} spp{}", t.error_de00, t.cost, t.score,
                              t.samples_at_equal_cost,
                              t.darker ? " (darker than another in some block of its trial: not chosen)" : "");
        }
        fmt::print("  auto: {}{} (trials of {} spp, errors compared at the cost of {} spp of the cheapest: {})\n",
                   integrator_info(choice->chosen).name, with, choice->trial_spp, choice->render_spp, rows);
      }
    }
    if (stats.iterations > 0)
      fmt::print("  {} iterations: {} light paths ({} kept at most), {} photons, {} merges, radius {:.3g} mm at the last\n",
                 stats.iterations, stats.light_paths, format_bytes(stats.light_subpath_bytes), stats.photons,
                 stats.merges, stats.radius_m * 1e3);
  }
  return 0;
}

}  // namespace

Resolution parse_resolution(const std::string& text) {
  long long w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%lld%c%lld%c", &w, &x, &h, &extra) != 3 || x != 'x')
    fail_usage("--resolution: expected WIDTHxHEIGHT such as 640x480 (got '{}')", text);
  return {w, h};
}

namespace {
void set_display_overrides(SceneBuilder& b, const SceneOverrides& o) {
  if (o.exposure_ev) b.exposure_ev(*o.exposure_ev, Source::option("--exposure"));
  if (o.iso || o.shutter_s || o.f_number) {
    if (!o.iso || !o.shutter_s || !o.f_number) fail_usage("--iso, --shutter and --f-number: give all three or none");
    b.camera_exposure({*o.iso, *o.shutter_s, *o.f_number}, Source::option("--iso/--shutter/--f-number"));
  }
  if (o.auto_exposure == "on") b.auto_exposure(true);
  else if (o.auto_exposure == "off") b.auto_exposure(false);
  else if (!o.auto_exposure.empty()) fail_usage("--auto-exposure: expected on or off (got '{}')", o.auto_exposure);
  if (!o.white_balance.empty()) b.white_balance(o.white_balance, Source::option("--white-balance"));
  if (!o.display.empty()) b.display_curve(o.display, Source::option("--display"));
  if (o.expose_float_outputs) b.expose_float_outputs(true);
}
}  // namespace

SceneDesc load_scene_with(const std::string& scene, const SceneOverrides& o) {
  SceneBuilder b(scene);
  if (!o.studio.empty() && !is_gltf_file(scene))
    fail_usage("--studio: only for a glTF asset rendered as it is (a scene file gives its own 'background')");
  if (!o.studio.empty()) load_gltf_scene(scene, b, o.studio == "on");
  else load_scene(scene, b);
  if (!o.integrator.empty()) b.integrator(o.integrator, Source::option("--integrator"));
  if (!o.spectral.empty()) b.spectral_mode(o.spectral, Source::option("--spectral"));
  if (o.spp) b.spp(*o.spp, Source::option("--spp"));
  if (o.max_depth) b.max_depth(*o.max_depth, Source::option("--max-depth"));
  if (o.seed) b.seed(*o.seed, Source::option("--seed"));
  if (!o.guiding.empty()) b.guiding(o.guiding == "on");
  if (!o.resolution.empty()) {
    const Resolution r = parse_resolution(o.resolution);
    b.resolution(r.width, r.height, Source::option("--resolution"));
  }
  set_display_overrides(b, o);
  SceneDesc desc = std::move(b).build();
  for (const std::string& w : desc.warnings) fmt::print(stderr, "bouguer: warning: {}\n", w);
  return desc;
}

void add_display_options(CLI::App& app, SceneOverrides& o, bool float_outputs) {
  app.add_option("--exposure", o.exposure_ev,
                 "Exposure compensation in EV, -32 to 32: +1 doubles the linear values shown (overrides the scene)");
  app.add_option("--iso", o.iso,
                 "Camera exposure: ISO speed S (with --shutter and --f-number; turns --auto-exposure off)");
  app.add_option("--shutter", o.shutter_s, "Camera exposure: shutter time t in seconds");
  app.add_option("--f-number", o.f_number,
                 "Camera exposure: f-number N; luminance L is shown as L/(1.2*2^EV100), "
                 "EV100 = log2(N^2/t) - log2(S/100)");
  app.add_option("--auto-exposure", o.auto_exposure,
                 "on|off: expose the finished film so that the 97th percentile of its lit pixels' largest channel "
                 "shows at 0.8 (default: on for glTF assets, off for JSON scenes)");
  app.add_option("--white-balance", o.white_balance,
                 "Adapt this white to the display's D65 (Bradford): an illuminant (D65, D50, A, E, F2, F7, F11, "
                 "blackbody:<kelvin>), brightest_emitter or none");
  app.add_option("--display", o.display,
                 "Display curve of PNG images: clip (default) or filmic (a shoulder that keeps hue)");
  if (float_outputs)
    app.add_flag("--expose-float-outputs", o.expose_float_outputs,
                 "Apply the exposure and white balance to EXR, PFM and the spectral EXR too "
                 "(otherwise linear and unscaled)");
}

Command add_render_command(CLI::App& parent) {
  auto o = std::make_shared<RenderCli>();
  CLI::App* app = parent.add_subcommand("render", "Render a scene file (JSON, see docs/scene-format.md).");
  app->add_option("SCENE", o->scene, "Scene file")->required();
  app->add_option("-o,--output", o->outputs,
                  "Image(s) to write: .png (sRGB 8-bit), .exr or .pfm (linear float); repeat for several")
      ->capture_default_str();
  app->add_option("--spectral-exr", o->spectral_exr, "Also write a spectral EXR (JCGT layout; --spectral full)");
  SceneOverrides& over = o->overrides;
  app->add_option("--spp", over.spp, "Samples per pixel, 1 to 1048576 (overrides the scene)");
  std::string integrator_help = "Estimator (overrides the scene):", mode_help = "Wavelengths carried (overrides the scene):";
  for (const IntegratorInfo& i : integrator_table()) {
    integrator_help += fmt::format(" {} ({});", i.name, i.summary);
  }
  for (const SpectralModeInfo& m : spectral_mode_table()) {
    mode_help += fmt::format(" {} ({});", m.name, m.summary);
  }
  app->add_option("--integrator", over.integrator, integrator_help);
  app->add_option("--spectral", over.spectral, mode_help);
  app->add_option("--resolution", over.resolution, "Image size WIDTHxHEIGHT, each 1 to 16384 (overrides the scene)");
  app->add_option("--threads", o->threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 1024));
  app->add_option("--seed", over.seed, "Random seed, 0 to 2147483647 (overrides the scene)");
  app->add_option("--max-depth", over.max_depth, "Maximum ray depth, 1 to 1000 (overrides the scene)");
  app->add_option("--studio", over.studio,
                  "A glTF asset's default studio, a uniform white background: on or off (default: on where the "
                  "asset has neither lights nor emitting materials)")
      ->check(CLI::IsMember({"on", "off"}));
  app->add_option("--guiding", over.guiding,
                  "The path tracer's path guiding at diffuse surfaces, trained before the render: on or off "
                  "(overrides the scene; default off)")
      ->check(CLI::IsMember({"on", "off"}));
  app->add_option("--time", o->time_s,
                  "Render whole passes for at most SECONDS, then write the image (with --spp: whichever ends first; "
                  "the image then depends on the machine)")
      ->check(CLI::PositiveNumber);
  app->add_option("--noise", o->noise,
                  "Adaptive sampling: a pixel stops once its error estimate (from two half buffers) is at most this "
                  "CIEDE2000 on the display colour; --spp (default 4096 with --noise) and --time cap it (path, whitted)")
      ->check(CLI::PositiveNumber);
  app->add_option("--spp-map", o->spp_map, "With --noise: write the samples each pixel took (.exr or .pfm)");
  app->add_flag("--denoise", o->denoise,
                "Filter the image from its two half buffers (non-local means, each half weighted by the other): "
                "smooth noise goes, edges and converged regions stay; biased, deterministic; -o images only, not "
                "--spectral-exr");
  app->add_option("--noisy-output", o->noisy_output, "With --denoise: also write the image before denoising");
  app->add_option("--stats-json", o->stats_json, "Write seconds, rays, rays_per_second, spp, resolution as JSON");
  add_display_options(*app, over, true);
  app->add_flag("--quiet", o->quiet, "No progress and no summary line");
  return {app, [o] { return run_render(*o); }};
}

}  // namespace bouguer::cli
