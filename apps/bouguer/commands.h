#pragma once
// Each subcommand registers its options on the CLI11 app and returns what to run once parsed.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "bouguer/scene/description.h"

namespace bouguer::cli {

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;  // returns the exit code; throws bouguer::Error for bad input
};

Command add_color_command(CLI::App& parent);
Command add_render_command(CLI::App& parent);
Command add_compare_command(CLI::App& parent);
Command add_material_command(CLI::App& parent);
Command add_report_command(CLI::App& parent);

// Validators shared by subcommands: a finite number from lo to hi (CLI::Range lets NaN through
// and prints its bounds with six decimals).
CLI::Validator finite_between(double lo, double hi);

// "640x480" -> {640, 480}; anything else (missing x, trailing text) is a UsageError naming
// --resolution. The sizes are checked by the SceneBuilder (load_scene_with).
struct Resolution {
  std::int64_t width = 0, height = 0;
};
Resolution parse_resolution(const std::string& text);

// The command line's overrides of a scene's settings. They are set on the SceneBuilder after the
// scene file, so each passes the one check the file's value passes, its message naming the option.
struct SceneOverrides {
  std::string integrator, spectral, resolution;
  std::string studio;  // --studio on|off: a glTF asset's default studio (docs/assets.md)
  std::string guiding;  // --guiding on|off: the path tracer's path guiding (integrators/guiding.h)
  std::optional<std::int64_t> spp, max_depth, seed;
  // The display (io/display.h): --exposure, --iso/--shutter/--f-number (all three), --auto-exposure
  // on|off, --white-balance, --display, --expose-float-outputs.
  std::optional<double> exposure_ev, iso, shutter_s, f_number;
  std::string auto_exposure, white_balance, display;
  bool expose_float_outputs = false;
};
// Registers the display options above on a subcommand (render, report).
void add_display_options(CLI::App& app, SceneOverrides& o, bool float_outputs);
bouguer::SceneDesc load_scene_with(const std::string& scene, const SceneOverrides& overrides);

}  // namespace bouguer::cli
