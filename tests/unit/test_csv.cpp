#include <gtest/gtest.h>

#include "bouguer/core/error.h"
#include "bouguer/core/csv.h"
#include "bouguer/spectra/spectrum_csv.h"
#include "support/test_support.h"

namespace bouguer {
namespace {

// The error message for loading `text` as a spectrum file named name.csv.
std::string load_error(const std::string& name, const std::string& text, SpectrumCsvRules rules = {}) {
  const auto dir = test::scratch_dir("csv_" + name);
  const auto path = dir / (name + ".csv");
  test::write_file(path, text);
  try {
    load_spectrum_csv(path, rules);
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << "one line";
    EXPECT_NE(std::string(e.what()).find(name + ".csv"), std::string::npos) << "names the file: " << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error for " << name;
  return {};
}

TEST(Csv, ParsesCommentsHeaderAndCrlf) {
  const CsvTable t = parse_csv("# source: test\r\nwavelength_nm, value\r\n400,1\r\n\r\n500, 2.5e-1\r\n", "t.csv");
  ASSERT_EQ(t.columns, (std::vector<std::string>{"wavelength_nm", "value"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_DOUBLE_EQ(t.rows[1][1], 0.25);
  EXPECT_EQ(t.line[0], 3);
  EXPECT_EQ(t.line[1], 5);
}

TEST(SpectrumCsv, LoadsAValidFile) {
  const auto dir = test::scratch_dir("csv_valid");
  test::write_file(dir / "s.csv", "wavelength_nm,transmittance\n400,0.5\n700,0.9\n");
  const TabulatedSpectrum s = load_spectrum_csv(dir / "s.csv");
  EXPECT_DOUBLE_EQ(eval(s, 550), 0.7);
}

TEST(SpectrumCsv, NonMonotonicWavelengthNamesTheLine) {
  const std::string e = load_error("nonmono", "wavelength_nm,v\n400,1\n500,1\n450,1\n");
  EXPECT_NE(e.find("line 4"), std::string::npos) << e;
  EXPECT_NE(e.find("does not increase"), std::string::npos) << e;
}

TEST(SpectrumCsv, NanIsRejected) {
  const std::string e = load_error("nan", "wavelength_nm,v\n400,1\n500,nan\n");
  EXPECT_NE(e.find("line 3"), std::string::npos) << e;
}

TEST(SpectrumCsv, NegativeIsRejectedUnlessAllowed) {
  const std::string e = load_error("negative", "wavelength_nm,v\n400,1\n500,-0.1\n");
  EXPECT_NE(e.find("negative"), std::string::npos) << e;
  const auto dir = test::scratch_dir("csv_negative_ok");
  test::write_file(dir / "n.csv", "wavelength_nm,v\n400,1\n500,-0.1\n");
  EXPECT_DOUBLE_EQ(eval(load_spectrum_csv(dir / "n.csv", {.allow_negative = true}), 500), -0.1);
}

TEST(SpectrumCsv, EmptyAndHeaderOnlyFilesAreErrors) {
  EXPECT_NE(load_error("empty", "").find("empty"), std::string::npos);
  EXPECT_NE(load_error("comments_only", "# nothing\n\n").find("empty"), std::string::npos);
  EXPECT_NE(load_error("header_only", "wavelength_nm,v\n").find("no data"), std::string::npos);
}

TEST(SpectrumCsv, StructuralErrors) {
  EXPECT_NE(load_error("noheader", "400,1\n500,2\n").find("header"), std::string::npos);
  EXPECT_NE(load_error("wrongfirst", "nm,v\n400,1\n").find("wavelength_nm"), std::string::npos);
  EXPECT_NE(load_error("cells", "wavelength_nm,v\n400,1,2\n").find("line 2"), std::string::npos);
  EXPECT_NE(load_error("text", "wavelength_nm,v\n400,abc\n").find("'abc' is not a number"), std::string::npos);
  EXPECT_NE(load_error("threecol", "wavelength_nm,a,b\n400,1,2\n").find("two columns"), std::string::npos);
  EXPECT_NE(load_error("zero_nm", "wavelength_nm,v\n0,1\n").find("positive"), std::string::npos);
}

TEST(SpectrumCsv, MissingFileIsAnError) {
  try {
    load_spectrum_csv("/nonexistent/spectrum.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/spectrum.csv: file not found"), std::string::npos);
  }
}

}  // namespace
}  // namespace bouguer
