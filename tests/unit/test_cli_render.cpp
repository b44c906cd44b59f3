// bouguer render and bouguer compare, run as a user runs them.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "bouguer/io/image_io.h"
#include "bouguer/spectra/spectral_sampling.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

const std::string kExample = (fs::path(BOUGUER_SOURCE_DIR) / "scenes" / "examples" / "issue3.json").string();

// Settings at which the example takes several seconds to render (on one thread, without --quiet:
// the first progress line comes at 0 %). An output the run cannot write must be refused first.
std::vector<std::string> slow_render(const std::vector<std::string>& outputs) {
  std::vector<std::string> args = {"render", kExample, "--resolution", "400x300", "--spp", "64", "--threads", "1"};
  args.insert(args.end(), outputs.begin(), outputs.end());
  return args;
}

struct TimedRun {
  test::RunResult result;
  double seconds = 0.0;
};

TimedRun timed_run(const std::vector<std::string>& args) {
  const auto start = std::chrono::steady_clock::now();
  TimedRun t{test::run_bouguer(args)};
  t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return t;
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

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

// --time: whole passes within the budget, then the image; with --spp, whichever ends first.
TEST(CliRender, TimeBudgetEndsTheRenderWithTheSamplesDone) {
  const auto dir = test::scratch_dir("cli_time");
  const TimedRun timed = timed_run({"render", kExample, "--resolution", "160x120", "--time", "1.5", "--threads", "1",
                                    "-o", (dir / "t.pfm").string(), "--stats-json", (dir / "t.json").string(),
                                    "--quiet"});
  ASSERT_EQ(timed.result.exit_code, 0) << timed.result.err;
  const auto j = nlohmann::json::parse(test::read_file(dir / "t.json"));
  const int spp = j["spp"].get<int>();
  std::printf("--time 1.5: %d spp in %.2f s (the whole command)\n", spp, timed.seconds);
  EXPECT_GE(spp, 1);
  // The last pass is cut to what fits at the rate measured so far. Under load on 2 cores it can
  // still run slower than that rate (2.09 s once in a clean clone's ctest -j2, 2.65 s once in CI):
  // a pass is never cut short, so the bound is that the render stops within a few budgets, where
  // one that ignored the budget would run on for minutes (kTimedSpp samples), and that it did not
  // reach those samples.
  EXPECT_LT(j["seconds"].get<double>(), 1.5 * 4);
  EXPECT_LT(spp, 4096);
  EXPECT_TRUE(fs::exists(dir / "t.pfm"));
  // The samples end first: exactly --spp, and the image that --spp alone gives.
  const auto a = test::run_bouguer({"render", kExample, "--resolution", "40x30", "--spp", "4", "--time", "100", "-o",
                                    (dir / "a.pfm").string(), "--stats-json", (dir / "a.json").string(), "--quiet"});
  const auto b = test::run_bouguer({"render", kExample, "--resolution", "40x30", "--spp", "4", "-o",
                                    (dir / "b.pfm").string(), "--quiet"});
  ASSERT_EQ(a.exit_code, 0) << a.err;
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_EQ(nlohmann::json::parse(test::read_file(dir / "a.json"))["spp"].get<int>(), 4);
  EXPECT_EQ(test::read_file(dir / "a.pfm"), test::read_file(dir / "b.pfm"));
  EXPECT_EQ(test::run_bouguer({"render", kExample, "--time", "0", "-o", (dir / "c.pfm").string()}).exit_code, 2);
}

// Each output is checked before the scene is read: one line naming the option and the path, exit 2,
// in a fraction of a second, with no render begun.
TEST(CliRender, OutputsThatCannotBeWrittenFailBeforeRendering) {
  const auto dir = test::scratch_dir("cli_bad_outputs");
  fs::create_directories(dir / "folder.png");
  const std::string missing = (dir / "missing" / "dir").string(), d = dir.string();
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"-o", missing + "/x.png"}, "-o " + missing + "/x.png: folder '" + missing + "' does not exist"},
      {{"-o", d + "/x.jpg"}, "-o " + d + "/x.jpg: unknown file type '.jpg' (use .png, .exr or .pfm)"},
      {{"--stats-json", missing + "/s.json"}, "--stats-json " + missing + "/s.json: folder '" + missing + "' does not"},
      {{"--spectral-exr", d + "/s.png"}, "--spectral-exr " + d + "/s.png: unknown file type '.png' (use .exr)"},
      {{"-o", d + "/folder.png"}, "-o " + d + "/folder.png: it is a folder"},
      {{"-o", d + "/a.png", "-o", d + "/a.png"}, "-o " + d + "/a.png: the same file as -o " + d + "/a.png"},
  };
  for (const auto& [outputs, expected] : cases) {
    const TimedRun t = timed_run(slow_render(outputs));
    EXPECT_EQ(t.result.exit_code, 2) << expected;
    EXPECT_EQ(t.result.err.rfind("bouguer: error: ", 0), 0u) << t.result.err;
    EXPECT_NE(t.result.err.find(expected), std::string::npos) << t.result.err;
    EXPECT_EQ(test::line_count(t.result.err), 1) << t.result.err;  // no progress line: no render began
    // The render it would have begun takes over 10 s; a refusal takes a process start (0.55 s
    // in a sanitized build, 0.05 s in Release).
    EXPECT_LT(t.seconds, 2.0) << expected;
  }
  EXPECT_EQ(names_in(dir), std::vector<std::string>{"folder.png"});
}

