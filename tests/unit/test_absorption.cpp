#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <cmath>

#include "bouguer/core/error.h"
#include "bouguer/media/absorption.h"
#include "bouguer/media/ior.h"
#include "bouguer/media/ior_library.h"
#include "bouguer/media/library.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

constexpr double kSigmaOfAbsorbance1PerCm = 230.25850929940458;  // ln(10) · 100 per m

TabulatedSpectrum flat(double v, double nm = 550.0) { return make_tabulated({nm}, {v}, "test"); }

double sigma(const TabulatedSpectrum& t, AbsorptionUnit u, double concentration = 1.0,
             std::optional<double> thickness = std::nullopt) {
  return eval(to_sigma_a_per_m(t, u, concentration, thickness, "test"), 550.0);
}

// The same absorber (10 % internal transmittance through 1 cm at 550 nm) in every unit.
TEST(Absorption, EveryUnitGivesTheSameSigma) {
  EXPECT_NEAR(absorbance_per_cm_to_sigma_a_per_m(1.0), kSigmaOfAbsorbance1PerCm, 1e-9);
  EXPECT_NEAR(sigma(flat(kSigmaOfAbsorbance1PerCm), AbsorptionUnit::attenuation_per_m), kSigmaOfAbsorbance1PerCm, 1e-9);
  EXPECT_NEAR(sigma(flat(1.0), AbsorptionUnit::absorbance_per_cm), kSigmaOfAbsorbance1PerCm, 1e-9);
  EXPECT_NEAR(sigma(flat(0.1), AbsorptionUnit::internal_transmittance, 1.0, 0.01), kSigmaOfAbsorbance1PerCm, 1e-9);
  EXPECT_NEAR(sigma(flat(0.01), AbsorptionUnit::internal_transmittance, 1.0, 0.02), kSigmaOfAbsorbance1PerCm, 1e-9);
  // ε = 250 L/(mol·cm) at c = 0.004 mol/L: A = 1 per cm.
  EXPECT_NEAR(sigma(flat(250.0), AbsorptionUnit::molar_absorptivity, 0.004), kSigmaOfAbsorbance1PerCm, 1e-9);
  // k = σ λ / 4π.
  const double k = kSigmaOfAbsorbance1PerCm * 550e-9 / (4.0 * std::numbers::pi);
  EXPECT_NEAR(sigma(flat(k), AbsorptionUnit::extinction_coefficient), kSigmaOfAbsorbance1PerCm, 1e-9);
}

TEST(Absorption, ConcentrationScalesLinearly) {
  EXPECT_NEAR(sigma(flat(1.0), AbsorptionUnit::absorbance_per_cm, 2.0), 2.0 * kSigmaOfAbsorbance1PerCm, 1e-9);
  EXPECT_EQ(sigma(flat(1.0), AbsorptionUnit::absorbance_per_cm, 0.0), 0.0);
}

TEST(Absorption, ImpossibleValuesAreRefused) {
  EXPECT_THROW(sigma(flat(0.0), AbsorptionUnit::internal_transmittance, 1.0, 0.01), Error);
  EXPECT_THROW(sigma(flat(1.2), AbsorptionUnit::internal_transmittance, 1.0, 0.01), Error);
  EXPECT_THROW(sigma(flat(0.5), AbsorptionUnit::internal_transmittance), Error);       // no thickness
  EXPECT_THROW(sigma(flat(0.5), AbsorptionUnit::absorbance_per_cm, 1.0, 0.01), Error);  // stray thickness
  EXPECT_THROW(sigma(flat(-1.0), AbsorptionUnit::absorbance_per_cm), Error);
  EXPECT_THROW(sigma(flat(1.0), AbsorptionUnit::absorbance_per_cm, -1.0), Error);
  EXPECT_FALSE(absorption_unit_from_name("absorbance").has_value());
  EXPECT_EQ(absorption_unit_from_name("molar_absorptivity"), AbsorptionUnit::molar_absorptivity);
}

// N-BK7 (SCHOTT): n_d = 1.5168 at 587.56 nm, n_F = 1.5224 at 486.13 nm.
TEST(Ior, SellmeierMatchesBk7Catalogue) {
  const SellmeierIor bk7{{1.03961212, 0.231792344, 1.01046945}, {0.00600069867, 0.0200179144, 103.560653}};
  EXPECT_NEAR(sellmeier_ior(bk7, 587.56), 1.5168, 1e-4);
  EXPECT_NEAR(sellmeier_ior(bk7, 486.13), 1.5224, 1e-4);
  EXPECT_NEAR(cauchy_ior({1.5, 0.004, 0.0}, 500.0), 1.5 + 0.004 / 0.25, 1e-12);
  EXPECT_EQ(ior_at(ConstantIor{1.33}, 400.0), 1.33);
}

// n_d (587.56 nm) from the built-in dispersion data against catalogue and handbook values
// (SCHOTT data sheets; refractiveindex.info as checked in shared/data/refractiveindex.info/SOURCE.txt).
TEST(Ior, LibraryMatchesCatalogueValues) {
  const std::pair<const char*, double> expected[] = {{"N-BK7", 1.51680}, {"F2", 1.62004},   {"N-SF11", 1.78472},
                                                     {"fused-silica", 1.45846}, {"water", 1.33340}, {"diamond", 2.41749}};
  for (const auto& [name, n_d] : expected) {
    const IorLibraryEntry* e = find_ior_material(name);
    ASSERT_NE(e, nullptr) << name;
    EXPECT_NEAR(sellmeier_ior(e->sellmeier, 587.56), n_d, 2e-5) << name;
    EXPECT_FALSE(e->citation.empty());
    // Normal dispersion: n falls with wavelength across the visible.
    EXPECT_GT(sellmeier_ior(e->sellmeier, 400.0), sellmeier_ior(e->sellmeier, 700.0)) << name;
  }
}

