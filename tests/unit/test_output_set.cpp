// OutputSet: every output checked before the work, all of them written or none after it.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <stdexcept>

#include "bouguer/core/error.h"
#include "bouguer/io/image_io.h"
#include "bouguer/io/output_set.h"
#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// The message with which adding `path` as an image output is refused; empty when it is accepted.
std::string refusal(const fs::path& path, std::span<const std::string_view> extensions = kImageExtensions) {
  OutputSet outputs;
  try {
    outputs.add("-o", path, extensions);
  } catch (const UsageError& e) {
    return e.what();
  }
  return {};
}

TEST(OutputSet, RefusesAnOutputThatCannotBeWrittenWhenItIsAdded) {
  const fs::path dir = test::scratch_dir("output_set_check");
  fs::create_directories(dir / "sub.png");
  test::write_file(dir / "file.txt", "not a folder");
  const std::pair<fs::path, std::string> cases[] = {
      {dir / "missing" / "dir" / "x.png",
       fmt::format("folder '{}' does not exist", (dir / "missing" / "dir").string())},
      {dir / "x.jpg", "unknown file type '.jpg' (use .png, .exr or .pfm)"},
      {dir / "x", "no file type (use .png, .exr or .pfm)"},
      {dir / "file.txt" / "x.png", fmt::format("'{}' is not a folder", (dir / "file.txt").string())},
      {dir / "sub.png", "it is a folder"},
      {dir / "sub.png" / "", "not a file name"},
  };
  for (const auto& [path, why] : cases) EXPECT_EQ(refusal(path), fmt::format("-o {}: {}", path.string(), why));
  EXPECT_EQ(refusal(dir / "X.PNG"), "");  // the extension in any case
  EXPECT_EQ(refusal(dir / "sub.png" / "y.exr"), "");
  EXPECT_EQ(refusal(dir / "stats", {}), "");  // no extensions given: any name
  EXPECT_EQ(refusal("relative.pfm"), "");     // the working folder

  // The same file twice, however it is spelt.
  OutputSet outputs;
  outputs.add("-o", dir / "a.exr", kImageExtensions);
  try {
    outputs.add("--spectral-exr", dir / "sub.png" / ".." / "a.exr");
    ADD_FAILURE() << "a second output on the same file was accepted";
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()),
              fmt::format("--spectral-exr {}: the same file as -o {}", (dir / "sub.png" / ".." / "a.exr").string(),
                          (dir / "a.exr").string()));
  }
  EXPECT_EQ(names_in(dir), (std::vector<std::string>{"file.txt", "sub.png"}));  // checking writes nothing
}

TEST(OutputSet, RefusesAFolderThatIsNotWritable) {
  if (::geteuid() == 0) GTEST_SKIP() << "root may write into a read-only folder";
  const fs::path dir = test::scratch_dir("output_set_read_only");
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec);
  const std::string why = refusal(dir / "x.png");
  fs::permissions(dir, fs::perms::owner_all);
  EXPECT_EQ(why.rfind(fmt::format("-o {}: folder '{}' is not writable", (dir / "x.png").string(), dir.string()), 0), 0u)
      << why;
}

// The second of three writers fails: the first and third files keep their earlier bytes, the
// second is not created, no temporary is left, and the message names the second output.
TEST(OutputSet, WritesEveryOutputOrNone) {
  const fs::path dir = test::scratch_dir("output_set_commit");
  test::write_file(dir / "a.txt", "earlier a");
  test::write_file(dir / "c.txt", "earlier c");
  OutputSet outputs;
  outputs.add("--first", dir / "a.txt");
  outputs.add("--second", dir / "b.txt");
  outputs.add("--third", dir / "c.txt");
  std::vector<fs::path> written;
  const auto text = [&](const std::string& bytes) {
    return [&, bytes](const fs::path& temp) {
      written.push_back(temp);
      test::write_file(temp, bytes);
    };
  };
  const auto disk_full = [&](const fs::path& temp) {
    written.push_back(temp);
    test::write_file(temp, "half a file");
    fail("{}: disk full", temp.string());
  };
  try {
    outputs.write_all({{"--first", text("new a")}, {"--second", disk_full}, {"--third", text("new c")}});
    ADD_FAILURE() << "a failed writer went unreported";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              fmt::format("--second {}: disk full; no output was written", (dir / "b.txt").string()));
  }
  ASSERT_EQ(written.size(), 2u);  // the third is not even started
  for (const fs::path& temp : written) {
    EXPECT_EQ(temp.parent_path(), dir);   // beside the target: the rename stays in one folder
    EXPECT_EQ(temp.extension(), ".txt");  // writers choose the format by extension
  }
  EXPECT_EQ(test::read_file(dir / "a.txt"), "earlier a");
  EXPECT_EQ(test::read_file(dir / "c.txt"), "earlier c");
  EXPECT_EQ(names_in(dir), (std::vector<std::string>{"a.txt", "c.txt"}));

  // Any other exception is passed on, with the same clean-up.
  EXPECT_THROW(outputs.write_all({{"--first", text("new a")},
                                  {"--second", [](const fs::path&) { throw std::runtime_error("internal"); }},
                                  {"--third", text("new c")}}),
               std::runtime_error);
  EXPECT_EQ(names_in(dir), (std::vector<std::string>{"a.txt", "c.txt"}));
  EXPECT_EQ(test::read_file(dir / "a.txt"), "earlier a");

  // When every writer succeeds, every file is replaced.
  outputs.write_all({{"--first", text("new a")}, {"--second", text("new b")}, {"--third", text("new c")}});
  EXPECT_EQ(names_in(dir), (std::vector<std::string>{"a.txt", "b.txt", "c.txt"}));
  EXPECT_EQ(test::read_file(dir / "a.txt"), "new a");
  EXPECT_EQ(test::read_file(dir / "b.txt"), "new b");
  EXPECT_EQ(test::read_file(dir / "c.txt"), "new c");
}

}  // namespace
}  // namespace bouguer
