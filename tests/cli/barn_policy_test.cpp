// `barn policy act` on both network formats, and its bad-input exits.
//
// Exit codes (src/cli/main.cpp): 0 ok, 1 the run failed, 2 bad usage or bad input.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <limits>
#include <string>

#include "barn/core/text_io.hpp"
#include "barn/learning/policy.hpp"
#include "barn/learning/transformer_policy.hpp"
#include "tests/cli/cli_runner.hpp"

namespace {

namespace fs = std::filesystem;
using barn::test::quote;
using barn::test::run;
using barn::test::RunResult;
using testing::HasSubstr;

const fs::path kSource = fs::path(BARN_SOURCE_DIR);

std::string line(double a, double b) {
  char text[64];
  std::snprintf(text, sizeof text, "%.9g %.9g\n", a, b);
  return text;
}

// Two scans: no returns, and a ramp 0.25 .. 2.05 m (comma separated, as a CSV row).
struct Scans {
  barn::core::LaserScan open, ramp;
  fs::path file = barn::test::uniqueTempPath("barn_policy_scans");
  Scans() {
    std::string text_open, text_ramp;
    for (int i = 0; i < 720; ++i) {
      text_open += (i ? " " : "") + std::string("inf");
      open.ranges.push_back(std::numeric_limits<double>::infinity());
      const double r = 0.25 + 0.0025 * i;
      text_ramp += (i ? "," : "") + barn::core::formatDouble(r);
      ramp.ranges.push_back(r);
    }
    barn::test::writeFile(file, text_open + "\n" + text_ramp + "\n");
  }
  ~Scans() {
    std::error_code ec;
    fs::remove(file, ec);
  }
};

TEST(BarnPolicyAct, ATransformerPolicyPrintsItsUnscaledOutputForTheGoalAsGiven) {
  const fs::path file = kSource / "tests" / "data" / "lics_transformer_small.policy";
  const barn::learning::TransformerPolicy policy = barn::learning::TransformerPolicy::load(file);
  const Scans scans;
  // (0, 0): LiCS's goal before its first plan, a valid input for the transformer.
  for (const std::string goal : {"0.6,-0.8", "0,0"}) {
    const RunResult result = run("policy act --policy " + quote(file) + " --goal " + goal + " < " + quote(scans.file));
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const Eigen::Vector2d g = goal == "0,0" ? Eigen::Vector2d(0.0, 0.0) : Eigen::Vector2d(0.6, -0.8);
    const Eigen::Vector2d a = policy.act(scans.open, g), b = policy.act(scans.ramp, g);
    EXPECT_EQ(result.output, line(a.x(), a.y()) + line(b.x(), b.y()));
  }
}

TEST(BarnPolicyAct, AnLflhPolicyGivesWhatBarnLflhActGives) {
  const fs::path file = kSource / "configs" / "policies" / "lflh_1ms.policy";
  const barn::learning::Policy policy = barn::learning::Policy::load(file);
  const Scans scans;
  const RunResult result = run("policy act --policy " + quote(file) + " --goal 1,0.5 < " + quote(scans.file));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const barn::core::Twist a = policy.act(scans.open, {1.0, 0.5}), b = policy.act(scans.ramp, {1.0, 0.5});
  EXPECT_EQ(result.output, line(a.linear, a.angular) + line(b.linear, b.angular));
  EXPECT_EQ(run("lflh act --policy " + quote(file) + " --goal 1,0.5 < " + quote(scans.file)).output, result.output);
  // An LfLH policy needs a direction.
  const RunResult zero = run("policy act --policy " + quote(file) + " --goal 0,0 < " + quote(scans.file));
  EXPECT_EQ(zero.exit_code, 2);
  EXPECT_THAT(zero.output, HasSubstr("--goal: must not be (0, 0)"));
}

TEST(BarnPolicyAct, AFileOfNeitherFormatOrAShortScanExitsTwo) {
  const Scans scans;
  const RunResult other = run("policy act --policy " + quote(kSource / "configs" / "sim" / "barn.yaml") + " < " + quote(scans.file));
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_THAT(other.output, HasSubstr("not a barnbench policy file"));
  const fs::path short_scan = barn::test::uniqueTempPath("barn_policy_short");
  barn::test::writeFile(short_scan, "1 2 3\n");
  const RunResult bad = run("policy act --policy " + quote(kSource / "tests" / "data" / "lics_transformer_small.policy") +
                            " < " + quote(short_scan));
  fs::remove(short_scan);
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.output, HasSubstr("stdin line 1: 3 ranges, the policy takes 720"));
}

}  // namespace
