// The layout check of OpenVDB files before OpenVDB reads them (io/vdb_layout.h, #36): a chunk
// size, a string length or a grid position that the file cannot hold is refused in one line
// naming the file and the byte, before OpenVDB allocates what it states. Without the check the
// first file below makes OpenVDB ask for 140 TB (ASan stops in bloscFromStream).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "bouguer/io/vdb.h"
#include "support/test_support.h"
#include "support/vdb_files.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

const fs::path kVdbCorpus = fs::path(BOUGUER_SOURCE_DIR) / "tests" / "fuzz" / "corpus" / "vdb";

// The message read_vdb_grid refuses `file` with (empty when it reads it).
std::string refusal(const fs::path& file) {
  try {
    (void)read_vdb_grid(file, "density");
  } catch (const VdbError& e) {
    return e.what();
  }
  return "";
}

void expect_one_line_naming(const std::string& message, const fs::path& file, const std::string& problem) {
  EXPECT_NE(message.find(file.string()), std::string::npos) << message;
  EXPECT_NE(message.find(problem), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

// cube_2.vdb with the size of its last blosc chunk (byte 10038) set to 2^47.
TEST(VdbLayout, RefusesABloscChunkLargerThanTheFile) {
  const fs::path file = kVdbCorpus / "blosc_size_140TB.vdb";
  expect_one_line_naming(refusal(file), file, "a blosc chunk at byte 10046 needs 140737488355328 bytes, but 48 remain");
  EXPECT_EQ(refusal(kVdbCorpus / "cube_2.vdb"), "");  // the file it was made from reads
}

// The fuzzer's finding: cube_2.vdb cut in half, whose descriptor places the grid past the end.
TEST(VdbLayout, RefusesAGridPastTheEndOfTheFile) {
  const fs::path file = kVdbCorpus / "found_huge_blosc_size.vdb";
  expect_one_line_naming(refusal(file), file, "places its grid at bytes 124, 9973, 10094 in a file of 5047");
}

// The fuzzer's second finding: cube_2.vdb whose grid says zip where its chunks are blosc. OpenVDB
// throws inside a root child's topology and never frees the child (270 KB leaked per read, which
// LeakSanitizer stops on); the check decompresses topology chunks first and refuses it.
TEST(VdbLayout, RefusesATopologyChunkThatDoesNotDecompress) {
  const fs::path file = kVdbCorpus / "found_zip_flag_on_blosc_chunks.vdb";
  expect_one_line_naming(refusal(file), file, "the zip chunk at byte 8836 does not decompress to the 131072 bytes");
}

// A grid instance (a second grid sharing the first one's tree) is what OpenVDB writes by default
// for grids that share a tree; its descriptor leaves the block position at 0. Both grids read.
TEST(VdbLayout, ReadsAGridInstance) {
  const fs::path file = test::scratch_dir("vdb_layout_instance") / "instance.vdb";
  test::write_vdb_file_with_instance(file, test::VdbTestGrid{}, "copy");
  auto names = vdb_grid_names(file);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"copy", "density"}));
  EXPECT_EQ(refusal(file), "");
  EXPECT_NO_THROW((void)read_vdb_grid(file, "copy"));
}

// A file cut at any length is refused with one line (a file whose data OpenVDB would read past
// its end reads garbage sizes: the 140 TB request came from there).
TEST(VdbLayout, RefusesEveryTruncationInOneLine) {
  const fs::path dir = test::scratch_dir("vdb_layout_truncated");
  test::VdbTestGrid g;
  g.count = {9, 9, 9};  // two leaves along each axis: several chunks
  const fs::path whole = dir / "whole.vdb";
  test::write_vdb_file(whole, {g});
  ASSERT_EQ(refusal(whole), "");
  const std::string bytes = test::read_file(whole);
  for (std::size_t length = 8; length < bytes.size(); length += 61) {
    const fs::path cut = dir / "cut.vdb";
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(length));
    const std::string message = refusal(cut);
    EXPECT_NE(message, "") << "cut at " << length;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace bouguer
