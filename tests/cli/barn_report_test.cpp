// `barn report`: the HTML page of a run and of a sweep, checked as text and in a real browser
// (headless Chromium, when installed: the page loads, its script runs without a console
// message, the per-world table has one row per world, a screenshot is taken).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using namespace barn::test;
using testing::AllOf;
using testing::HasSubstr;
using testing::Not;

std::size_t count(const std::string& text, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

// The rows of the table with id `id` in an HTML text.
std::size_t tableRows(const std::string& html, const std::string& id) {
  const std::size_t start = html.find("<table id=\"" + id + "\"");
  if (start == std::string::npos) return 0;
  const std::size_t body = html.find("<tbody>", start);
  const std::size_t end = html.find("</tbody>", body);
  return count(html.substr(body, end - body), "<tr>");
}

// Shell command output and exit code.
struct Shell {
  int exit_code = -1;
  std::string output;
};
Shell shell(const std::string& command) {
  Shell result;
  if (FILE* pipe = ::popen(command.c_str(), "r")) {
    char buffer[4096];
    while (std::fgets(buffer, sizeof(buffer), pipe)) result.output += buffer;
    const int status = ::pclose(pipe);
    result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  return result;
}

class BarnReport : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(uniqueTempPath("barn_report_test"));
    fs::create_directories(*dir_);
    // 8 worlds x 2 trials of dwa: some episodes fail, so the page draws them.
    const RunResult r = run("run --controller dwa --worlds 0:300:38 --trials 2 --out " + quote(*dir_ / "run"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(*dir_, ec);
    delete dir_;
  }
  static fs::path* dir_;
};
fs::path* BarnReport::dir_ = nullptr;

TEST_F(BarnReport, ARunsPageIsSelfContainedWithOneRowPerWorld) {
  const fs::path page = *dir_ / "run.html";
  const RunResult r = run("report " + quote(*dir_ / "run") + " -o " + quote(page));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string html = readFile(page);
  EXPECT_EQ(tableRows(html, "per-world"), 8u);
  EXPECT_EQ(tableRows(html, "summary"), 1u);
  EXPECT_GT(tableRows(html, "breakdown"), 0u);
  EXPECT_THAT(html, AllOf(HasSubstr("dwa on barnbench-generated worlds"), HasSubstr("data:image/png;base64,")));
  // Nothing loaded from elsewhere.
  EXPECT_THAT(html, AllOf(Not(HasSubstr("http://")), Not(HasSubstr("https://")), Not(HasSubstr("src=\"/")),
                          Not(HasSubstr("href="))));
  EXPECT_FALSE(fs::exists(*dir_ / ".barn_report.tmp"));
}

TEST_F(BarnReport, ASweepsPageListsEveryCell) {
  const RunResult s = run("sweep --controller pure_pursuit --param lookahead=0.4,0.8 --param speed=0.5,1.0 "
                          "--worlds 0:300:100 --out " + quote(*dir_ / "sweep"));
  ASSERT_EQ(s.exit_code, 0) << s.output;
  const fs::path page = *dir_ / "sweep.html";
  const RunResult r = run("report " + quote(*dir_ / "sweep") + " -o " + quote(page));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string html = readFile(page);
  EXPECT_EQ(tableRows(html, "cells"), 4u);
  EXPECT_GE(count(html, "data:image/png;base64,"), 1u);
}

TEST_F(BarnReport, BadInputIsExitTwoAndWritesNothing) {
  EXPECT_EQ(run("report " + quote(*dir_ / "nothing") + " -o " + quote(*dir_ / "x.html")).exit_code, 2);
  EXPECT_EQ(run("report " + quote(*dir_ / "run") + " -o " + quote(*dir_ / "x.pdf")).exit_code, 2);
  EXPECT_FALSE(fs::exists(*dir_ / "x.html"));
}

TEST_F(BarnReport, ChromiumLoadsThePageRunsItsScriptAndShowsEveryWorld) {
  if (shell("command -v chromium").exit_code != 0) GTEST_SKIP() << "chromium not installed (tools/setup.sh installs it)";
  const fs::path page = *dir_ / "browser.html";
  ASSERT_EQ(run("report " + quote(*dir_ / "run") + " -o " + quote(page)).exit_code, 0);
  const std::string flags = "--headless --no-sandbox --disable-gpu --disable-extensions --no-first-run "
                            "--user-data-dir=" + quote(*dir_ / "chromium-profile");
  // The DOM after the page's script ran; console messages (errors included) go to the log.
  const fs::path log = *dir_ / "console.log";
  const Shell dom = shell("timeout 120 chromium " + flags + " --enable-logging=stderr --v=0 --dump-dom " +
                          quote("file://" + page.string()) + " 2> " + quote(log));
  ASSERT_EQ(dom.exit_code, 0) << readFile(log);
  EXPECT_THAT(dom.output, HasSubstr("data-ready=\"1\"")) << "the page's script did not finish";
  EXPECT_EQ(tableRows(dom.output, "per-world"), 8u);
  EXPECT_THAT(readFile(log), Not(HasSubstr("CONSOLE"))) << readFile(log);
  // A screenshot of the rendered page.
  const fs::path shot = *dir_ / "page.png";
  const Shell screenshot = shell("timeout 120 chromium " + flags + " --window-size=1200,1600 --screenshot=" +
                                 quote(shot) + " " + quote("file://" + page.string()) + " 2>&1");
  ASSERT_EQ(screenshot.exit_code, 0) << screenshot.output;
  const std::string png = readFile(shot);
  ASSERT_GT(png.size(), 10000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
}

}  // namespace
