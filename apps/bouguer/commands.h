#pragma once
// Each subcommand registers its options on the CLI11 app and returns what to run once parsed.
#include <CLI/CLI.hpp>

#include <functional>
#include <string>

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

// "640x480" -> {640, 480}; anything else (missing x, trailing text, sizes outside 1..16384) is an
// Error naming --resolution.
struct Resolution {
  int width = 0, height = 0;
};
Resolution parse_resolution(const std::string& text);

}  // namespace bouguer::cli
