// bouguer material list | NAME | FILE: the library, and the colour of a material by thickness.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

#include "bouguer/analysis/slab_colour.h"
#include "bouguer/core/error.h"
#include "bouguer/io/output_set.h"
#include "bouguer/media/library.h"
#include "bouguer/media/scattering_library.h"
#include "bouguer/plot/material_plot.h"
#include "bouguer/scene/loader.h"
#include "bouguer/scene/material_file.h"
#include "bouguer/spectra/cie.h"
#include "commands.h"

namespace bouguer::cli {
namespace {

struct MaterialOptions {
  std::string what;
  std::string thickness;
  std::string reference;
  std::optional<double> concentration;
  std::optional<double> ior;
  std::string illuminant = "D65";
  std::string plot;
  bool json = false;
  bool info = false;
};

std::vector<double> parse_thicknesses(const std::string& list) {
  std::vector<double> out;
  std::size_t start = 0;
  while (start <= list.size()) {
    const std::size_t comma = list.find(',', start);
    const std::string item = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    double d = 0.0;
    try {
      d = parse_length_m(item);
    } catch (const Error& e) {
      fail("--thickness: {}", e.what());
    }
    if (!(d > 0.0)) fail("--thickness: '{}' must be a positive length", item);
    out.push_back(d);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  std::sort(out.begin(), out.end());
  return out;
}

int list_library() {
  for (const std::string& name : library_material_names()) {
    const LibraryMaterial* m = find_library_material(name);
    fmt::print("{:<24} {:<6} n {:<6.4g} {}{}\n", m->name, m->molar ? "molar" : "", m->default_ior, m->description,
               m->extended() ? " [extended]" : "");
  }
  fmt::print("\nscattering media (for a medium's \"scattering\": {{\"library\": NAME}}):\n");
  for (const ScatteringLibraryEntry& e : scattering_media())
    fmt::print("{:<32} {:<4} n {:<6.4g} g {:<6.3f} {}\n", e.name, e.rgb_measured ? "RGB" : "", e.ior,
               mean_cosine(e.phase), e.description);
  return 0;
}

// A scattering medium: what was measured and its coefficients. No slab colour: once light
// scatters, the colour depends on the geometry and the lighting (render it); the single-scattering
// albedo says how much of the light a collision keeps.
int show_scattering(const ScatteringLibraryEntry& e, bool json) {
  const std::vector<double> nm = {400, 450, 500, 550, 600, 650, 700};
  if (json) {
    nlohmann::json j;
    j["name"] = e.name;
    j["description"] = e.description;
    j["measured"] = e.measured;
    j["citation"] = e.citation;
    j["rgb_measured"] = e.rgb_measured;
    j["ior"] = e.ior;
    j["g"] = mean_cosine(e.phase);
    for (const double l : nm) {
      const double s = eval(e.sigma_s_per_m, l), a = eval(e.sigma_a_per_m, l);
      j["per_wavelength"].push_back({{"wavelength_nm", l}, {"sigma_s_per_m", s}, {"sigma_a_per_m", a},
                                     {"albedo", s + a > 0.0 ? s / (s + a) : 0.0}});
    }
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  fmt::print("name:        {}\n", e.name);
  fmt::print("description: {}\n", e.description);
  fmt::print("measured:    {}\n", e.measured);
  fmt::print("source:      {}\n", e.citation);
  if (e.rgb_measured) fmt::print("RGB ONLY:    three channels were measured; the spectra are lifted from them\n");
  fmt::print("default n:   {}\nphase:       Henyey-Greenstein, g = {:.3f}\n\n", e.ior, mean_cosine(e.phase));
  fmt::print("{:>6}  {:>12}  {:>12}  {:>9}  {:>12}\n", "nm", "σ_s per m", "σ_a per m", "albedo", "1/σ_t (mm)");
  for (const double l : nm) {
    const double s = eval(e.sigma_s_per_m, l), a = eval(e.sigma_a_per_m, l);
    fmt::print("{:>6g}  {:>12.5g}  {:>12.5g}  {:>9.6f}  {:>12.5g}\n", l, s, a, s + a > 0.0 ? s / (s + a) : 0.0,
               s + a > 0.0 ? 1e3 / (s + a) : INFINITY);
  }
  fmt::print("natural log, per metre; albedo = σ_s/(σ_s + σ_a), what one collision keeps; no slab colour is shown:\n"
             "with scattering it depends on the shape and the light (render it with --integrator path)\n");
  return 0;
}

void print_info(const ResolvedMaterial& r) {
  if (const LibraryMaterial* m = r.library) {
    fmt::print("name:        {}\n", m->name);
    fmt::print("description: {}\n", m->description);
    fmt::print("measured:    {}\n", m->measured);
    fmt::print("source:      {}\n", m->citation);
    fmt::print("unit:        sigma_a, natural log, per m{}\n", m->molar ? " per mol/L (give --concentration in mol/L)" : "");
    fmt::print("default n:   {}\n", m->default_ior);
    fmt::print("measured range: {:g}-{:g} nm\n", m->measured_min_nm, m->measured_max_nm);
    if (m->extended())
      fmt::print("EXTENDED:    outside {:g}-{:g} nm the data is {}\n", m->measured_min_nm, m->measured_max_nm,
                 m->extension);
    else
      fmt::print("extension:   none (the data covers 360-830 nm)\n");
    return;
  }
  const MaterialFile& f = *r.file;
  fmt::print("name:        {}\n", f.name);
  if (!f.description.empty()) fmt::print("description: {}\n", f.description);
  if (!f.source.empty()) fmt::print("source:      {}\n", f.source);
  fmt::print("unit:        {}{}\n", absorption_unit_name(f.unit),
             f.thickness_m ? fmt::format(" at {}", format_thickness(*f.thickness_m)) : "");
  fmt::print("measured range: {:g}-{:g} nm\n", f.values.wavelength_nm.front(), f.values.wavelength_nm.back());
  if (f.values.wavelength_nm.front() > kLambdaMinNm || f.values.wavelength_nm.back() < kLambdaMaxNm)
    fmt::print("EXTENDED:    outside that range the end values are held (the table is constant beyond its ends)\n");
}

nlohmann::json colour_json(const SlabColour& c) {
  return {{"xyz", {c.xyz.x, c.xyz.y, c.xyz.z}},
          {"linear_srgb", {c.linear_srgb.x, c.linear_srgb.y, c.linear_srgb.z}},
          {"hex", c.hex}};
}

int run_material(const MaterialOptions& o) {
  OutputSet plot_output;  // checked before any work
  if (!o.plot.empty()) plot_output.add("--plot", o.plot, kPlotExtensions);
  if (o.what == "list") return list_library();
  if (const ScatteringLibraryEntry* e = find_scattering_medium(o.what); e && !find_library_material(o.what)) {
    if (!o.plot.empty() || !o.thickness.empty() || o.concentration)
      fail_usage("{} scatters: --plot, --thickness and --concentration are for absorbing materials (slab colours)", o.what);
    return show_scattering(*e, o.json);
  }
  ResolvedMaterial r = resolve_material(o.what, o.concentration);
  if (o.ior) r.ior = *o.ior;
  if (o.info) {
    print_info(r);
    return 0;
  }
  const std::vector<double> thicknesses =
      o.thickness.empty() ? default_thickness_series(r.sigma_a_per_m) : parse_thicknesses(o.thickness);
  double reference = thicknesses[thicknesses.size() / 2];
  if (!o.reference.empty()) {
    try {
      reference = parse_length_m(o.reference);
    } catch (const Error& e) {
      fail("--reference-thickness: {}", e.what());
    }
    if (!(reference > 0.0)) fail("--reference-thickness must be a positive length");
  }
  const Spectrum illuminant = named_illuminant(o.illuminant, 1.0);
  const ThicknessAnalysis a = analyse_thicknesses(r.sigma_a_per_m, r.ior, thicknesses, illuminant, reference);
  for (const ThicknessRow& row : a.rows) {
    bool finite = std::isfinite(row.delta_e_rgb3) && std::isfinite(row.delta_e_fitted);
    for (double t : row.internal_transmittance) finite = finite && std::isfinite(t);
    if (!finite) fail("{}: the colour at {} is not finite (check --concentration and --thickness)", r.name, format_thickness(row.thickness_m));
  }
  const std::string concentration = r.molar ? fmt::format("{:g} mol/L", r.concentration)
                                    : r.concentration != 1.0 ? fmt::format("x{:g}", r.concentration)
                                                             : "";
  if (!o.plot.empty()) {
    MaterialPlot plot;
    plot.name = r.name;
    plot.concentration_note = concentration;
    plot.sigma_a_per_m = r.sigma_a_per_m;
    plot.illuminant = o.illuminant;
    plot.analysis = a;
    if (r.library) {
      plot.measured_min_nm = r.library->measured_min_nm;
      plot.measured_max_nm = r.library->measured_max_nm;
      plot.extended = r.library->extended();
    } else {
      plot.measured_min_nm = std::max(kLambdaMinNm, r.file->values.wavelength_nm.front());
      plot.measured_max_nm = std::min(kLambdaMaxNm, r.file->values.wavelength_nm.back());
      plot.extended = plot.measured_min_nm > kLambdaMinNm || plot.measured_max_nm < kLambdaMaxNm;
    }
    plot_output.write_all({{"--plot", [&plot](const std::filesystem::path& p) { write_material_plot(p, plot); }}});
  }
  if (o.json) {
    nlohmann::json j;
    j["material"] = r.name;
    j["ior"] = r.ior;
    j["molar"] = r.molar;
    j["concentration"] = r.concentration;
    j["illuminant"] = o.illuminant;
    j["reference_thickness_m"] = reference;
    j["rgb3_sigma_a_per_m"] = {a.rgb3_sigma_a_per_m.x, a.rgb3_sigma_a_per_m.y, a.rgb3_sigma_a_per_m.z};
    j["fitted_sigma_a_per_m"] = {a.fitted_sigma_a_per_m.x, a.fitted_sigma_a_per_m.y, a.fitted_sigma_a_per_m.z};
    for (const ThicknessRow& row : a.rows) {
      nlohmann::json t;
      t["thickness_m"] = row.thickness_m;
      for (std::size_t i = 0; i < a.probe_nm.size(); ++i)
        t["internal_transmittance"][fmt::format("{:g}", a.probe_nm[i])] = row.internal_transmittance[i];
      t["spectral"] = colour_json(row.spectral);
      t["rgb3"] = colour_json(row.rgb3);
      t["rgb3"]["delta_e00"] = row.delta_e_rgb3;
      t["fitted"] = colour_json(row.fitted);
      t["fitted"]["delta_e00"] = row.delta_e_fitted;
      j["thicknesses"].push_back(t);
    }
    fmt::print("{}\n", j.dump(2));
    return 0;
  }
  fmt::print("{}{}: slab in air, n = {:g}, normal incidence, under {} (Y = 1); RGB fitted at {}\n", r.name,
             concentration.empty() ? "" : " at " + concentration, r.ior, o.illuminant, format_thickness(reference));
  fmt::print("{:>10}  {:>7} {:>7} {:>7}  {:<8} {:>7} {:>7} {:>7}  {:<8} {:>6}  {:<8} {:>6}\n", "thickness", "T450",
             "T550", "T650", "spectral", "R", "G", "B", "rgb3", "ΔE00", "fitted", "ΔE00");
  for (const ThicknessRow& row : a.rows)
    fmt::print("{:>10}  {:>7.4f} {:>7.4f} {:>7.4f}  {:<8} {:>7.4f} {:>7.4f} {:>7.4f}  {:<8} {:>6.2f}  {:<8} {:>6.2f}\n",
               format_thickness(row.thickness_m), row.internal_transmittance[0], row.internal_transmittance[1],
               row.internal_transmittance[2], row.spectral.hex, row.spectral.linear_srgb.x, row.spectral.linear_srgb.y,
               row.spectral.linear_srgb.z, row.rgb3.hex, row.delta_e_rgb3, row.fitted.hex, row.delta_e_fitted);
  fmt::print("T: internal transmittance at 450/550/650 nm; R G B: linear Rec.709 of the light through the slab\n");
  return 0;
}

}  // namespace

Command add_material_command(CLI::App& parent) {
  auto o = std::make_shared<MaterialOptions>();
  CLI::App* app = parent.add_subcommand(
      "material", "The material library, and the colour of a material by thickness against the RGB shortcuts.");
  app->add_option("what", o->what, "'list', a library name (see 'bouguer material list') or a material CSV file")
      ->required();
  app->add_option("--thickness", o->thickness,
                  "comma-separated thicknesses with units, e.g. 1mm,2mm,4mm (default: 7 from pale to deep)");
  app->add_option("--reference-thickness", o->reference,
                  "where the fitted RGB renderer matches exactly (default: the middle thickness)");
  app->add_option("--concentration", o->concentration, "mol/L for solutes (molar materials), else a factor on σ_a")
      ->check(finite_between(0.0, 1e12));
  app->add_option("--ior", o->ior, "refractive index of the slab (default: the material's)")
      ->check(finite_between(1.0, 5.0));
  app->add_option("--illuminant", o->illuminant, "the light behind the slab: D65, D50, A, E, F2, F7, F11, blackbody:<K>")
      ->capture_default_str();
  app->add_option("--plot", o->plot, "also draw the figure to OUT.svg, OUT.png or OUT.pdf");
  app->add_flag("--json", o->json, "print JSON instead of a table");
  app->add_flag("--info", o->info, "where the data comes from, its unit and measured range, and how it is extended");
  return {app, [o] { return run_material(*o); }};
}

}  // namespace bouguer::cli
