#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "bouguer/core/error.h"
#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/color_space.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

struct Xy {
  double x, y;
};

Xy chromaticity(const Spectrum& s, Observer o = Observer::cie1931_2deg) {
  const Vec3 xyz = spectrum_to_xyz(s, o);
  const double sum = xyz.x + xyz.y + xyz.z;
  return {xyz.x / sum, xyz.y / sum};
}

void expect_xy(const Spectrum& s, Xy expected, double tolerance, Observer o = Observer::cie1931_2deg) {
  const Xy got = chromaticity(s, o);
  EXPECT_NEAR(got.x, expected.x, tolerance);
  EXPECT_NEAR(got.y, expected.y, tolerance);
}

// White points from CIE 015:2018 Table 1 / Table 10.x.
TEST(Colorimetry, D65AndAChromaticities1931) {
  expect_xy(named_illuminant("D65"), {0.3127, 0.3290}, 0.0002);
  expect_xy(named_illuminant("A"), {0.4476, 0.4074}, 0.0002);
  expect_xy(named_illuminant("D50"), {0.3457, 0.3585}, 0.0002);
}

TEST(Colorimetry, D65Chromaticity1964) {
  expect_xy(named_illuminant("D65"), {0.3138, 0.3310}, 0.0002, Observer::cie1964_10deg);
}

// CIE 015:2018 Table 10.5 (computed there from the 5 nm tables; ours are the CIE's 1 nm interpolation).
TEST(Colorimetry, FluorescentChromaticities) {
  expect_xy(named_illuminant("F2"), {0.3721, 0.3751}, 0.0005);
  expect_xy(named_illuminant("F7"), {0.3129, 0.3292}, 0.0005);
  expect_xy(named_illuminant("F11"), {0.3805, 0.3769}, 0.0005);
}

// Illuminant A is defined (ISO/CIE 11664-2 eq. 1) by Planck's formula with c2 = 1.435e-2 m·K and
// T = 2848 K; with today's c2 = 1.438777e-2 m·K that is the blackbody at 2848 · 1.438777 / 1.435 K
// (about 2856 K).
TEST(Colorimetry, IlluminantAIsAPlanckianRadiator) {
  const double kelvin = 2848.0 * 1.438777 / 1.435;
  const Xy bb = chromaticity(BlackbodySpectrum{kelvin, 1.0});
  const Xy a = chromaticity(named_illuminant("A"));
  EXPECT_NEAR(bb.x, a.x, 2e-5);
  EXPECT_NEAR(bb.y, a.y, 2e-5);
}

TEST(Colorimetry, D65WithScaleOneIsLinearSrgbWhite) {
  const Vec3 rgb = xyz_to_linear_rgb(kRec709, spectrum_to_xyz(named_illuminant("D65", 1.0)));
  EXPECT_NEAR(rgb.x, 1.0, 0.002);
  EXPECT_NEAR(rgb.y, 1.0, 0.002);
  EXPECT_NEAR(rgb.z, 1.0, 0.002);
}

TEST(Colorimetry, ScaleIsLuminance) {
  for (const char* name : {"D65", "A", "F11", "E", "blackbody:3200K"})
    EXPECT_NEAR(spectrum_to_xyz(named_illuminant(name, 3.5)).y, 3.5, 1e-12) << name;
}

TEST(Colorimetry, EqualEnergyHasUnitLuminanceAndIsNearlyNeutral) {
  const Vec3 xyz = spectrum_to_xyz(ConstantSpectrum{1.0});
  EXPECT_NEAR(xyz.y, 1.0, 1e-12);  // the normalisation: ∫ȳ / ∫ȳ
  expect_xy(ConstantSpectrum{1.0}, {1.0 / 3.0, 1.0 / 3.0}, 1e-4);
}

TEST(Colorimetry, NamesAreCaseInsensitiveAndUnknownNamesFail) {
  EXPECT_TRUE(named_illuminant_spd("d65").has_value());
  EXPECT_FALSE(named_illuminant_spd("D66").has_value());
  EXPECT_FALSE(named_illuminant_spd("blackbody:abc").has_value());
  EXPECT_FALSE(named_illuminant_spd("blackbody:-5").has_value());
  EXPECT_THROW(named_illuminant("D66"), Error);
}

// The compiled-in tables are the CIE's numbers, unchanged (checked against the CIE files, copied verbatim
// into tests/data/cie).
TEST(Colorimetry, CompiledTablesEqualTheCieFiles) {
  const struct {
    const char* file;
    Observer observer;
  } cases[] = {{"cie/CIE_xyz_1931_2deg.csv", Observer::cie1931_2deg},
               {"cie/CIE_xyz_1964_10deg.csv", Observer::cie1964_10deg}};
  for (const auto& c : cases) {
    std::ifstream in(test::test_data(c.file));
    ASSERT_TRUE(in) << "missing " << test::test_data(c.file);
    const ObserverTable& t = observer_table(c.observer);
    std::string line;
    int rows = 0;
    while (std::getline(in, line)) {
      if (line.empty() || line == "\r") continue;
      std::istringstream cells(line);
      std::string nm, x, y, z;
      std::getline(cells, nm, ',');
      std::getline(cells, x, ',');
      std::getline(cells, y, ',');
      std::getline(cells, z, ',');
      const int i = std::stoi(nm) - static_cast<int>(kLambdaMinNm);
      const double zv = z.rfind("NaN", 0) == 0 ? 0.0 : std::stod(z);  // CIE: NaN means 0
      EXPECT_EQ(t.xbar[i], std::stod(x)) << c.file << " " << nm;
      EXPECT_EQ(t.ybar[i], std::stod(y)) << c.file << " " << nm;
      EXPECT_EQ(t.zbar[i], zv) << c.file << " " << nm;
      ++rows;
    }
    EXPECT_EQ(rows, kCmfCount);
  }
}

}  // namespace
}  // namespace bouguer
