#include "support/test_support.h"

#include <fmt/format.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "bouguer/render/render.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"

namespace bouguer::test {
namespace fs = std::filesystem;

fs::path scratch_dir(const std::string& test_name) {
  const fs::path dir = fs::path(BOUGUER_TEST_TMP) / test_name;
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

RunResult run_bouguer(const std::vector<std::string>& args) {
  static int counter = 0;
  const fs::path dir = fs::path(BOUGUER_TEST_TMP) / "run";
  fs::create_directories(dir);
  const std::string stem = fmt::format("{}/{}_{}", dir.string(), ::getpid(), counter++);
  std::string cmd = shell_quote(BOUGUER_EXE);
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

Film render_text(const std::string& json, int threads) { return render_desc(parse_scene(json, "test.json"), threads); }

fs::path test_data(const std::string& relative) { return fs::path(BOUGUER_SOURCE_DIR) / "tests" / "data" / relative; }

}  // namespace bouguer::test