// The Abbe form reproduces n_d and the Abbe number it was built from.
TEST(Ior, AbbeFormReproducesItsDefinition) {
  const CauchyIor c = cauchy_from_abbe(2.417, 55.3);
  const double nd = cauchy_ior(c, 587.56), nf = cauchy_ior(c, 486.13), nc = cauchy_ior(c, 656.27);
  EXPECT_NEAR(nd, 2.417, 1e-9);
  EXPECT_NEAR((nd - 1.0) / (nf - nc), 55.3, 1e-6);
}

// Every library entry loads, is finite and non-negative over the domain, and names its source.
TEST(Library, EveryEntryIsCompleteAndPhysical) {
  const auto names = library_material_names();
  for (const char* required : {"red-glass", "light-blue-glass", "red-wine", "white-wine", "water"})
    EXPECT_NE(std::find(names.begin(), names.end(), required), names.end()) << required;
  int glasses = 0, molar = 0, gems = 0;
  for (const auto& name : names) {
    const LibraryMaterial* m = find_library_material(name);
    ASSERT_NE(m, nullptr) << name;
    EXPECT_FALSE(m->citation.empty()) << name;
    EXPECT_FALSE(m->measured.empty()) << name;
    EXPECT_GE(m->default_ior, 1.0);
    EXPECT_FALSE(m->description.empty()) << name;
    // Measured range inside the domain; data beyond it is extended by a stated rule.
    EXPECT_GE(m->measured_min_nm, kLambdaMinNm) << name;
    EXPECT_LE(m->measured_max_nm, kLambdaMaxNm) << name;
    EXPECT_EQ(m->extended(), m->measured_min_nm > kLambdaMinNm || m->measured_max_nm < kLambdaMaxNm) << name;
    glasses += name.find("glass") != std::string::npos;
    molar += m->molar;
    gems += name == "ruby" || name == "emerald";
    for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm; nm += 1.0) {
      const double s = eval(m->sigma_a_per_m, nm);
      ASSERT_TRUE(std::isfinite(s) && s >= 0.0) << name << " at " << nm;
    }
  }
  EXPECT_GE(glasses, 6);
  EXPECT_GE(molar, 5);
  EXPECT_GE(gems, 1);
  EXPECT_EQ(find_library_material("blue-glass"), nullptr);
}

// The red glass has the paper's abrupt edge: transparent in the red, opaque in the green.
TEST(Library, RedGlassHasAnAbruptEdgeAndTheWinesMatchTheirTargets) {
  const LibraryMaterial& red = *find_library_material("red-glass");
  EXPECT_LT(eval(red.sigma_a_per_m, 650.0), 5.0);      // per m: nearly clear
  EXPECT_GT(eval(red.sigma_a_per_m, 550.0), 2000.0);   // opaque within a millimetre
  // The wine models reproduce their fitted Glories targets (decadic absorbance per cm).
  const LibraryMaterial& white = *find_library_material("white-wine");
  EXPECT_NEAR(eval(white.sigma_a_per_m, 420.0) / kSigmaOfAbsorbance1PerCm, 0.17, 1e-4);
  EXPECT_NEAR(eval(white.sigma_a_per_m, 620.0) / kSigmaOfAbsorbance1PerCm, 0.006, 1e-5);
  const LibraryMaterial& redwine = *find_library_material("red-wine");
  EXPECT_NEAR(eval(redwine.sigma_a_per_m, 520.0) / kSigmaOfAbsorbance1PerCm, 1.90, 1e-3);
}

// Water equals the IOCCG table (tests/data/water) where it is tabulated and is clearest in the blue:
// 10 m of water keep 94 % at 440 nm (Pope & Fry 0.00635 /m) but 0.2 % at 700 nm (0.624 /m).
TEST(Library, WaterMatchesTheIoccgTable) {
  const LibraryMaterial& water = *find_library_material("water");
  EXPECT_DOUBLE_EQ(eval(water.sigma_a_per_m, 440.0), 0.00635);
  EXPECT_DOUBLE_EQ(eval(water.sigma_a_per_m, 700.0), 0.624);
  std::ifstream src(test::test_data("water/ioccg_2018.csv"));
  ASSERT_TRUE(src) << test::test_data("water/ioccg_2018.csv");
  std::string line;
  std::getline(src, line);
  int checked = 0;
  while (std::getline(src, line)) {
    const double nm = std::stod(line.substr(0, line.find(',')));
    if (nm < 360.0 || nm > 830.0) continue;
    const std::string rest = line.substr(line.find(',') + 1);
    EXPECT_DOUBLE_EQ(eval(water.sigma_a_per_m, nm), std::stod(rest.substr(0, rest.find(',')))) << nm << " nm";
    ++checked;
  }
  EXPECT_EQ(checked, 95);
  EXPECT_DOUBLE_EQ(water.default_ior, 1.333);
}

}  // namespace
}  // namespace bouguer
