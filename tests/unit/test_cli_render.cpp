// bouguer render and bouguer compare, run as a user runs them.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "bouguer/io/image_io.h"
#include "bouguer/render/spectral_sampling.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

const std::string kExample = (fs::path(BOUGUER_SOURCE_DIR) / "scenes" / "examples" / "issue3.json").string();

TEST(CliRender, ThreadsOneAndTwoGiveBitIdenticalImages) {
  const auto dir = test::scratch_dir("cli_threads");
  for (const char* threads : {"1", "2"}) {
    const auto r = test::run_bouguer({"render", kExample, "--resolution", "80x60", "--spp", "4", "--threads", threads,
                                      "-o", (dir / (std::string(threads) + ".pfm")).string(), "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.out.empty());  // --quiet
  }
  EXPECT_EQ(test::read_file(dir / "1.pfm"), test::read_file(dir / "2.pfm"));
}

TEST(CliRender, StatsJsonSpectralExrAndSummaryLine) {
  const auto dir = test::scratch_dir("cli_stats");
  const auto r = test::run_bouguer({"render", kExample, "--resolution", "40x30", "--spp", "2", "-o",
                                    (dir / "a.exr").string(), "--spectral-exr", (dir / "s.exr").string(),
                                    "--stats-json", (dir / "stats.json").string()});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("40x30, 2 spp"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rays/s"), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(test::read_file(dir / "stats.json"));
  for (const char* key : {"seconds", "rays", "rays_per_second", "spp", "resolution"}) EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_EQ(j["resolution"][0], 40);
  EXPECT_GT(j["rays"].get<double>(), 40.0 * 30 * 2);
  const Film spectral = read_exr(dir / "s.exr");
  EXPECT_EQ(spectral.wavelengths_nm.size(), kFullBins);
  EXPECT_EQ(spectral.rgb, read_exr(dir / "a.exr").rgb);
  // rgb3 carries no spectrum to write.
  const auto bad = test::run_bouguer({"render", kExample, "--resolution", "8x8", "--spectral", "rgb3",
                                      "--spectral-exr", (dir / "t.exr").string(), "-o", (dir / "t.png").string()});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_FALSE(fs::exists(dir / "t.png"));
}

TEST(CliCompare, ZeroForIdenticalImagesAndPositiveForTheRgbApproach) {
  const auto dir = test::scratch_dir("cli_compare");
  for (const char* mode : {"full", "rgb3"})
    ASSERT_EQ(test::run_bouguer({"render", kExample, "--resolution", "60x45", "--spp", "1", "--spectral", mode, "-o",
                                 (dir / (std::string(mode) + ".exr")).string(), "--quiet"})
                  .exit_code,
              0);
  const auto same = test::run_bouguer({"compare", (dir / "full.exr").string(), (dir / "full.exr").string(), "--json"});
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(nlohmann::json::parse(same.out)["max"].get<double>(), 0.0);
  const auto diff = test::run_bouguer({"compare", (dir / "full.exr").string(), (dir / "rgb3.exr").string(), "--json",
                                       "--heatmap", (dir / "heat.png").string(), "--montage",
                                       (dir / "pair.png").string()});
  ASSERT_EQ(diff.exit_code, 0) << diff.err;
  const auto j = nlohmann::json::parse(diff.out);
  for (const char* key : {"mean", "median", "p95", "max", "rmse"}) EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_GT(j["max"].get<double>(), 1.0);
  EXPECT_LE(j["median"].get<double>(), j["p95"].get<double>());
  EXPECT_TRUE(fs::exists(dir / "heat.png"));
  EXPECT_TRUE(fs::exists(dir / "pair.png"));
  // Different sizes: one line, exit 1.
  ASSERT_EQ(test::run_bouguer({"render", kExample, "--resolution", "30x20", "--spp", "1", "-o",
                               (dir / "small.exr").string(), "--quiet"})
                .exit_code,
            0);
  const auto sizes = test::run_bouguer({"compare", (dir / "full.exr").string(), (dir / "small.exr").string()});
  EXPECT_EQ(sizes.exit_code, 1);
  EXPECT_EQ(test::line_count(sizes.err), 1) << sizes.err;
  // A heat-map scale of NaN is a usage error, not a black heat map.
  const auto nan = test::run_bouguer(
      {"compare", (dir / "full.exr").string(), (dir / "full.exr").string(), "--heatmap-max", "nan"});
  EXPECT_EQ(nan.exit_code, 2);
  EXPECT_EQ(test::line_count(nan.err), 1) << nan.err;
}

TEST(CliRender, BadOverridesAreRefused) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"render", kExample, "--resolution", "80by60"},
        {"render", kExample, "--resolution", "80x0"}, {"render", kExample, "--resolution", "80x60x2"},
        {"render", kExample, "--spectral", "rgb"}, {"render", kExample, "--integrator", "bidirectional"},
        {"render", kExample, "--threads", "-1"}}) {
    const auto r = test::run_bouguer(args);
    EXPECT_NE(r.exit_code, 0) << args[2];
    EXPECT_EQ(test::line_count(r.err), 1) << args[2] << ": " << r.err;
  }
}

}  // namespace
}  // namespace bouguer
