// bouguer render SCENE: load -> compile -> render -> write.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <mutex>
#include <nlohmann/json.hpp>

#include "bouguer/core/error.h"
#include "bouguer/io/atomic_file.h"
#include "bouguer/io/image_io.h"
#include "bouguer/io/output_set.h"
#include "bouguer/render/render.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "commands.h"

namespace bouguer::cli {
namespace {

struct RenderCli {
  std::vector<std::string> outputs = {"render.png"};
  std::string scene, spectral_exr, stats_json, integrator, spectral, resolution;
  int spp = 0, threads = 0, max_depth = 0;
  long long seed = -1;
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

const char* mode_name(SpectralMode m) {
  return m == SpectralMode::full ? "full" : m == SpectralMode::hero ? "hero" : "rgb3";
}

void apply_overrides(const RenderCli& o, SceneDesc& s) {
  if (!o.integrator.empty()) s.render.integrator = o.integrator == "path" ? IntegratorType::path : IntegratorType::whitted;
  if (!o.spectral.empty())
    s.render.spectral = o.spectral == "rgb3" ? SpectralMode::rgb3 : o.spectral == "hero" ? SpectralMode::hero : SpectralMode::full;
  if (o.spp > 0) s.render.spp = o.spp;
  if (o.max_depth > 0) s.render.max_depth = o.max_depth;
  if (o.seed >= 0) s.render.seed = static_cast<std::uint64_t>(o.seed);
  if (!o.resolution.empty()) {
    const Resolution r = parse_resolution(o.resolution);
    s.camera.width_px = r.width;
    s.camera.height_px = r.height;
  }
}

// Every file the command line asks for, checked before the scene is even read.
OutputSet checked_outputs(const RenderCli& o) {
  static constexpr std::string_view kExr[] = {".exr"};
  OutputSet outputs;
  for (const auto& output : o.outputs) outputs.add("-o", output, kImageExtensions);
  if (!o.spectral_exr.empty()) outputs.add("--spectral-exr", o.spectral_exr, kExr);
  if (!o.stats_json.empty()) outputs.add("--stats-json", o.stats_json);
  return outputs;
}

int run_render(const RenderCli& o) {
  const OutputSet outputs = checked_outputs(o);
  SceneDesc desc = load_scene(o.scene);
  apply_overrides(o, desc);
  const RenderScene scene = compile(desc);
  Progress progress(o.quiet);
  RenderOptions options;
  options.threads = o.threads;
  options.keep_spectra = !o.spectral_exr.empty();
  options.progress = [&progress](double f) { progress.update(f); };
  RenderStats stats;
  const Film film = render(scene, options, stats);
  const double rays_per_second = stats.seconds > 0 ? static_cast<double>(stats.rays) / stats.seconds : 0.0;
  std::string stats_text;
  if (!o.stats_json.empty()) {
    const nlohmann::json j = {{"seconds", stats.seconds},
                              {"rays", stats.rays},
                              {"rays_per_second", rays_per_second},
                              {"spp", scene.render.spp},
                              {"resolution", {film.width, film.height}},
                              {"spectral", mode_name(scene.render.spectral)},
                              {"threads", o.threads}};
    stats_text = j.dump(2) + "\n";
  }
  // All or nothing: no file is replaced unless every output was written.
  using Path = std::filesystem::path;
  outputs.write_all({{"-o", [&](const Path& p) { write_image(p, film); }},
                     {"--spectral-exr", [&](const Path& p) { write_spectral_exr(p, film); }},
                     {"--stats-json", [&](const Path& p) { write_bytes_atomically(p, stats_text); }}});
  if (!o.quiet)
    fmt::print("{}: {}x{}, {} spp, {}, {:.2f} s, {} rays, {:.3g} rays/s -> {}\n", o.scene, film.width, film.height,
               scene.render.spp, mode_name(scene.render.spectral), stats.seconds,
               stats.rays, rays_per_second, fmt::join(o.outputs, ", "));
  return 0;
}

}  // namespace

Resolution parse_resolution(const std::string& text) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || x != 'x' || w < 1 || h < 1 || w > 16384 ||
      h > 16384)
    fail("--resolution: expected WIDTHxHEIGHT such as 640x480, each 1 to 16384 (got '{}')", text);
  return {w, h};
}

Command add_render_command(CLI::App& parent) {
  auto o = std::make_shared<RenderCli>();
  CLI::App* app = parent.add_subcommand("render", "Render a scene file (JSON, see docs/scene-format.md).");
  app->add_option("SCENE", o->scene, "Scene file")->required();
  app->add_option("-o,--output", o->outputs,
                  "Image(s) to write: .png (sRGB 8-bit), .exr or .pfm (linear float); repeat for several")
      ->capture_default_str();
  app->add_option("--spectral-exr", o->spectral_exr, "Also write a spectral EXR (JCGT layout; --spectral full)");
  app->add_option("--spp", o->spp, "Samples per pixel (overrides the scene)")->check(CLI::Range(1, 1 << 20));
  app->add_option("--integrator", o->integrator, "whitted (the paper's ray tracer) or path (unbiased path tracing)")
      ->check(CLI::IsMember({"whitted", "path"}));
  app->add_option("--spectral", o->spectral,
                  "Wavelengths carried: full (96 bins), hero (4 sampled per path) or rgb3 (the paper's RGB)")
      ->check(CLI::IsMember({"full", "hero", "rgb3"}));
  app->add_option("--resolution", o->resolution, "Image size WIDTHxHEIGHT (overrides the scene)");
  app->add_option("--threads", o->threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 1024));
  app->add_option("--seed", o->seed, "Random seed (overrides the scene)")->check(CLI::Range(0LL, 2147483647LL));
  app->add_option("--max-depth", o->max_depth, "Maximum ray depth (overrides the scene)")->check(CLI::Range(1, 1000));
  app->add_option("--stats-json", o->stats_json, "Write seconds, rays, rays_per_second, spp, resolution as JSON");
  app->add_flag("--quiet", o->quiet, "No progress and no summary line");
  return {app, [o] { return run_render(*o); }};
}

}  // namespace bouguer::cli
