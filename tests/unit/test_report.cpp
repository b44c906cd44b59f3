// `bouguer report` in a real browser: headless Chromium loads the page from disk (no server),
// takes a screenshot, and the test fails if any image or plot fails to decode or the page logs
// anything to the console. Small renders keep it quick; the page is the same as `make demo`'s.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <regex>

#include "support/test_support.h"

namespace bouguer {
namespace {
namespace fs = std::filesystem;

struct Output {
  int code = -1;
  std::string text;
};

Output run(const std::string& command) {
  Output o;
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (!p) return o;
  char buf[4096];
  std::size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) o.text.append(buf, n);
  const int status = pclose(p);
  o.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return o;
}

// The flags that work on these machines: no sandbox (root), no GPU, and no background
// networking (the network is closed), with a fresh profile.
std::string chromium(const fs::path& profile, const std::string& args) {
  return "chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
         "--disable-background-networking --disable-component-update --disable-sync --hide-scrollbars "
         "--enable-logging=stderr --v=0 --virtual-time-budget=10000 --user-data-dir='" +
         profile.string() + "' " + args;
}

TEST(Report, PassesTheBrowserCheck) {
  const fs::path dir = test::scratch_dir("report");
  const auto r = test::run_bouguer({"report", "--out", (dir / "page").string(), "--scenes",
                                    (fs::path(BOUGUER_SOURCE_DIR) / "scenes" / "paper").string(), "--resolution", "48x48",
                                    "--spp", "4", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const fs::path page = dir / "page" / "index.html";
  ASSERT_TRUE(fs::exists(page));
  const std::string html = test::read_file(page);
  // Self-contained: no file or network references, only data: URIs.
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("src=\"file"), std::string::npos);
  std::size_t images = 0;
  for (std::size_t at = html.find("<img"); at != std::string::npos; at = html.find("<img", at + 1)) ++images;
  EXPECT_GE(images, 6u * 3u + 2u);  // 6 paper scenes × (full, rgb3, heat map) + the materials' plots

  ASSERT_EQ(run("command -v chromium").code, 0) << "chromium is missing: run scripts/install-deps.sh";
  const std::string url = "file://" + fs::absolute(page).string();
  const Output dom = run(chromium(dir / "profile-dom", "--dump-dom '" + url + "'"));
  ASSERT_EQ(dom.code, 0) << dom.text;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(dom.text, m, std::regex("data-images=\"([^\"]*)\""))) << dom.text.substr(0, 2000);
  EXPECT_EQ(m[1].str(), "ok: " + std::to_string(images));
  // Anything the page logs (console calls, uncaught exceptions) shows as an INFO:CONSOLE line.
  EXPECT_EQ(dom.text.find(":CONSOLE"), std::string::npos) << dom.text.substr(0, 2000);

  const fs::path shot = dir / "report.png";
  const Output screenshot =
      run(chromium(dir / "profile-shot", "--window-size=1280,2400 --screenshot='" + shot.string() + "' '" + url + "'"));
  ASSERT_EQ(screenshot.code, 0) << screenshot.text;
  ASSERT_TRUE(fs::exists(shot)) << screenshot.text;
  EXPECT_GT(fs::file_size(shot), 50000u);  // a page with pictures, not a blank one
  EXPECT_EQ(screenshot.text.find(":CONSOLE"), std::string::npos) << screenshot.text.substr(0, 2000);

  // The check itself can fail: the same page with a broken image and a logged error is caught.
  std::string broken = html;
  broken.insert(broken.find("<h2"), R"(<img alt="broken one" src="data:image/png;base64,AAAA"><script>console.error("boom")</script>)");
  test::write_file(dir / "broken.html", broken);
  const Output bad = run(chromium(dir / "profile-bad", "--dump-dom 'file://" + fs::absolute(dir / "broken.html").string() + "'"));
  EXPECT_NE(bad.text.find("data-images=\"failed: broken one\""), std::string::npos);
  EXPECT_NE(bad.text.find(":CONSOLE"), std::string::npos);
}

// Bad options give one line and leave an earlier page alone.
TEST(Report, BadInputGivesOneLineAndKeepsTheEarlierPage) {
  const fs::path dir = test::scratch_dir("report_bad");
  test::write_file(dir / "index.html", "earlier page");
  const std::string scenes = (fs::path(BOUGUER_SOURCE_DIR) / "scenes" / "paper").string();
  // A bad --resolution is a bad command line (exit 2, checked by the SceneBuilder as a scene's
  // resolution is); a folder that is not there is bad input (exit 1).
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"report", "--out", dir.string(), "--scenes", scenes, "--resolution", "64x0"}, "--resolution"},
      {{"report", "--out", dir.string(), "--scenes", scenes, "--resolution", "64"}, "--resolution"},
      {{"report", "--out", dir.string(), "--scenes", scenes, "--resolution", "64x48x2"}, "--resolution"},
      {{"report", "--out", dir.string(), "--scenes", (dir / "absent").string()}, "is not a folder"},
  };
  for (const auto& [args, expected] : cases) {
    const auto r = test::run_bouguer(args);
    EXPECT_EQ(r.exit_code, expected == "--resolution" ? 2 : 1) << args.back();
    EXPECT_EQ(test::line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
  EXPECT_EQ(test::read_file(dir / "index.html"), "earlier page");
}

// A page that cannot be written is refused before the first scene is rendered (exit 2, no progress line).
TEST(Report, AnOutFolderThatCannotHoldThePageFailsBeforeRendering) {
  const fs::path dir = test::scratch_dir("report_bad_out");
  fs::create_directories(dir / "page" / "index.html");
  test::write_file(dir / "file", "not a folder");
  const std::string scenes = (fs::path(BOUGUER_SOURCE_DIR) / "scenes" / "paper").string();
  const std::vector<std::pair<fs::path, std::string>> cases = {
      {dir / "page", "--out " + (dir / "page" / "index.html").string() + ": it is a folder"},
      {dir / "file", "--out " + (dir / "file").string() + ": cannot create the folder"},
  };
  for (const auto& [out, expected] : cases) {
    const auto r = test::run_bouguer({"report", "--out", out.string(), "--scenes", scenes});
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(test::line_count(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace bouguer
