#pragma once
// Helpers shared by the tests: scratch folders, running the bouguer binary.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace bouguer::test {

// A fresh, empty folder under the build tree for one test.
std::filesystem::path scratch_dir(const std::string& test_name);

void write_file(const std::filesystem::path& path, const std::string& text);
std::string read_file(const std::filesystem::path& path);

struct RunResult {
  int exit_code = -1;
  std::string out, err;
};

// Runs build/bouguer with the given arguments (each shell-quoted), capturing stdout and stderr.
RunResult run_bouguer(const std::vector<std::string>& args);
// The same for any program (found on PATH when the name has no slash).
RunResult run_program(const std::string& program, const std::vector<std::string>& args);

// Runs `body` in a child process whose address space may grow by at most budget_bytes beyond what
// it had at the fork (RLIMIT_AS, like `ulimit -v`). `outcome` says how it ended: "ok" (it
// returned), "error: <message>" (a bouguer::Error), or what else happened (another exception,
// std::bad_alloc, a signal).
std::string run_with_memory_budget(const std::function<void()>& body, std::size_t budget_bytes);

// Number of lines in text (a trailing newline does not start a new line).
int line_count(const std::string& text);

// A reference table inside the repository, tests/data/<relative> (see tests/data/README.md).
std::filesystem::path test_data(const std::string& relative);

}  // namespace bouguer::test

#include "bouguer/scene/description.h"
#include "bouguer/render/film.h"

namespace bouguer::test {

// Compiles the description and renders it with its own settings on `threads` threads (0: all).
Film render_desc(const SceneDesc& desc, int threads = 0);
// Renders of one scene with the seeds first_seed, first_seed + 1, ... (`seeds` of them), each at
// desc.render's spp, the scene compiled once.
std::vector<Film> render_seeds(const SceneDesc& desc, int seeds, std::uint64_t first_seed, int threads = 0);
// The same from scene-file text.
Film render_text(const std::string& json, int threads = 0);

// The largest relative difference of `a` from `reference` over every pixel and channel (the
// furnaces' measure: a ball's image against the sky's alone).
double largest_relative_difference(const Film& a, const Film& reference);

// The measure of chromatic noise of #4: the spread (standard deviation, x and y combined) of the
// chromaticity over the pixels whose r + g + b is at least 0.05 (light reflected away has no colour
// to measure); `lit` receives how many pixels that is.
double chromaticity_spread(const Film& film, int& lit);

}  // namespace bouguer::test
