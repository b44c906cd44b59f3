// mpirun -np N bouguer render, as a user runs it (docs/distributed.md): the one-process image bit
// for bit, and a rank that fails stops the job and leaves an earlier output as it was. CI runs as
// root (--allow-run-as-root) on 2 cores (--oversubscribe); --bind-to none lets every rank's
// threads use every core; --timeout stops a job that hangs.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <stdlib.h>

#include <stdexcept>
#include <system_error>

#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

const std::string kExample = (fs::path(BOUGUER_SOURCE_DIR) / "scenes" / "examples" / "issue3.json").string();
constexpr std::string_view kMpiexec = BOUGUER_MPIEXEC;  // empty when the build has no MPI

#define SKIP_WITHOUT_MPI()                                                                                  \
  if (kMpiexec.empty()) {                                                                                   \
    GTEST_SKIP() << "this build has no MPI (install libopenmpi-dev and openmpi-bin, then configure again)"; \
  }

// The shared-memory transport copies instead of reading the other process's memory (CMA), which
// containers often forbid (ptrace rules); it makes no difference to the image.
// clang-format off
const std::vector<std::string> kMpirunOptions = {"--allow-run-as-root", "--oversubscribe", "--bind-to", "none",
                                                 "--timeout", "60", "--mca", "btl_vader_single_copy_mechanism", "none"};
// clang-format on

