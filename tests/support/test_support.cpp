#include "support/test_support.h"

#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <new>
#include <sstream>

#include "bouguer/core/error.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"

namespace bouguer::test {
namespace fs = std::filesystem;

fs::path scratch_dir(const std::string& test_name) {
  // BOUGUER_TEST_SCRATCH moves every test's files elsewhere (scripts/validate-gltf.sh keeps the
  // assets the tests write apart from a concurrent run's).
  const char* root = std::getenv("BOUGUER_TEST_SCRATCH");
  const fs::path dir = fs::path(root && *root ? root : BOUGUER_TEST_TMP) / test_name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string read_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

namespace {
std::string shell_quote(const std::string& s) {
  std::string q(1, '\'');
  for (char c : s) {
    if (c == '\'') q.append("'\\''");
    else q.push_back(c);
  }
  q.push_back('\'');
  return q;
}
}  // namespace

RunResult run_bouguer(const std::vector<std::string>& args) { return run_program(BOUGUER_EXE, args); }

RunResult run_program(const std::string& program, const std::vector<std::string>& args) {
  static int counter = 0;
  const fs::path dir = fs::path(BOUGUER_TEST_TMP) / "run";
  fs::create_directories(dir);
  const std::string stem = fmt::format("{}/{}_{}", dir.string(), ::getpid(), counter++);
  std::string cmd = shell_quote(program);
  for (const auto& a : args) {
    cmd.push_back(' ');
    cmd.append(shell_quote(a));
  }
  cmd += fmt::format(" >{} 2>{} </dev/null", shell_quote(stem + ".out"), shell_quote(stem + ".err"));
  const int status = std::system(cmd.c_str());
  RunResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  r.out = read_file(stem + ".out");
  r.err = read_file(stem + ".err");
  return r;
}

std::string run_with_memory_budget(const std::function<void()>& body, std::size_t budget_bytes) {
  int pipe_fds[2];
  if (::pipe(pipe_fds) != 0) return "pipe failed";
  const pid_t pid = ::fork();
  if (pid < 0) return "fork failed";
  if (pid == 0) {
    ::close(pipe_fds[0]);
    std::string outcome;
    std::size_t pages = 0;
    std::ifstream("/proc/self/statm") >> pages;  // the address space now, in pages
    const rlim_t limit = pages * static_cast<rlim_t>(::sysconf(_SC_PAGESIZE)) + budget_bytes;
    const rlimit rl{limit, limit};
    if (pages == 0 || ::setrlimit(RLIMIT_AS, &rl) != 0) {
      outcome = "cannot limit the address space";
    } else {
      try {
        body();
        outcome = "ok";
      } catch (const Error& e) {
        outcome = std::string("error: ") + e.what();
      } catch (const std::bad_alloc&) {
        outcome = "std::bad_alloc: more memory than the budget";
      } catch (const std::exception& e) {
        outcome = std::string("exception: ") + e.what();
      }
    }
    const ssize_t written = ::write(pipe_fds[1], outcome.data(), outcome.size());
    ::_exit(written == static_cast<ssize_t>(outcome.size()) ? 0 : 1);
  }
  ::close(pipe_fds[1]);
  std::string outcome;
  char buffer[4096];
  for (ssize_t n; (n = ::read(pipe_fds[0], buffer, sizeof buffer)) > 0;) outcome.append(buffer, static_cast<std::size_t>(n));
  ::close(pipe_fds[0]);
  int status = 0;
  ::waitpid(pid, &status, 0);
  if (WIFSIGNALED(status)) return fmt::format("killed by signal {} (after: '{}')", WTERMSIG(status), outcome);
  if (WEXITSTATUS(status) != 0) return fmt::format("exited with code {} (after: '{}')", WEXITSTATUS(status), outcome);
  return outcome;
}

int line_count(const std::string& text) {
  if (text.empty()) return 0;
  const auto n = static_cast<int>(std::count(text.begin(), text.end(), '\n'));
  return text.back() == '\n' ? n : n + 1;
}

Film render_desc(const SceneDesc& desc, int threads) {
  RenderControl control;
  control.threads = threads;
  RenderStats stats;
  return render(compile(desc), desc.render, control, stats);
}

std::vector<Film> render_seeds(const SceneDesc& desc, int seeds, std::uint64_t first_seed, int threads) {
  const RenderScene scene = compile(desc);
  RenderControl control;
  control.threads = threads;
  RenderSettings settings = desc.render;
  std::vector<Film> films;
  for (int k = 0; k < seeds; ++k) {
    settings.seed = first_seed + static_cast<std::uint64_t>(k);
    RenderStats stats;
    films.push_back(render(scene, settings, control, stats));
  }
  return films;
}

Film render_text(const std::string& json, int threads) { return render_desc(parse_scene(json, "test.json"), threads); }

double largest_relative_difference(const Film& a, const Film& reference) {
  double worst = 0.0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const double v = a.rgb_at(x, y)[c], r = reference.rgb_at(x, y)[c];
        worst = std::max(worst, std::abs(v - r) / r);
      }
  return worst;
}

fs::path test_data(const std::string& relative) { return fs::path(BOUGUER_SOURCE_DIR) / "tests" / "data" / relative; }

double chromaticity_spread(const Film& f, int& lit) {
  double sx = 0, sy = 0, sxx = 0, syy = 0;
  lit = 0;
  for (int y = 0; y < f.height; ++y)
    for (int x = 0; x < f.width; ++x) {
      const Vec3f c = f.rgb_at(x, y);
      const double sum = c.x + c.y + c.z;
      if (sum < 0.05) continue;
      const double cx = c.x / sum, cy = c.y / sum;
      sx += cx, sy += cy, sxx += cx * cx, syy += cy * cy, ++lit;
    }
  if (lit == 0) return 0.0;
  const double n = lit;
  return std::sqrt(std::max(0.0, sxx / n - sx * sx / n / n) + std::max(0.0, syy / n - sy * sy / n / n));
}

}  // namespace bouguer::test