// An earlier file at an output's path survives a run that fails on another output: a bad later -o,
// a missing --stats-json folder, or a --spectral-exr that rgb3 cannot fill. (A write that fails at
// the end, after others succeeded, is tested on OutputSet itself.)
TEST(CliRender, AFailingOutputReplacesNoEarlierFile) {
  const auto dir = test::scratch_dir("cli_keep");
  const fs::path keep_png = dir / "keep.png", keep_exr = dir / "keep.exr";
  ASSERT_EQ(test::run_bouguer({"render", kExample, "--resolution", "8x8", "--spp", "1", "-o", keep_png.string(), "-o",
                               keep_exr.string(), "--quiet"})
                .exit_code,
            0);
  const std::string png_bytes = test::read_file(keep_png), exr_bytes = test::read_file(keep_exr);
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {slow_render({"-o", keep_png.string(), "-o", (dir / "bad.jpg").string(), "-o", keep_exr.string()}),
       "-o " + (dir / "bad.jpg").string() + ": unknown file type '.jpg'"},
      {slow_render({"-o", keep_png.string(), "--stats-json", (dir / "missing" / "s.json").string()}),
       "--stats-json " + (dir / "missing" / "s.json").string() + ": folder"},
      {{"render", kExample, "--resolution", "8x8", "--spp", "1", "--spectral", "rgb3", "-o", keep_png.string(), "-o",
        (dir / "new.pfm").string(), "--spectral-exr", (dir / "s.exr").string(), "--quiet"},
       "spectral output needs --spectral full"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = test::run_bouguer(args);
    EXPECT_GT(r.exit_code, 0) << expected;
    EXPECT_LT(r.exit_code, 128) << expected;
    EXPECT_EQ(test::line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_TRUE(test::read_file(keep_png) == png_bytes) << "keep.png was replaced: " << expected;
    EXPECT_TRUE(test::read_file(keep_exr) == exr_bytes) << "keep.exr was replaced: " << expected;
    EXPECT_EQ(names_in(dir), (std::vector<std::string>{"keep.exr", "keep.png"})) << expected;  // and no temporaries
  }
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
  for (const char* key : {"mean", "median", "p95", "max", "rmse", "mean_lightness", "mean_colour"})
    EXPECT_TRUE(j.contains(key)) << key;
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

// Guiding asked of an estimator that has none (bdpt, or the one `auto` chose) renders unguided and
// says so in one line; the path tracer trains its guide and says how.
TEST(CliRender, GuidingOnAnEstimatorWithoutItWarns) {
  const auto dir = test::scratch_dir("cli_guiding");
  const auto bdpt = test::run_bouguer({"render", kExample, "--integrator", "bdpt", "--guiding", "on", "--spp", "1",
                                       "--resolution", "8x6", "--quiet", "-o", (dir / "b.png").string()});
  EXPECT_EQ(bdpt.exit_code, 0) << bdpt.err;
  EXPECT_EQ(bdpt.err, "bouguer: warning: guiding: only the path tracer is guided; bdpt renders unguided\n");
  const auto path = test::run_bouguer({"render", kExample, "--integrator", "path", "--guiding", "on", "--spp", "4",
                                       "--resolution", "8x6", "-o", (dir / "p.png").string()});
  EXPECT_EQ(path.exit_code, 0) << path.err;
  EXPECT_NE(path.err.find("guiding: 1 iteration (1 spp)"), std::string::npos) << path.err;
  EXPECT_EQ(path.err.find("warning"), std::string::npos) << path.err;
}

}  // namespace
}  // namespace bouguer

