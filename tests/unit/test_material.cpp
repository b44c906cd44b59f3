// `bouguer material`: the colour of thickness equals the renderer's slab, doubling concentration
// equals doubling thickness, and the command's outputs (table, JSON, plots, info, errors).
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "bouguer/analysis/slab_colour.h"
#include "bouguer/media/library.h"
#include "bouguer/media/scattering_library.h"
#include "bouguer/render/render.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "bouguer/scene/material_file.h"
#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"
#include "support/test_support.h"

namespace bouguer {
namespace {


// The slab test of #3: a slab of the library material between a D65 panel (Y = 1) and an
// orthographic camera, in vacuum, rendered in full spectrum by the Whitted tracer (exact: every
// branch of the multiple reflections is followed).
Vec3 rendered_slab(const std::string& absorption, double thickness_m) {
  const std::string scene = fmt::format(R"({{
    "camera": {{"type": "orthographic", "position": [0, 0, {0}], "look_at": [0, 0, 0], "width": "5 mm",
                "resolution": [2, 2]}},
    "render": {{"integrator": "whitted", "spectral": "full", "spp": 1, "max_depth": 16}},
    "world_medium": "vacuum",
    "media": {{"m": {{"absorption": {1}}}}},
    "objects": [
      {{"name": "slab", "shape": {{"type": "box", "size": ["60 mm", "60 mm", {2}]}}, "inside": "m"}},
      {{"name": "panel", "shape": {{"type": "quad", "size": [1, 1]}}, "transform": [{{"translate": [0, 0, {3}]}}],
        "emission": {{"spectrum": "D65", "scale": 1}}}}
    ]
  }})",
                                        thickness_m + 0.1, absorption, thickness_m, -(thickness_m / 2 + 0.05));
  const Film f = test::render_text(scene);
  const Vec3f c = f.rgb_at(0, 0);
  return {c.x, c.y, c.z};
}

double delta_e(const Vec3& a, const Vec3& b) {
  const Vec3 white = spectrum_to_xyz(named_illuminant("D65"));
  return ciede2000(xyz_to_lab(linear_rgb_to_xyz(kRec709, a), white), xyz_to_lab(linear_rgb_to_xyz(kRec709, b), white));
}

// For every library material, at its characteristic thickness and at a quarter of it.
TEST(Material, ColourOfThicknessEqualsTheRenderedSlab) {
  double worst = 0.0;
  for (const std::string& name : library_material_names()) {
    const LibraryMaterial& m = *find_library_material(name);
    const double c = m.molar ? 0.01 : 1.0;
    const Spectrum sigma = scaled(m.sigma_a_per_m, c);
    const double d0 = default_thickness_series(sigma)[3];  // about 1 / mean σ_a: the colour well formed
    for (const double d : {d0, d0 / 4}) {
      const ThicknessAnalysis a = analyse_thicknesses(sigma, m.default_ior, {d}, named_illuminant("D65"), d);
      const std::string absorption =
          m.molar ? fmt::format(R"({{"library": "{}", "concentration": {}}})", name, c)
                  : fmt::format(R"({{"library": "{}"}})", name);
      const Vec3 rendered = rendered_slab(absorption, d);
      const double e = delta_e(a.rows[0].spectral.linear_srgb, rendered);
      worst = std::max(worst, e);
      EXPECT_LT(e, 0.3) << name << " at " << d << " m: tool " << a.rows[0].spectral.hex << ", render "
                        << srgb_hex(rendered);
    }
  }
  std::printf("bouguer material vs rendered slab: worst ΔE00 %.3f over %zu materials\n", worst,
              library_material_names().size());
}

// Beer's law: c·d is all that matters, in the tool and in the renderer.
TEST(Material, DoublingConcentrationEqualsDoublingThickness) {
  const ResolvedMaterial thin = resolve_material("potassium-permanganate", 0.0004);
  const ResolvedMaterial dilute = resolve_material("potassium-permanganate", 0.0002);
  const auto a = analyse_thicknesses(thin.sigma_a_per_m, thin.ior, {0.005}, named_illuminant("D65"), 0.005);
  const auto b = analyse_thicknesses(dilute.sigma_a_per_m, dilute.ior, {0.010}, named_illuminant("D65"), 0.010);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(a.rows[0].spectral.xyz[k], b.rows[0].spectral.xyz[k], 1e-12);
  const Vec3 r1 = rendered_slab(R"({"library": "potassium-permanganate", "concentration": 0.0004})", 0.005);
  const Vec3 r2 = rendered_slab(R"({"library": "potassium-permanganate", "concentration": 0.0002})", 0.010);
  EXPECT_LT(delta_e(r1, r2), 1e-3);
  EXPECT_LT(delta_e(r1, a.rows[0].spectral.linear_srgb), 0.3);
}

