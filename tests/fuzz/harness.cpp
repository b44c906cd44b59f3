// The libFuzzer entry point for one reader: built once per target in targets.cpp as
// fuzz_<name>, with BOUGUER_FUZZ_TARGET naming it (tests/fuzz/CMakeLists.txt). The environment
// variable BOUGUER_FUZZ_TARGET picks another target, so one binary can be carried to another
// machine for all (FUZZ_BIN and FUZZ_NO_BUILD in scripts/fuzz-lib.sh and fuzz-long.sh). A
// bouguer::Error is the expected answer to bad input; anything else escapes and is a crash.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "bouguer/core/error.h"
#include "fuzz/targets.h"

namespace {
const bouguer::fuzz::Target* target = nullptr;
std::filesystem::path dir;
}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* chosen = std::getenv("BOUGUER_FUZZ_TARGET");
  const char* name = chosen && *chosen ? chosen : BOUGUER_FUZZ_TARGET;
  target = bouguer::fuzz::find_target(name);
  if (!target) {
    std::fprintf(stderr, "fuzz: unknown target '%s'\n", name);
    std::abort();
  }
  std::string pattern = (std::filesystem::temp_directory_path() / "bouguer-fuzz-XXXXXX").string();
  if (!mkdtemp(pattern.data())) std::abort();
  dir = pattern;
  std::atexit([] {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    target->run(std::string_view(reinterpret_cast<const char*>(data), size), dir);
  } catch (const bouguer::Error&) {
  }
  return 0;
}
