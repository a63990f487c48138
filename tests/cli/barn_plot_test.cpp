// `barn plot`, `barn world render` and their outputs through the real executable: the
// extension of -o chooses PNG, PDF or SVG, and any other is bad input (exit 2) refused before
// any work, with nothing written.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "cli_runner.hpp"

namespace {

using namespace barn::test;
using testing::HasSubstr;

const fs::path kRepo = BARN_SOURCE_DIR;

/// A file's kind by its first bytes.
std::string magic(const fs::path& file) {
  const std::string text = readFile(file);
  if (text.rfind("\x89PNG\r\n\x1a\n", 0) == 0) return "png";
  if (text.rfind("%PDF-", 0) == 0) return "pdf";
  if (text.find("<svg") != std::string::npos && text.find("<svg") < 200) return "svg";
  return "?";
}

class BarnPlot : public ::testing::Test {
 protected:
  // One record for the suite: the straight-line fixture on worlds 0 and 150, 2 trials each
  // (fast, and it collides, so trajectories have contacts).
  static void SetUpTestSuite() {
    dir_ = new fs::path(uniqueTempPath("barn_plot_test"));
    fs::create_directories(*dir_);
    const RunResult r = run("run --controller straight --worlds 0,150 --trials 2 --out " + quote(*dir_ / "record"));
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static void TearDownTestSuite() {
    std::error_code ec;
    fs::remove_all(*dir_, ec);
    delete dir_;
  }
  static fs::path record() { return *dir_ / "record"; }
  static fs::path* dir_;
};
fs::path* BarnPlot::dir_ = nullptr;

TEST_F(BarnPlot, ScoresAreWrittenInTheFormatOfTheExtension) {
  for (const std::string extension : {"png", "pdf", "svg"}) {
    const fs::path out = *dir_ / ("scores." + extension);
    const RunResult r = run("plot scores " + quote(record()) + " -o " + quote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(magic(out), extension);
    EXPECT_GT(fs::file_size(out), 3000u);
  }
  // PNG size (plots.hpp): 720 + 128 wide; 448 + 22 (subtitle) + 24 (one legend row) + 34
  // (outcome strip) tall. Bytes 16 and 20 hold them big-endian.
  const std::string png = readFile(*dir_ / "scores.png");
  const auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(png[at]) << 24) | (static_cast<unsigned char>(png[at + 1]) << 16) |
           (static_cast<unsigned char>(png[at + 2]) << 8) | static_cast<unsigned char>(png[at + 3]);
  };
  EXPECT_EQ(be32(16), 848u);
  EXPECT_EQ(be32(20), 528u);
}

TEST_F(BarnPlot, AnUnknownExtensionIsBadInputNamingTheFile) {
  const fs::path jpg = *dir_ / "scores.jpg";
  RunResult r = run("plot scores " + quote(record()) + " -o " + quote(jpg));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr(jpg.string()));
  EXPECT_THAT(r.output, HasSubstr(".png, .pdf or .svg"));
  EXPECT_FALSE(fs::exists(jpg));

  const fs::path gif = *dir_ / "traj.gif";
  r = run("plot trajectory " + quote(record()) + " --world 0 -o " + quote(gif));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr(gif.string()));
  EXPECT_FALSE(fs::exists(gif));

  const fs::path none = *dir_ / "world";
  r = run("world render " + quote(kRepo / "worlds" / "world_000.yaml") + " -o " + quote(none));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("unknown image type"));
}

