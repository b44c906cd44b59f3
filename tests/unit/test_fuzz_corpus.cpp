// Every file of the fuzzing corpus (tests/fuzz/corpus/<target>/: small valid files and each input
// that once crashed a reader, minimised) through the same entry points as the libFuzzer harnesses
// (tests/fuzz/targets.cpp): each is read or refused with a bouguer::Error, nothing else.
// BOUGUER_FUZZ_CORPUS_VERBOSE=1 prints each refusal.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

#include "bouguer/core/error.h"
#include "fuzz/targets.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

const fs::path kCorpus = fs::path(BOUGUER_SOURCE_DIR) / "tests" / "fuzz" / "corpus";

std::vector<std::string> target_names() {
  std::vector<std::string> names;
  for (const fuzz::Target& t : fuzz::targets()) names.emplace_back(t.name);
  return names;
}

class FuzzCorpus : public testing::TestWithParam<std::string> {};

TEST_P(FuzzCorpus, EveryInputIsReadOrRefusedWithAnError) {
  const fuzz::Target* target = fuzz::find_target(GetParam());
  ASSERT_NE(target, nullptr);
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(kCorpus / GetParam()))
    if (entry.is_regular_file()) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  const fs::path dir = test::scratch_dir("fuzz_corpus_" + GetParam());
  int read = 0, refused = 0;
  for (const fs::path& file : files) {
    try {
      target->run(test::read_file(file), dir);
      ++read;
    } catch (const Error& e) {
      ++refused;
      if (std::getenv("BOUGUER_FUZZ_CORPUS_VERBOSE")) std::printf("  %s: %s\n", file.filename().c_str(), e.what());
    } catch (const std::exception& e) {
      ADD_FAILURE() << file.filename() << ": " << e.what();
    }
  }
  std::printf("fuzz corpus %s: %d files read, %d refused with an Error\n", GetParam().c_str(), read, refused);
  EXPECT_GT(read, 0) << "no valid seed in " << (kCorpus / GetParam());
  EXPECT_GT(read + refused, 1);
}

INSTANTIATE_TEST_SUITE_P(Readers, FuzzCorpus, testing::ValuesIn(target_names()),
                         [](const testing::TestParamInfo<std::string>& p) { return p.param; });

TEST(FuzzCorpus, EveryCorpusFolderHasATarget) {
  for (const auto& entry : fs::directory_iterator(kCorpus))
    EXPECT_NE(fuzz::find_target(entry.path().filename().string()), nullptr) << entry.path();
}

}  // namespace
}  // namespace bouguer
