#pragma once
// One function per file reader, shared by the libFuzzer harnesses (harness.cpp, built with
// -DBOUGUER_FUZZ=ON) and the corpus replay in the ordinary test suite (unit/test_fuzz_corpus.cpp),
// so both call the same code. Each writes the bytes to a file in `dir`, reads it through the
// public reader functions and checks what the reader accepted (every number finite). Bad input
// ends in bouguer::Error, which the caller expects; a violated check throws std::logic_error, and
// anything but an Error is a finding.
#include <filesystem>
#include <string_view>
#include <vector>

namespace bouguer::fuzz {

using TargetFn = void (*)(std::string_view bytes, const std::filesystem::path& dir);

struct Target {
  const char* name;  // the harness (fuzz_<name>) and its corpus folder (tests/fuzz/corpus/<name>)
  TargetFn run;
};

const std::vector<Target>& targets();
const Target* find_target(std::string_view name);

// OBJ inputs carry their MTL file after this line; the OBJ names it `mtllib input.mtl`.
inline constexpr std::string_view kMtlSeparator = "\n#--- input.mtl ---\n";

}  // namespace bouguer::fuzz
