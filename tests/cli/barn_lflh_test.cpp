// `barn lflh collect|train|act` end to end on a tiny configuration, and its bad-input exits.
//
// Exit codes (src/cli/main.cpp): 0 ok, 1 the run failed, 2 bad usage or bad input.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <filesystem>
#include <random>
#include <string>

#include "barn/core/text_io.hpp"
#include "barn/core/robot_config.hpp"
#include "barn/learning/exploration.hpp"
#include "barn/learning/policy.hpp"

namespace {

namespace fs = std::filesystem;
using testing::HasSubstr;

const fs::path kBarn = fs::path(BARN_BINARY_DIR) / "barn";

// 30 s of driving, every 4th record, a 16-unit network for 3 epochs: about a second.
constexpr char kTinyConfig[] = R"(name: tiny
collect: {duration: 30.0}
hallucination: {stride: 4}
train: {hidden: 16, epochs: 3, activation: leaky_relu}
)";

struct RunResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

class BarnLflh : public ::testing::Test {
 protected:
  void SetUp() override {
    std::random_device device;
    dir_ = fs::temp_directory_path() / ("barn_lflh_test_" + std::to_string(device()));
    fs::create_directories(dir_);
    barn::core::writeFileAtomic(dir_ / "tiny.yaml", kTinyConfig);
  }
  void TearDown() override { fs::remove_all(dir_); }

