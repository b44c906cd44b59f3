// bouguer color SPECTRUM: the colour of a named illuminant or a CSV spectrum.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "bouguer/core/error.h"
#include "bouguer/spectra/spectrum_csv.h"
#include "bouguer/core/limits.h"
#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"
#include "commands.h"

namespace bouguer::cli {

CLI::Validator finite_between(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& value) -> std::string {
      double v = 0.0;
      try {
        std::size_t used = 0;
        v = std::stod(value, &used);
        if (used != value.size()) return "'" + value + "' is not a number";
      } catch (const std::exception&) {
        return "'" + value + "' is not a number";
      }
      if (!(std::isfinite(v) && v >= lo && v <= hi))
        return fmt::format("must be a finite number from {:g} to {:g}, got {}", lo, hi, value);
      return {};
    },
    fmt::format("NUMBER in [{:g}, {:g}]", lo, hi));
}

namespace {

struct ColorOptions {
  std::string spectrum;
  std::string observer = "1931";
  double scale = 1.0;
  bool normalise = false;
  bool json = false;
};

// A named illuminant is normalised to luminance Y = scale; a CSV spectrum is taken in its own
// units and multiplied by scale (or normalised to Y = scale with --normalise).
Spectrum resolve_spectrum(const ColorOptions& o) {
  if (const auto spd = named_illuminant_spd(o.spectrum)) return normalised_to_luminance(*spd, o.scale);
  std::error_code ec;
  if (!std::filesystem::exists(o.spectrum, ec))
    fail("'{}' is neither a named illuminant (D65, D50, A, E, F2, F7, F11, blackbody:<kelvin>) nor a file",
         o.spectrum);
  const Spectrum s = load_spectrum_csv(o.spectrum);
  return o.normalise ? normalised_to_luminance(s, o.scale) : scaled(s, o.scale);
}

bool in_gamut(const Vec3& rgb) {
  // The CIE D65 table's white differs from the nominal sRGB white by about 2e-4.
  constexpr double eps = 1e-3;
  return std::min({rgb.x, rgb.y, rgb.z}) >= -eps && std::max({rgb.x, rgb.y, rgb.z}) <= 1.0 + eps;
}

int run_color(const ColorOptions& o) {
  const Observer observer = o.observer == "1964" ? Observer::cie1964_10deg : Observer::cie1931_2deg;
  const Spectrum s = resolve_spectrum(o);
  const Vec3 xyz = spectrum_to_xyz(s, observer);
  const double sum = xyz.x + xyz.y + xyz.z;
  const double x = sum > 0.0 ? xyz.x / sum : 0.0, y = sum > 0.0 ? xyz.y / sum : 0.0;
  // RGB spaces are defined on CIE 1931 XYZ, whatever observer the user asked XYZ and Lab for.
  const Vec3 rgb = xyz_to_linear_rgb(kRec709, spectrum_to_xyz(s, Observer::cie1931_2deg));
  const Vec3 white = spectrum_to_xyz(named_illuminant("D65"), observer);
  const Lab lab = xyz_to_lab(xyz, white);
  const std::string hex = srgb_hex(rgb);
  for (double v : {xyz.x, xyz.y, xyz.z, rgb.x, rgb.y, rgb.z, lab.L, lab.a, lab.b})
    if (!std::isfinite(v)) fail("{}: the colour is not finite at scale {:g} (the spectrum times the scale overflows)", o.spectrum, o.scale);

  if (o.json) {
    const nlohmann::json j = {{"spectrum", o.spectrum},     {"observer", std::string(observer_name(observer))},
                              {"scale", o.scale},           {"XYZ", {xyz.x, xyz.y, xyz.z}},
                              {"xy", {x, y}},               {"linear_srgb", {rgb.x, rgb.y, rgb.z}},
                              {"srgb_hex", hex},            {"in_srgb_gamut", in_gamut(rgb)},
                              {"lab", {lab.L, lab.a, lab.b}}};
    fmt::print("{}\n", j.dump());
    return 0;
  }
  fmt::print("{}  (scale {}, {} observer)\n", o.spectrum, o.scale, observer_name(observer));
  fmt::print("  XYZ          {:9.6f} {:9.6f} {:9.6f}\n", xyz.x, xyz.y, xyz.z);
  fmt::print("  xy           {:9.6f} {:9.6f}\n", x, y);
  fmt::print("  linear sRGB  {:9.6f} {:9.6f} {:9.6f}\n", rgb.x, rgb.y, rgb.z);
  fmt::print("  sRGB         {}{}\n", hex, in_gamut(rgb) ? "" : "  (outside the sRGB gamut or above white: clipped)");
  fmt::print("  CIELAB       {:9.4f} {:9.4f} {:9.4f}  (white: D65, Y = 1)\n", lab.L, lab.a, lab.b);
  return 0;
}

}  // namespace

Command add_color_command(CLI::App& parent) {
  auto options = std::make_shared<ColorOptions>();
  CLI::App* app = parent.add_subcommand(
      "color", "Print XYZ, xy, linear sRGB, sRGB hex and CIELAB of a named illuminant or a CSV spectrum.");
  app->add_option("SPECTRUM", options->spectrum,
                  "D65, D50, A, E, F2, F7, F11, blackbody:<kelvin>, or a CSV file 'wavelength_nm,<quantity>'")
      ->required();
  app->add_option("--observer", options->observer, "Standard observer for XYZ, xy and CIELAB")
      ->check(CLI::IsMember({"1931", "1964"}))
      ->capture_default_str();
  app->add_option("--scale", options->scale,
                  "Named illuminants: luminance Y. CSV spectra: factor on the values (see --normalise)")
      ->check(finite_between(0.0, kMaxEmission))
      ->capture_default_str();
  app->add_flag("--normalise,--normalize", options->normalise, "Scale a CSV spectrum to luminance Y = scale");
  app->add_flag("--json", options->json, "Print one JSON object (XYZ, xy, linear_srgb, srgb_hex, lab)");
  return {app, [options] { return run_color(*options); }};
}

}  // namespace bouguer::cli
