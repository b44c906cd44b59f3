#pragma once
// The figure of `bouguer material --plot`: the absorption spectrum with its unit (the paper's
// Figs. 1 and 7), internal transmittance for a set of thicknesses (Fig. 2), swatches of the slab's
// colour from thin to thick for the spectral answer and the two RGB shortcuts, and ΔE00 of the
// shortcuts against thickness. Drawn once with cairo; SVG, PNG or PDF by the file's extension.
#include <array>
#include <filesystem>
#include <string>
#include <string_view>

#include "bouguer/analysis/slab_colour.h"
#include "bouguer/spectra/spectrum.h"

namespace bouguer {

struct MaterialPlot {
  std::string name;
  std::string concentration_note;  // e.g. "0.01 mol/L", empty when not applicable
  Spectrum sigma_a_per_m;          // concentration applied
  double measured_min_nm = 360.0, measured_max_nm = 830.0;
  bool extended = false;
  std::string illuminant = "D65";
  ThicknessAnalysis analysis;
};

// Writes atomically; the format follows the extension (.svg, .png, .pdf), anything else is an Error.
inline constexpr std::array<std::string_view, 3> kPlotExtensions = {".svg", ".png", ".pdf"};
void write_material_plot(const std::filesystem::path& path, const MaterialPlot& plot);

// The same drawing in memory: "svg", "png" or "pdf" bytes.
std::string render_material_plot(const MaterialPlot& plot, const std::string& format);

}  // namespace bouguer