  RunResult run(const std::string& args) {
    const fs::path capture = dir_ / "output.txt";
    const std::string command = "'" + kBarn.string() + "' " + args + " > '" + capture.string() + "' 2>&1";
    const int status = std::system(command.c_str());
    RunResult result;
    result.output = barn::core::readTextFile(capture);
    if (status != -1 && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    return result;
  }
  std::string path(const std::string& name) const { return "'" + (dir_ / name).string() + "'"; }

  fs::path dir_;
};

TEST_F(BarnLflh, CollectThenTrainWritesALoadablePolicyWithItsLossCsvAndPlot) {
  const RunResult collect = run("lflh collect --config " + path("tiny.yaml") + " --out " + path("data"));
  ASSERT_EQ(collect.exit_code, 0) << collect.output;
  EXPECT_THAT(collect.output, HasSubstr("1501 records (30.0 s at 50 Hz)"));  // 30 s * 50 Hz + 1
  EXPECT_TRUE(fs::exists(dir_ / "data" / "exploration_tiny.csv"));

  const RunResult train =
      run("lflh train --config " + path("tiny.yaml") + " --data " + path("data") + " --out " + path("out/tiny.policy"));
  ASSERT_EQ(train.exit_code, 0) << train.output;
  EXPECT_THAT(train.output, HasSubstr("epoch    3/3"));
  const barn::learning::Policy policy = barn::learning::Policy::load(dir_ / "out" / "tiny.policy");
  EXPECT_EQ(policy.info().name, "tiny");
  EXPECT_EQ(policy.info().hidden, 16);
  EXPECT_EQ(policy.info().epochs, 3);
  EXPECT_EQ(policy.info().activation, barn::learning::Activation::LeakyRelu);
  EXPECT_EQ(policy.info().slope, 0.01);
  // Header line + 3 epochs.
  const std::string csv = barn::core::readTextFile(dir_ / "out" / "tiny.loss.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);
  EXPECT_EQ(barn::core::readTextFile(dir_ / "out" / "tiny.loss.png").substr(1, 3), "PNG");
}

TEST_F(BarnLflh, ActPrintsThePolicysCommandForEachScanOnStdin) {
  barn::learning::Mlp<float> net(722, 8, 2, barn::learning::Activation::LeakyRelu, 0.01);
  barn::core::Rng rng(9);
  net.initialise(rng);
  barn::learning::PolicyInfo info;
  info.hidden = 8;
  info.name = "small";
  info.activation = barn::learning::Activation::LeakyRelu;
  barn::learning::writePolicyFile(dir_ / "small.policy", info, net.parameters());
  const barn::learning::Policy policy = barn::learning::Policy::load(dir_ / "small.policy");

  // Two scans: no returns at all, and a ramp (comma separated, as a CSV row).
  std::string open, ramp;
  barn::core::LaserScan open_scan, ramp_scan;
  for (int i = 0; i < 720; ++i) {
    open += (i ? " " : "") + std::string("inf");
    open_scan.ranges.push_back(std::numeric_limits<double>::infinity());
    const double r = 0.25 + 0.0025 * i;
    ramp += (i ? "," : "") + barn::core::formatDouble(r);
    ramp_scan.ranges.push_back(r);
  }
  barn::core::writeFileAtomic(dir_ / "scans.txt", open + "\n" + ramp + "\n");
  const RunResult result = run("lflh act --policy " + path("small.policy") + " --goal 1,0.5 < " + path("scans.txt"));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto line = [](const barn::core::Twist& t) {
    char text[64];
    std::snprintf(text, sizeof text, "%.9g %.9g\n", t.linear, t.angular);
    return std::string(text);
  };
  EXPECT_EQ(result.output, line(policy.act(open_scan, {1.0, 0.5})) + line(policy.act(ramp_scan, {1.0, 0.5})));

  barn::core::writeFileAtomic(dir_ / "short.txt", "1 2 3\n");
  const RunResult short_scan = run("lflh act --policy " + path("small.policy") + " < " + path("short.txt"));
  EXPECT_EQ(short_scan.exit_code, 2);
  EXPECT_THAT(short_scan.output, HasSubstr("stdin line 1: 3 ranges, the policy takes 720"));
}

TEST_F(BarnLflh, AlsoTrainOnJoinsAnotherConfigsRecording) {
  barn::core::writeFileAtomic(dir_ / "joined.yaml",
                              "name: joined\ncollect: {duration: 20.0}\nhallucination: {stride: 4}\n"
                              "train: {hidden: 16, epochs: 2, batches_per_epoch: 5}\nalso_train_on: [tiny.yaml]\n");
  ASSERT_EQ(run("lflh collect --config " + path("joined.yaml") + " --out " + path("data")).exit_code, 0);
  // Without the other config's recording: exit 2 naming it.
  const RunResult missing =
      run("lflh train --config " + path("joined.yaml") + " --data " + path("data") + " --out " + path("j.policy"));
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_THAT(missing.output, HasSubstr("exploration_tiny.csv"));
  ASSERT_EQ(run("lflh collect --config " + path("tiny.yaml") + " --out " + path("data")).exit_code, 0);
  const RunResult train =
      run("lflh train --config " + path("joined.yaml") + " --data " + path("data") + " --out " + path("j.policy"));
  ASSERT_EQ(train.exit_code, 0) << train.output;
  EXPECT_THAT(train.output, HasSubstr("joined tiny (1501 records)"));
  EXPECT_THAT(train.output, HasSubstr("from 2502 records"));  // 1001 + 1501
  EXPECT_THAT(train.output, HasSubstr("epoch    2/2"));
}

TEST_F(BarnLflh, BadConfigIsExitTwoNamingTheKey) {
  barn::core::writeFileAtomic(dir_ / "bad.yaml", "name: tiny\ntrain: {epochz: 3}\n");
  const RunResult result = run("lflh collect --config " + path("bad.yaml") + " --out " + path("data"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output, HasSubstr("train.epochz: unknown key"));
}

TEST_F(BarnLflh, CollectDrivesThePlantOfTheSimConfig) {
  // The default sim config is the default plant: the same recording; another plant (turning at
  // 1.5x) records another motion; a bad sim config is exit 2 naming the field.
  const auto collect = [&](const std::string& folder, const std::string& sim_config) {
    const std::string option = sim_config.empty() ? "" : " --sim-config '" + sim_config + "'";
    return run("lflh collect --config " + path("tiny.yaml") + option + " --out " + path(folder));
  };
  const auto recording = [&](const std::string& folder) {
    return barn::core::readTextFile(dir_ / folder / "exploration_tiny.csv");
  };
  barn::core::writeFileAtomic(dir_ / "fast.yaml", "robot: {turn_efficiency: 1.5}\n");
  barn::core::writeFileAtomic(dir_ / "bad_plant.yaml", "robot: {turn_efficiency: -1}\n");
  ASSERT_EQ(collect("plain", "").exit_code, 0);
  ASSERT_EQ(collect("shipped", (fs::path(BARN_SOURCE_DIR) / "configs" / "sim" / "barn.yaml").string()).exit_code, 0);
  ASSERT_EQ(collect("fast", (dir_ / "fast.yaml").string()).exit_code, 0);
  EXPECT_EQ(recording("shipped"), recording("plain"));
  EXPECT_NE(recording("fast"), recording("plain"));

  const RunResult bad = collect("bad", (dir_ / "bad_plant.yaml").string());
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.output, HasSubstr("robot.turn_efficiency"));
  EXPECT_FALSE(fs::exists(dir_ / "bad"));
}

TEST_F(BarnLflh, APolicyRemembersItsPlantAndARunOnAnotherPlantWarnsOnce) {
  // Trained on a robot that turns at 1.5x: a run with the default robot warns (once, though
  // two trials run), a run on the plant it was trained on does not.
  barn::core::writeFileAtomic(dir_ / "fast.yaml", "robot: {turn_efficiency: 1.5}\n");
  ASSERT_EQ(run("lflh collect --config " + path("tiny.yaml") + " --sim-config " + path("fast.yaml") + " --out " + path("data")).exit_code, 0);
  ASSERT_EQ(run("lflh train --config " + path("tiny.yaml") + " --data " + path("data") + " --out " + path("tiny.policy")).exit_code, 0);
  const barn::learning::Policy policy = barn::learning::Policy::load(dir_ / "tiny.policy");
  barn::core::RobotConfig fast;
  fast.turn_efficiency = 1.5;
  EXPECT_EQ(policy.info().plant_hash, barn::sim::plantHash(fast, {}));

  barn::core::writeFileAtomic(dir_ / "tiny_lflh.yaml", "type: lflh\nlflh: {policy: tiny.policy}\n");
  const std::string args = "run --controller tiny_lflh --config " + path("tiny_lflh.yaml") + " --worlds 0 --trials 2 --out ";
  const RunResult other = run(args + path("other_plant"));
  ASSERT_EQ(other.exit_code, 0) << other.output;
  const std::string warning = "warning: tiny_lflh: its policy was trained on another plant";
  EXPECT_THAT(other.output, HasSubstr(warning));
  EXPECT_EQ(other.output.find(warning), other.output.rfind(warning));
  const RunResult same = run(args + path("same_plant") + " --sim-config " + path("fast.yaml"));
  ASSERT_EQ(same.exit_code, 0) << same.output;
  EXPECT_THAT(same.output, testing::Not(HasSubstr("trained on another plant")));
}

TEST_F(BarnLflh, JoiningARecordingOfAnotherPlantIsExitTwo) {
  barn::core::writeFileAtomic(dir_ / "fast.yaml", "robot: {turn_efficiency: 1.5}\n");
  barn::core::writeFileAtomic(dir_ / "joined.yaml", "name: joined\ncollect: {duration: 20.0}\nhallucination: {stride: 4}\n"
                                                    "train: {hidden: 16, epochs: 2}\nalso_train_on: [tiny.yaml]\n");
  ASSERT_EQ(run("lflh collect --config " + path("joined.yaml") + " --out " + path("data")).exit_code, 0);
  ASSERT_EQ(run("lflh collect --config " + path("tiny.yaml") + " --sim-config " + path("fast.yaml") + " --out " + path("data")).exit_code, 0);
  const RunResult result =
      run("lflh train --config " + path("joined.yaml") + " --data " + path("data") + " --out " + path("j.policy"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output, HasSubstr("exploration_tiny.csv was recorded on another plant"));
  EXPECT_FALSE(fs::exists(dir_ / "j.policy"));
}

TEST_F(BarnLflh, TrainingOnDataFromOtherCollectSettingsIsExitTwo) {
  ASSERT_EQ(run("lflh collect --config " + path("tiny.yaml") + " --out " + path("data")).exit_code, 0);
  std::string other = kTinyConfig;
  other.replace(other.find("duration: 30.0"), 14, "duration: 40.0");
  barn::core::writeFileAtomic(dir_ / "other.yaml", other);
  const RunResult result =
      run("lflh train --config " + path("other.yaml") + " --data " + path("data") + " --out " + path("x.policy"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output, HasSubstr("collect_hash differs"));
}

TEST_F(BarnLflh, MissingRecordingIsExitTwoNamingTheFile) {
  const RunResult result =
      run("lflh train --config " + path("tiny.yaml") + " --data " + path("nowhere") + " --out " + path("x.policy"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_THAT(result.output, HasSubstr("exploration_tiny.csv"));
}

}  // namespace
