// bouguer compare A B: CIEDE2000 between two renders, per pixel.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "bouguer/core/error.h"
#include "bouguer/io/image_io.h"
#include "bouguer/render/compare.h"
#include "commands.h"

namespace bouguer::cli {
namespace {

struct CompareCli {
  std::string a, b, heatmap, montage;
  double heatmap_max = 10.0;
  bool json = false;
};

int run_compare(const CompareCli& o) {
  const Film a = read_image(o.a), b = read_image(o.b);
  ImageDifference d;
  try {
    d = compare_images(a, b);
  } catch (const Error& e) {
    fail("{} and {}: {}", o.a, o.b, e.what());
  }
  if (!o.heatmap.empty() || !o.montage.empty()) {
    const Film heat = delta_e_heatmap(d, o.heatmap_max);
    if (!o.heatmap.empty()) write_png(o.heatmap, heat);
    if (!o.montage.empty()) write_png(o.montage, side_by_side({&a, &b, &heat}, 8));
  }
  if (o.json) {
    const nlohmann::json j = {{"mean", d.mean},
                              {"median", d.median},
                              {"p95", d.p95},
                              {"max", d.max},
                              {"rmse", d.rmse},
                              {"mean_lightness", d.mean_lightness},
                              {"mean_colour", d.mean_colour},
                              {"pixels", d.delta_e.size()}};
    fmt::print("{}\n", j.dump());
  } else {
    fmt::print("CIEDE2000 over {} pixels: mean {:.3f}  median {:.3f}  p95 {:.3f}  max {:.3f}  (RMSE linear RGB {:.4g})\n",
               d.delta_e.size(), d.mean, d.median, d.p95, d.max, d.rmse);
    // (no "mean " on this line: bench scripts read the first line's with sed)
    fmt::print("  its average from lightness alone {:.3f}, from colour alone {:.3f}\n", d.mean_lightness,
               d.mean_colour);
  }
  return 0;
}

}  // namespace

Command add_compare_command(CLI::App& parent) {
  auto o = std::make_shared<CompareCli>();
  CLI::App* app = parent.add_subcommand("compare", "CIEDE2000 colour difference between two renders (EXR or PFM).");
  app->add_option("A", o->a, "First image (.exr or .pfm, linear Rec.709)")->required();
  app->add_option("B", o->b, "Second image, same size")->required();
  app->add_option("--heatmap", o->heatmap, "Write a PNG of the per-pixel difference");
  app->add_option("--montage", o->montage, "Write a PNG of A, B and the heat map side by side");
  app->add_option("--heatmap-max", o->heatmap_max, "ΔE00 shown at the top of the heat-map scale")
      ->check(finite_between(1e-6, 1e6))
      ->capture_default_str();
  app->add_flag("--json", o->json,
                "Print one JSON object: mean, median, p95, max, rmse, mean_lightness, mean_colour, pixels");
  return {app, [o] { return run_compare(*o); }};
}

}  // namespace bouguer::cli
