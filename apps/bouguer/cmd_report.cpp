// bouguer report: one self-contained HTML page (every image inlined as a data: URI, so it opens
// offline without a server) with the paper's scenes rendered in full spectrum and in the paper's
// RGB approach side by side, their ΔE00 heat maps and numbers, the absorption and transmittance
// plots of the materials in them, and the render settings and times.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <filesystem>

#include "bouguer/analysis/slab_colour.h"
#include "bouguer/core/error.h"
#include "bouguer/core/strings.h"
#include "bouguer/io/atomic_file.h"
#include "bouguer/io/image_io.h"
#include "bouguer/io/output_set.h"
#include "bouguer/plot/material_plot.h"
#include "bouguer/render/compare.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/display_white.h"
#include "bouguer/scene/loader.h"
#include "bouguer/spectra/cie.h"
#include "commands.h"

namespace bouguer::cli {
namespace {
namespace fs = std::filesystem;

struct ReportOptions {
  std::string out = "out/report";
  std::string scenes = "scenes/paper";
  SceneOverrides overrides;  // resolution and spp
  int threads = 0;
  bool quiet = false;
};

std::string html_escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string img(const std::string& mime, const std::string& bytes, const std::string& alt, const std::string& cls = "") {
  return fmt::format(R"(<img class="{}" alt="{}" src="data:{};base64,{}">)", cls, html_escape(alt), mime,
                     base64_encode(bytes));
}

constexpr const char* kStyle = R"(
body { font-family: "DejaVu Sans", sans-serif; margin: 2em auto; max-width: 1280px; color: #222; }
h1 { margin-bottom: 0.2em; } h2 { border-bottom: 1px solid #ccc; padding-bottom: 0.2em; margin-top: 2em; }
.row { display: flex; gap: 12px; align-items: flex-start; flex-wrap: wrap; }
figure { margin: 0; } figcaption { font-size: 0.85em; color: #555; text-align: center; }
img.render { width: 300px; image-rendering: auto; border: 1px solid #ddd; }
img.plot { width: 100%; max-width: 1200px; border: 1px solid #ddd; }
table { border-collapse: collapse; font-size: 0.9em; margin: 0.8em 0; }
td, th { border: 1px solid #ccc; padding: 3px 8px; text-align: right; } th { background: #f3f3f3; }
td:first-child, th:first-child { text-align: left; }
.note { color: #555; font-size: 0.9em; }
)";

// Marks the page after load: every image decoded, or the names of those that failed (the test
// suite's browser check reads this attribute).
constexpr const char* kCheckScript = R"(
window.addEventListener('load', function () {
  var bad = [];
  for (var i = 0; i < document.images.length; ++i) {
    var im = document.images[i];
    if (!im.complete || im.naturalWidth === 0) bad.push(im.alt);
  }
  document.body.setAttribute('data-images', bad.length ? 'failed: ' + bad.join(', ')
                                                        : 'ok: ' + document.images.length);
});
)";

int run_report(const ReportOptions& o) {
  std::vector<fs::path> scenes;
  std::error_code ec;
  if (!fs::is_directory(o.scenes, ec)) fail("--scenes: '{}' is not a folder", o.scenes);
  for (const auto& e : fs::directory_iterator(o.scenes))
    if (e.path().extension() == ".json") scenes.push_back(e.path());
  std::sort(scenes.begin(), scenes.end());
  if (scenes.empty()) fail("--scenes: no .json scene files in '{}'", o.scenes);
  fs::create_directories(o.out, ec);
  if (ec) fail_usage("--out {}: cannot create the folder: {}", o.out, ec.message());
  const fs::path index = fs::path(o.out) / "index.html";
  OutputSet output;  // checked before the first render
  output.add("--out", index);

  std::string body, summary;
  summary += "<table><tr><th>scene</th><th>resolution</th><th>spp</th><th>integrator</th><th>full s</th>"
             "<th>rgb3 s</th><th>mean ΔE00</th><th>median</th><th>p95</th><th>max</th></tr>\n";
  std::string materials;
  std::vector<std::string> plotted;
  const auto start = std::chrono::steady_clock::now();
  for (const fs::path& file : scenes) {
    const SceneDesc desc = load_scene_with(file.string(), o.overrides);
    const std::string name = file.stem().string();
    if (!o.quiet) fmt::print(stderr, "report: {} ({}x{}, {} spp)\n", name, desc.camera.width_px, desc.camera.height_px,
                             desc.render.spp);
    RenderControl control;
    control.threads = o.threads;
    Film films[2];
    RenderStats stats[2];
    // One compiled scene (geometry, environment) serves both modes; only the settings differ.
    const RenderScene scene = compile(desc);
    const SpectralMode modes[2] = {SpectralMode::full, SpectralMode::rgb3};
    for (int m = 0; m < 2; ++m) {
      RenderSettings settings = desc.render;
      settings.spectral = modes[m];
      films[m] = render(scene, settings, control, stats[m]);
    }
    // One exposure for both (measured on the full-spectrum film), so that they are shown alike.
    const DisplayTransform display = display_transform(scene, desc.display, films[0]);
    const ImageDifference d = compare_images(films[0], films[1]);
    const Film heat = delta_e_heatmap(d, 10.0);
    const std::string integrator(integrator_info(desc.render.integrator).name);
    summary += fmt::format(
        "<tr><td><a href=\"#{0}\">{0}</a></td><td>{1}×{2}</td><td>{3}</td><td>{4}</td><td>{5:.2f}</td><td>{6:.2f}</td>"
        "<td>{7:.2f}</td><td>{8:.2f}</td><td>{9:.2f}</td><td>{10:.1f}</td></tr>\n",
        name, desc.camera.width_px, desc.camera.height_px, desc.render.spp, integrator, stats[0].seconds,
        stats[1].seconds, d.mean, d.median, d.p95, d.max);
    body += fmt::format("<h2 id=\"{0}\">{0}</h2>\n<p class=\"note\">{1}: {2}×{3}, {4} spp, {5} integrator, seed {6}. "
                        "Full spectrum {7:.2f} s, rgb3 {8:.2f} s. ΔE00 full vs rgb3: mean {9:.2f}, median {10:.2f}, "
                        "p95 {11:.2f}, max {12:.1f}.</p>\n<div class=\"row\">",
                        name, html_escape(file.string()), desc.camera.width_px, desc.camera.height_px,
                        desc.render.spp, integrator, desc.render.seed, stats[0].seconds, stats[1].seconds, d.mean,
                        d.median, d.p95, d.max);
    body += fmt::format("<figure>{}<figcaption>full spectrum (96 bins)</figcaption></figure>",
                        img("image/png", encode_png(displayed(films[0], display)), name + " full", "render"));
    body += fmt::format("<figure>{}<figcaption>rgb3: 700.0, 546.1, 435.8 nm (the paper's RGB)</figcaption></figure>",
                        img("image/png", encode_png(displayed(films[1], display)), name + " rgb3", "render"));
    body += fmt::format("<figure>{}<figcaption>ΔE00, 0 (black) to 10 (white)</figcaption></figure></div>\n",
                        img("image/png", encode_png(heat), name + " heat map", "render"));
    // The absorbing media of the scene: their spectra and transmittance by thickness.
    for (const auto& [medium_name, medium] : desc.media) {
      if (!medium.absorbing) continue;
      if (std::find(plotted.begin(), plotted.end(), medium_name) != plotted.end()) continue;
      plotted.push_back(medium_name);
      const double n = ior_at(medium.ior, kReferenceWavelengthNm);
      const std::vector<double> thick = default_thickness_series(medium.sigma_a_per_m);
      MaterialPlot plot;
      plot.name = medium_name;
      plot.sigma_a_per_m = medium.sigma_a_per_m;
      plot.analysis = analyse_thicknesses(medium.sigma_a_per_m, n, thick, named_illuminant("D65"), thick[3]);
      materials += fmt::format("<h3>{}</h3>\n<p class=\"note\">first seen in {}</p>\n{}\n", html_escape(medium_name),
                               name, img("image/svg+xml", render_material_plot(plot, "svg"), medium_name + " plot", "plot"));
    }
  }
  summary += "</table>\n";
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string page = fmt::format(
      R"(<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>Bouguer: the paper, rendered</title>
<style>{}</style><script>{}</script></head>
<body>
<h1>The paper, rendered by Bouguer</h1>
<p>Sun, Fracchia and Drew trace rays through coloured glass and wine with a full spectrum, and show that an RGB
tracer sampling the absorptivity at 700.0, 546.1 and 435.8 nm gets the colours wrong, because transmittance
10<sup>−a(λ)·l</sup> depends on the path length. Each scene below is rendered twice with the same paths:
in full spectrum and in the paper's RGB approach, with the CIEDE2000 difference between them.</p>
<p class="note">Scenes from <code>{}</code>; {} scenes, {:.1f} s in all. Colours: linear Rec.709 shown as sRGB;
emitters normalised to luminance, see docs/colour.md.</p>
{}
{}
<h2>The materials in these scenes</h2>
<p class="note">Each plot: the absorption coefficient with its unit, internal transmittance for seven
thicknesses, the colour of a slab of each thickness in air against D65 (spectral, the paper's rgb3, and an RGB
renderer fitted at the middle thickness), and how far the RGB answers drift (ΔE00).</p>
{}
</body></html>
)",
      kStyle, kCheckScript, html_escape(o.scenes), scenes.size(), total, summary, body, materials);
  output.write_all({{"--out", [&page](const fs::path& p) { write_bytes_atomically(p, page); }}});
  if (!o.quiet) fmt::print(stderr, "report: wrote {} ({:.1f} s)\n", index.string(), total);
  return 0;
}

}  // namespace

Command add_report_command(CLI::App& parent) {
  auto o = std::make_shared<ReportOptions>();
  CLI::App* app = parent.add_subcommand(
      "report", "Render the paper's scenes in full spectrum and RGB and write one self-contained HTML page.");
  app->add_option("--out", o->out, "folder for index.html")->capture_default_str();
  app->add_option("--scenes", o->scenes, "folder of scene files")->capture_default_str();
  app->add_option("--resolution", o->overrides.resolution, "WxH instead of each scene's own");
  app->add_option("--spp", o->overrides.spp, "samples per pixel instead of each scene's own");
  app->add_option("--threads", o->threads, "worker threads (0: all cores)")->check(CLI::Range(0, 1024));
  add_display_options(*app, o->overrides, false);
  app->add_flag("--quiet", o->quiet, "no progress lines");
  return {app, [o] { return run_report(*o); }};
}

}  // namespace bouguer::cli