// One rank's command line: `render SCENE -o OUT` and the integrator's settings.
std::vector<std::string> render_args(const std::string& scene, const fs::path& out, const std::string& integrator,
                                     const std::vector<std::string>& extra = {}, const char* spp = "4") {
  std::vector<std::string> args = {BOUGUER_EXE, "render",    scene, "--integrator", integrator, "--resolution",
                                   "40x30",     "--spp",     spp,   "--threads",    "1",        "--quiet",
                                   "-o",        out.string()};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

// mpirun with one command line per group of ranks: {{ranks, args}, ...} joined by ':'. Each job
// keeps its session directory in a folder of its own (orte_tmpdir_base): ctest runs two of these
// tests at once, and Open MPI 4's jobs share /tmp/ompi.<host>.<uid>, which one job's cleanup can
// remove while the other creates its own inside it ("A call to mkdir was unable to create the
// desired directory", open-mpi/ompi#8510; a fresh clone's `make test` failed so). Under /tmp, short:
// the folder also holds PMIx's socket, whose path has a length limit.
test::RunResult mpirun(const std::vector<std::pair<int, std::vector<std::string>>>& groups) {
  std::string base = (fs::temp_directory_path() / "bouguer-ompi-XXXXXX").string();
  if (!mkdtemp(base.data())) throw std::runtime_error("mkdtemp failed for " + base);
  std::vector<std::string> args = kMpirunOptions;
  args.insert(args.end(), {"--mca", "orte_tmpdir_base", base});
  for (std::size_t i = 0; i < groups.size(); ++i) {
    if (i > 0) args.push_back(":");
    args.insert(args.end(), {"-np", std::to_string(groups[i].first)});
    args.insert(args.end(), groups[i].second.begin(), groups[i].second.end());
  }
  test::RunResult r = test::run_program(std::string(kMpiexec), args);
  std::error_code ignored;
  fs::remove_all(base, ignored);
  return r;
}

class MpiRender : public ::testing::TestWithParam<std::tuple<const char*, int>> {};

TEST_P(MpiRender, GivesTheOneProcessImageBitForBit) {
  SKIP_WITHOUT_MPI();
  const auto [integrator, ranks] = GetParam();
  const auto dir = test::scratch_dir(fmt::format("mpi_{}_{}", integrator, ranks));
  // Spectra travel too: the path tracer's run also writes the spectral EXR.
  auto spectral = [&](const char* name) {
    return std::string(integrator) == "path" ? std::vector<std::string>{"--spectral-exr", (dir / name).string()}
                                             : std::vector<std::string>{};
  };
  auto one = render_args(kExample, dir / "one.exr", integrator, spectral("one_spectra.exr"));
  const auto single = test::run_program(one[0], {one.begin() + 1, one.end()});
  ASSERT_EQ(single.exit_code, 0) << single.err;
  const auto r = mpirun({{ranks, render_args(kExample, dir / "mpi.exr", integrator, spectral("mpi_spectra.exr"))}});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string image = test::read_file(dir / "one.exr");
  ASSERT_GT(image.size(), 1000u);
  EXPECT_TRUE(image == test::read_file(dir / "mpi.exr"));
  if (std::string(integrator) == "path") {
    EXPECT_TRUE(test::read_file(dir / "one_spectra.exr") == test::read_file(dir / "mpi_spectra.exr"));
  }
  EXPECT_EQ(test::line_count(r.out), 0) << r.out;  // --quiet on every rank
}

INSTANTIATE_TEST_SUITE_P(Cli, MpiRender,
                         ::testing::Combine(::testing::Values("whitted", "path", "light", "bdpt", "vcm"), ::testing::Values(2, 3)),
                         [](const auto& p) {
                           return fmt::format("{}_{}ranks", std::get<0>(p.param), std::get<1>(p.param));
                         });

// Path guiding: every rank trains the same guide before rendering its pieces (integrators/guiding.h),
// so the guided image is the one-process one bit for bit; and it is not the unguided one (the guide
// drew).
TEST(CliMpi, AGuidedRenderIsTheOneProcessImageBitForBit) {
  SKIP_WITHOUT_MPI();
  const auto dir = test::scratch_dir("mpi_guided");
  // (a red glass ball on a diffuse floor under a small lamp: the floor is guided)
  const std::string scene = test::test_data("red_ball_lamp/scene.json").string();
  auto one = render_args(scene, dir / "one.exr", "path", {"--guiding", "on"}, "8");
  const auto single = test::run_program(one[0], {one.begin() + 1, one.end()});
  ASSERT_EQ(single.exit_code, 0) << single.err;
  auto plain = render_args(scene, dir / "plain.exr", "path", {"--guiding", "off"}, "8");
  ASSERT_EQ(test::run_program(plain[0], {plain.begin() + 1, plain.end()}).exit_code, 0);
  const auto r = mpirun({{2, render_args(scene, dir / "mpi.exr", "path", {"--guiding", "on"}, "8")}});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string image = test::read_file(dir / "one.exr");
  ASSERT_GT(image.size(), 1000u);
  EXPECT_TRUE(image == test::read_file(dir / "mpi.exr"));
  EXPECT_FALSE(image == test::read_file(dir / "plain.exr"));
}

// Shell transport (integrators/shell_hops.h): the tables come from the seed and the sample index
// alone (each rank makes them once for all its pieces, which this cannot tell from each piece
// making its own), so the image is the one-process one bit for bit; and it is not the image
// without it (spheres were taken: the whole-milk ball of 1.5 mm holds them).
TEST(CliMpi, AShellTransportRenderIsTheOneProcessImageBitForBit) {
  SKIP_WITHOUT_MPI();
  const auto dir = test::scratch_dir("mpi_shells");
  nlohmann::json scene = nlohmann::json::parse(test::read_file(test::test_data("whole_milk_ball/scene.json")));
  scene["background"]["environment"] = test::test_data("whole_milk_ball/sky.pfm").string();
  test::write_file(dir / "on.json", scene.dump());
  scene["render"]["shell_transport"] = false;
  test::write_file(dir / "off.json", scene.dump());
  auto one = render_args((dir / "on.json").string(), dir / "one.exr", "path", {}, "8");
  const auto single = test::run_program(one[0], {one.begin() + 1, one.end()});
  ASSERT_EQ(single.exit_code, 0) << single.err;
  auto plain = render_args((dir / "off.json").string(), dir / "plain.exr", "path", {}, "8");
  ASSERT_EQ(test::run_program(plain[0], {plain.begin() + 1, plain.end()}).exit_code, 0);
  const auto r = mpirun({{2, render_args((dir / "on.json").string(), dir / "mpi.exr", "path", {}, "8")}});
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  const std::string image = test::read_file(dir / "one.exr");
  ASSERT_GT(image.size(), 1000u);
  EXPECT_TRUE(image == test::read_file(dir / "mpi.exr"));
  EXPECT_FALSE(image == test::read_file(dir / "plain.exr"));
}

// A rank that exits early (its scene is not there) or renders another job (other options) stops
// the whole job with a message; the output written before stays as it was.
TEST(CliMpi, ARankThatFailsStopsTheJobAndKeepsTheEarlierOutput) {
  SKIP_WITHOUT_MPI();
  const auto dir = test::scratch_dir("mpi_failure");
  const fs::path out = dir / "out.exr";
  test::write_file(out, "the earlier output");
  const auto missing =
      mpirun({{2, render_args(kExample, out, "path")}, {1, render_args((dir / "missing.json").string(), out, "path")}});
  EXPECT_NE(missing.exit_code, 0);
  EXPECT_NE(missing.err.find("missing.json"), std::string::npos) << missing.err;
  EXPECT_EQ(test::read_file(out), "the earlier output");
  const auto other =
      mpirun({{1, render_args(kExample, out, "light")}, {1, render_args(kExample, out, "light", {}, "3")}});
  EXPECT_NE(other.exit_code, 0);
  EXPECT_NE(other.err.find("bouguer: error: rank 0 of 2: rank 1 renders another job than rank 0 (spp 3 against 4)"),
            std::string::npos)
      << other.err;
  EXPECT_EQ(test::read_file(out), "the earlier output");
  const auto timed = mpirun({{2, render_args(kExample, out, "path", {"--time", "1"})}});
  EXPECT_NE(timed.exit_code, 0);
  EXPECT_NE(timed.err.find("--time: not under mpirun"), std::string::npos) << timed.err;
  EXPECT_EQ(test::read_file(out), "the earlier output");
}

}  // namespace
}  // namespace bouguer