namespace bouguer {
namespace {

// Ctrl-C during a render: the first SIGINT lets the tiles in flight finish and writes the image
// so far (saying how many samples it has), exit 130; a second SIGINT exits at once. One tile of
// 16 × 16 pixels and a million samples: a second after the start the passes have grown to
// hundreds of samples, so the tile in flight takes a good fraction of a second to finish.
struct InterruptedRun {
  int exit_code = -1;
  std::string err;
  double seconds_after_signal = 0.0;
};

int read_png_size(const fs::path& png) {
  const std::string bytes = test::read_file(png);
  return bytes.size() > 24 && bytes.compare(1, 3, "PNG") == 0 ? static_cast<unsigned char>(bytes[19]) : -1;
}

InterruptedRun interrupt_render(const fs::path& dir, int signals, double gap_s = 0.02) {
  const std::string exe = BOUGUER_EXE;
  const std::string cmd = fmt::format(
      "cd '{}' && ( '{}' render '{}' --resolution 16x16 --spp 1000000 --threads 1 -o out.png 2>err.txt & pid=$!; "
      "while ! grep -q 'render:' err.txt 2>/dev/null; do sleep 0.05; done; sleep 1; {} wait $pid; "
      "echo $? > code.txt )",
      dir.string(), exe, kExample,
      signals == 1 ? std::string("kill -INT $pid;")
                   : fmt::format("kill -INT $pid; sleep {}; kill -INT $pid 2>/dev/null;", gap_s));
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(std::system(cmd.c_str()), 0);
  InterruptedRun r;
  // At least a second passes between the first progress line and the signal.
  r.seconds_after_signal = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() - 1.0;
  r.exit_code = std::stoi(test::read_file(dir / "code.txt"));
  r.err = test::read_file(dir / "err.txt");
  return r;
}

TEST(CliRender, FirstInterruptWritesTheImageSoFarSecondExitsAtOnce) {
  const fs::path once = test::scratch_dir("interrupt_once");
  const InterruptedRun first = interrupt_render(once, 1);
  EXPECT_EQ(first.exit_code, 130) << first.err;
  EXPECT_NE(first.err.find("interrupted: wrote the image after"), std::string::npos) << first.err;
  EXPECT_NE(first.err.find("of 1000000 samples per pixel"), std::string::npos) << first.err;
  ASSERT_TRUE(fs::exists(once / "out.png"));
  EXPECT_GT(read_png_size(once / "out.png"), 0);
  EXPECT_LT(first.seconds_after_signal, 5.0);

  // The second signal must arrive while the tiles in flight still run (they take tens of
  // milliseconds); when they win the race the run is the first case again, and when both signals
  // arrive before the handler runs they count as one: so try a few times, at gaps from 5 to 40 ms
  // (on a loaded machine the shell's own sleep stretches, and one gap may always lose).
  bool exited_at_once = false;
  constexpr double kGaps_s[] = {0.02, 0.005, 0.01, 0.04};
  for (int attempt = 0; attempt < 12 && !exited_at_once; ++attempt) {
    const fs::path twice = test::scratch_dir("interrupt_twice");
    const InterruptedRun second = interrupt_render(twice, 2, kGaps_s[attempt % 4]);
    EXPECT_EQ(second.exit_code, 130);
    EXPECT_LT(second.seconds_after_signal, 2.0);
    exited_at_once = !fs::exists(twice / "out.png") && second.err.find("interrupted:") == std::string::npos;
  }
  EXPECT_TRUE(exited_at_once) << "a second Ctrl-C never ended the run before the image was written";
}

}  // namespace
}  // namespace bouguer