// The RGB shortcuts: the fitted renderer is exact at its reference thickness (for a colour inside
// the Rec.709 gamut: an RGB renderer cannot make negative channels) and drifts away from it.
TEST(Material, FittedRgbIsExactAtItsReferenceOnly) {
  const LibraryMaterial& blue = *find_library_material("light-blue-glass");
  const auto a = analyse_thicknesses(blue.sigma_a_per_m, 1.52, {0.001, 0.004, 0.016}, named_illuminant("D65"), 0.004);
  EXPECT_LT(a.rows[1].delta_e_fitted, 1e-3);
  EXPECT_GT(a.rows[0].delta_e_fitted + a.rows[2].delta_e_fitted, 1.0);
  EXPECT_GT(a.rows[2].delta_e_rgb3, 1.0);
}

TEST(MaterialCli, ListsTheLibraryOneLineEach) {
  const auto r = test::run_bouguer({"material", "list"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // The absorbers, a blank line and a heading, then the scattering media.
  EXPECT_EQ(test::line_count(r.out),
            static_cast<int>(library_material_names().size() + 2 + scattering_medium_names().size()));
  EXPECT_NE(r.out.find("potassium-permanganate"), std::string::npos);
  EXPECT_NE(r.out.find("whole_milk"), std::string::npos);
}

// A scattering medium shows σ_s, σ_a, the albedo and g with its provenance, never a slab colour
// (meaningless once light scatters); the slab options are refused.
TEST(MaterialCli, ScatteringMediaShowTheirCoefficientsNotASlabColour) {
  const auto table = test::run_bouguer({"material", "skimmed_milk"});
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("albedo"), std::string::npos);
  EXPECT_NE(table.out.find("Frisvad"), std::string::npos);
  EXPECT_EQ(table.out.find("ΔE00"), std::string::npos);
  const auto rgb = test::run_bouguer({"material", "espresso"});
  EXPECT_NE(rgb.out.find("RGB ONLY"), std::string::npos);
  const auto json = test::run_bouguer({"material", "whole_milk", "--json"});
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto j = nlohmann::json::parse(json.out);
  const auto& at550 = j["per_wavelength"][3];
  EXPECT_EQ(at550["wavelength_nm"].get<double>(), 550.0);
  const double s = at550["sigma_s_per_m"].get<double>(), a = at550["sigma_a_per_m"].get<double>();
  EXPECT_GT(s, 1e4);  // whole milk: tens of thousands per metre
  EXPECT_NEAR(at550["albedo"].get<double>(), s / (s + a), 1e-12);
  const auto bad = test::run_bouguer({"material", "whole_milk", "--thickness", "1mm"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find("whole_milk scatters"), std::string::npos) << bad.err;
}

TEST(MaterialCli, TableJsonInfoAndPlots) {
  const auto dir = test::scratch_dir("material_cli");
  const auto table = test::run_bouguer({"material", "red-glass", "--thickness", "1mm,2mm,4mm"});
  EXPECT_EQ(table.exit_code, 0) << table.err;
  EXPECT_EQ(test::line_count(table.out), 6) << table.out;  // title, header, 3 rows, legend
  const auto json = test::run_bouguer({"material", "copper-sulfate", "--concentration", "0.5", "--json"});
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["thicknesses"].size(), 7u);
  EXPECT_TRUE(j["thicknesses"][0]["spectral"]["hex"].get<std::string>().starts_with("#"));
  const auto info = test::run_bouguer({"material", "ruby", "--info"});
  EXPECT_EQ(info.exit_code, 0);
  EXPECT_NE(info.out.find("EXTENDED"), std::string::npos) << info.out;
  EXPECT_NE(info.out.find("NOT MEASURED"), std::string::npos) << info.out;
  const auto water = test::run_bouguer({"material", "water", "--info"});
  EXPECT_EQ(water.out.find("EXTENDED"), std::string::npos) << water.out;
  for (const char* ext : {"svg", "png", "pdf"}) {
    const auto plot = dir / fmt::format("red.{}", ext);
    const auto r = test::run_bouguer({"material", "red-glass", "--plot", plot.string()});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string bytes = test::read_file(plot);
    ASSERT_GT(bytes.size(), 2000u) << ext;
    const std::string e = ext;
    if (e == "png") {
      EXPECT_EQ(bytes.substr(1, 3), "PNG");
    } else if (e == "svg") {
      EXPECT_NE(bytes.find("<svg"), std::string::npos);
    } else {
      EXPECT_EQ(bytes.substr(0, 4), "%PDF");
    }
  }
}

// A user material: a CSV naming its unit, read the same way by the command and by a scene.
TEST(MaterialCli, UserCsvWorksInTheCommandAndInAScene) {
  const auto dir = test::scratch_dir("material_csv");
  test::write_file(dir / "amber.csv",
                   "# name: amber test glass\n# unit: internal_transmittance\n# thickness: 2 mm\n# ior: 1.54\n"
                   "wavelength_nm,value\n380,0.05\n480,0.40\n580,0.80\n680,0.92\n780,0.95\n");
  const auto r = test::run_bouguer({"material", (dir / "amber.csv").string(), "--thickness", "2mm", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  // σ_a is interpolated between the table's points: τ(550) = 0.40^0.3 · 0.80^0.7.
  EXPECT_NEAR(j["thicknesses"][0]["internal_transmittance"]["550"].get<double>(), std::pow(0.4, 0.3) * std::pow(0.8, 0.7),
              1e-9);
  EXPECT_DOUBLE_EQ(j["ior"].get<double>(), 1.54);
  const ResolvedMaterial m = resolve_material((dir / "amber.csv").string(), std::nullopt);
  const auto a = analyse_thicknesses(m.sigma_a_per_m, m.ior, {0.002}, named_illuminant("D65"), 0.002);
  const Vec3 rendered = rendered_slab(fmt::format(R"({{"csv": "{}"}})", (dir / "amber.csv").string()), 0.002);
  EXPECT_LT(delta_e(rendered, a.rows[0].spectral.linear_srgb), 0.3);
}

TEST(MaterialCli, BadInputGivesOneLine) {
  const auto dir = test::scratch_dir("material_bad");
  test::write_file(dir / "nounit.csv", "wavelength_nm,value\n400,1\n700,2\n");
  test::write_file(dir / "twice.csv",
                   "# unit: absorbance_per_cm\n# unit: attenuation_per_m\nwavelength_nm,value\n400,1\n700,2\n");
  test::write_file(dir / "infrared.csv", "# unit: absorbance_per_cm\nwavelength_nm,value\n1000,1\n1100,2\n");
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"material", "red-glas"}, "did you mean 'red-glass'?"},
      {{"material", "copper-sulfate"}, "give --concentration in mol/L"},
      {{"material", (dir / "nounit.csv").string()}, "no '# unit: ...' line"},
      {{"material", (dir / "twice.csv").string()}, "twice.csv:2: 'unit' is given twice"},
      {{"material", (dir / "infrared.csv").string()}, "covers 1000-1100 nm, none of the range 360-830 nm"},
      {{"material", "water", "--thickness", "1 furlong"}, "--thickness"},
      {{"material", "water", "--thickness", "2"}, "--thickness: '2' has no unit"},
      {{"material", "water", "--thickness", "nan mm"}, "not a finite length"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = test::run_bouguer(args);
    EXPECT_EQ(r.exit_code, 1) << args[1];
    EXPECT_EQ(test::line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
  // Command-line errors (exit 2): CLI11's range checks alone would let NaN through; a plot that
  // cannot be written is refused before the analysis.
  const std::vector<std::pair<std::vector<std::string>, std::string>> usage = {
      {{"material", "water", "--ior", "nan"}, "--ior"},
      {{"material", "water", "--ior", "inf"}, "--ior"},
      {{"material", "water", "--ior", "0.5"}, "--ior"},
      {{"material", "water", "--plot", (dir / "x.gif").string()}, ".svg, .png or .pdf"},
      {{"material", "water", "--plot", (dir / "absent" / "x.svg").string()},
       "--plot " + (dir / "absent" / "x.svg").string() + ": folder"},
  };
  for (const auto& [args, expected] : usage) {
    const auto r = test::run_bouguer(args);
    EXPECT_EQ(r.exit_code, 2) << args.back();
    EXPECT_EQ(test::line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace bouguer