TEST_F(BarnPlot, TrajectoriesOfSeveralWorldsAreOneFileEachInTheChosenFormat) {
  const RunResult r = run("plot trajectory " + quote(record()) + " --world 0,150 --colour trial -o " +
                          quote(*dir_ / "traj.pdf"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(magic(*dir_ / "traj_world_0.pdf"), "pdf");
  EXPECT_EQ(magic(*dir_ / "traj_world_150.pdf"), "pdf");
  EXPECT_FALSE(fs::exists(*dir_ / "traj.pdf"));
}

TEST_F(BarnPlot, TrajectoryColouringIsStateOrTrial) {
  const fs::path svg = *dir_ / "state.svg";
  RunResult r = run("plot trajectory " + quote(record()) + " --world 150 --trial 1 -o " + quote(svg));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(magic(svg), "svg");
  r = run("plot trajectory " + quote(record()) + " --world 150 --colour rainbow -o " + quote(*dir_ / "x.png"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("rainbow"));
}

TEST_F(BarnPlot, ACurveDrawsNamedColumnsOfACsvAndNamesAMissingOne) {
  const fs::path csv = *dir_ / "curve.csv";
  writeFile(csv, "steps,success,collision\n4096,0.1,0.9\n8192,0.2,nan\n12288,0.35,0.6\n");
  const fs::path png = *dir_ / "curve.png";
  RunResult r = run("plot curve " + quote(csv) + " --y success,collision --y-max 1 -o " + quote(png));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(magic(png), "png");
  EXPECT_GT(fs::file_size(png), 3000u);
  r = run("plot curve " + quote(csv) + " --y timeout -o " + quote(*dir_ / "none.png"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no column 'timeout' (columns: steps, success, collision)"));
  EXPECT_FALSE(fs::exists(*dir_ / "none.png"));
  writeFile(csv, "steps,success\n1,x\n");
  r = run("plot curve " + quote(csv) + " --y success -o " + quote(*dir_ / "bad.png"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr(":2: column success: 'x' is not a number"));
}

TEST_F(BarnPlot, WorldRenderWritesVectorFormats) {
  for (const std::string extension : {"pdf", "svg"}) {
    const fs::path out = *dir_ / ("world." + extension);
    const RunResult r = run("world render " + quote(kRepo / "worlds" / "world_000.yaml") + " -o " + quote(out));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(magic(out), extension);
  }
}

TEST_F(BarnPlot, ParamsDrawsOnePanelPerParameterOfATrajectoryFile) {
  // Two parameters set at 0 s and 1 s, the episode ending at 1.5 s; keys in first-seen order.
  const fs::path csv = *dir_ / "params.csv";
  writeFile(csv,
            "time_s,x,y,yaw,cmd_linear,cmd_angular,state,params\n"
            "0,0,0,0,0.5,0,planning,max_vel_x=1.5;vx_samples=8\n"
            "0.5,0.2,0,0,0.5,0,planning,\n"
            "1,0.4,0,0,0.5,0,planning,max_vel_x=0.25;vx_samples=12\n"
            "1.5,0.5,0,0,0.5,0,planning,\n");
  const fs::path png = *dir_ / "params.png";
  RunResult r = run("plot params " + quote(csv) + " -o " + quote(png));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Two stacked 900 x 170 panels: 900 x 340.
  const std::string bytes = readFile(png);
  ASSERT_GT(bytes.size(), 24u);
  const auto be32 = [&](std::size_t at) {
    return (static_cast<unsigned char>(bytes[at]) << 24) | (static_cast<unsigned char>(bytes[at + 1]) << 16) |
           (static_cast<unsigned char>(bytes[at + 2]) << 8) | static_cast<unsigned char>(bytes[at + 3]);
  };
  EXPECT_EQ(be32(16), 900u);
  EXPECT_EQ(be32(20), 340u);
  // --keys chooses and orders them; a key the file does not hold is bad input naming those it does.
  r = run("plot params " + quote(csv) + " --keys vx_samples -o " + quote(*dir_ / "one.svg"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(magic(*dir_ / "one.svg"), "svg");
  r = run("plot params " + quote(csv) + " --keys gdist_scale -o " + quote(*dir_ / "none.png"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no parameter 'gdist_scale' (it holds: max_vel_x, vx_samples)"));
  // A params cell that does not parse names its line.
  writeFile(csv, "time_s,x,y,yaw,cmd_linear,cmd_angular,state,params\n0,0,0,0,0.5,0,planning,max_vel_x\n");
  r = run("plot params " + quote(csv) + " -o " + quote(png));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("params.csv:2: params entry 'max_vel_x': expected key=number"));
  // A record's trajectory file of a controller that sets nothing: nothing to draw.
  r = run("run --controller straight --worlds 0 --trials 1 --trajectories --out " + quote(*dir_ / "with_traj"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run("plot params " + quote(*dir_ / "with_traj" / "trajectories" / "world_0_trial_0.csv") + " -o " + quote(png));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no parameter was set"));
}

}  // namespace
