// The bouguer command, run as a user runs it.
#include <gtest/gtest.h>

#include <filesystem>

#include <nlohmann/json.hpp>

#include "support/test_support.h"

namespace bouguer {
namespace {

using test::run_bouguer;

TEST(Cli, VersionAndHelp) {
  const auto v = run_bouguer({"--version"});
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_NE(v.out.find("bouguer "), std::string::npos);
  const auto h = run_bouguer({"color", "--help"});
  EXPECT_EQ(h.exit_code, 0);
  EXPECT_NE(h.out.find("--observer"), std::string::npos);
}

// OpenImageIO (and the 260 libraries it needs), OpenVDB and Open MPI are modules loaded on first use
// (io/texture_module.h, io/vdb_module.h, distributed/mpi_module.h): the program itself starts
// without them. ld.so lists what it would load and exits (LD_TRACE_LOADED_OBJECTS, as ldd does).
TEST(Cli, StartsWithoutTheLibrariesItLoadsOnFirstUse) {
  const auto r = test::run_program("/usr/bin/env", {"LD_TRACE_LOADED_OBJECTS=1", BOUGUER_EXE});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("libc.so"), std::string::npos) << r.out;
  for (const char* library : {"libOpenImageIO", "libopenvdb", "libmpi"})
    EXPECT_EQ(r.out.find(library), std::string::npos) << library << " is linked into the program";
  // Nor into this test program, whose ~490 processes in the suite would each pay OpenVDB's
  // relocations at their start (support/vdb_files.h).
  const std::string self = std::filesystem::read_symlink("/proc/self/exe").string();
  const auto t = test::run_program("/usr/bin/env", {"LD_TRACE_LOADED_OBJECTS=1", self});
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_NE(t.out.find("libc.so"), std::string::npos) << t.out;
  EXPECT_EQ(t.out.find("libopenvdb"), std::string::npos) << "libopenvdb is linked into the tests";
}

TEST(Cli, ColorJsonForD65) {
  const auto r = run_bouguer({"color", "D65", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  for (const char* key : {"XYZ", "xy", "linear_srgb", "srgb_hex", "lab"}) EXPECT_TRUE(j.contains(key)) << key;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(j["linear_srgb"][i].get<double>(), 1.0, 0.002);
  EXPECT_NEAR(j["xy"][0].get<double>(), 0.3127, 0.0002);
  EXPECT_NEAR(j["xy"][1].get<double>(), 0.3290, 0.0002);
  EXPECT_EQ(j["srgb_hex"], "#FFFFFF");
  EXPECT_NEAR(j["lab"][0].get<double>(), 100.0, 1e-9);
}

TEST(Cli, ColorScaleAndObserver) {
  const auto r = run_bouguer({"color", "A", "--scale", "0.25", "--observer", "1964", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_NEAR(j["xy"][0].get<double>(), 0.4512, 0.0002);  // A, 10° observer (CIE 015:2018 Table 1)
  EXPECT_NEAR(j["xy"][1].get<double>(), 0.4059, 0.0002);
}

TEST(Cli, ColorOfACsvSpectrum) {
  const auto dir = test::scratch_dir("cli_csv");
  test::write_file(dir / "flat.csv", "wavelength_nm,radiance\n300,2\n900,2\n");
  const auto r = run_bouguer({"color", (dir / "flat.csv").string(), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NEAR(nlohmann::json::parse(r.out)["XYZ"][1].get<double>(), 2.0, 1e-9);  // taken in its own units
  const auto n = run_bouguer({"color", (dir / "flat.csv").string(), "--normalise", "--scale", "0.5", "--json"});
  EXPECT_NEAR(nlohmann::json::parse(n.out)["XYZ"][1].get<double>(), 0.5, 1e-9);
}

// Bad command lines: exit 2, one line on stderr, nothing on stdout.
TEST(Cli, BadValuesGiveOneLineAndExitCode2) {
  const std::vector<std::vector<std::string>> cases = {
      {"color", "D65", "--scale", "-1"}, {"color", "D65", "--scale", "abc"}, {"color", "D65", "--scale", "inf"},
      {"color", "D65", "--observer", "1950"}, {"color", "D65", "--frobnicate"}, {"color"}, {"colr", "D65"}, {}};
  for (const auto& args : cases) {
    const auto r = run_bouguer(args);
    const std::string shown = args.empty() ? "(no arguments)" : args.back();
    EXPECT_EQ(r.exit_code, 2) << shown;
    EXPECT_EQ(test::line_count(r.err), 1) << shown << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << shown;
  }
  EXPECT_NE(run_bouguer({"colr", "D65"}).err.find("did you mean 'color'"), std::string::npos);
}

// Bad input files: exit 1, one line naming the file and the line.
TEST(Cli, MalformedSpectrumGivesOneLine) {
  const auto dir = test::scratch_dir("cli_bad_csv");
  const struct {
    const char* name;
    std::string text;
  } cases[] = {{"nonmono.csv", "wavelength_nm,v\n500,1\n400,1\n"},
               {"nan.csv", "wavelength_nm,v\n400,nan\n"},
               {"neg.csv", "wavelength_nm,v\n400,-1\n"},
               {"empty.csv", ""},
               {"binary.csv", std::string("\x89PNG\r\n\x1a\n\0\0", 10)}};
  for (const auto& c : cases) {
    test::write_file(dir / c.name, c.text);
    const auto r = run_bouguer({"color", (dir / c.name).string()});
    EXPECT_EQ(r.exit_code, 1) << c.name;
    EXPECT_EQ(test::line_count(r.err), 1) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.name), std::string::npos) << r.err;
  }
  const auto missing = run_bouguer({"color", (dir / "absent.csv").string()});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_EQ(test::line_count(missing.err), 1);
}

}  // namespace
}  // namespace bouguer
