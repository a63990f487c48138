#include "barn/learning/exploration.hpp"

#include <cmath>
#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "barn/core/config.hpp"
#include "barn/core/text_io.hpp"

namespace barn::learning {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

CollectConfig shortDrive() {
  CollectConfig c;
  c.duration = 20.0;
  return c;
}

fs::path tempDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("barn_exploration_test_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(Exploration, RecordsAtFiftyHertzWithCommandsInsideTheLimits) {
  const Recording r = collectExploration(shortDrive(), "short");
  // 20 s at 50 Hz, both ends included: 1001 records.
  ASSERT_EQ(r.records.size(), 1001u);
  EXPECT_DOUBLE_EQ(r.rate, 50.0);
  EXPECT_NEAR(r.records.back().t, 20.0, 1e-9);
  for (const MotionRecord& m : r.records) {
    EXPECT_GE(m.command.linear, 0.0);
    EXPECT_LE(m.command.linear, 1.0);
    EXPECT_LE(std::abs(m.command.angular), 1.3);
  }
  // The robot drives: about the mean command speed (> 0.3 m/s) times 20 s.
  const ExplorationStats s = explorationStats(r);
  EXPECT_GT(s.distance, 6.0);
}

TEST(Exploration, CommandsChangeSmoothlyAtTwentyFiveHertz) {
  const CollectConfig c = shortDrive();
  const Recording r = collectExploration(c, "short");
  for (std::size_t k = 1; k < r.records.size(); ++k) {
    const double dv = std::abs(r.records[k].command.linear - r.records[k - 1].command.linear);
    const double dw = std::abs(r.records[k].command.angular - r.records[k - 1].command.angular);
    // One command per 2 records (0.04 s): at most 2 m/s^2 * 0.04 s = 0.08 m/s and 4 * 0.04 = 0.16 rad/s.
    EXPECT_LE(dv, 0.08 + 1e-12);
    EXPECT_LE(dw, 0.16 + 1e-12);
    if (k % 2 == 1) {
      EXPECT_EQ(dv, 0.0);
      EXPECT_EQ(dw, 0.0);
    }
  }
}

TEST(Exploration, SameSeedGivesTheSameDriveBitForBit) {
  const Recording a = collectExploration(shortDrive(), "a");
  const Recording b = collectExploration(shortDrive(), "a");
  ASSERT_EQ(a.records.size(), b.records.size());
  for (std::size_t k = 0; k < a.records.size(); ++k) {
    EXPECT_EQ(a.records[k].pose.x, b.records[k].pose.x);
    EXPECT_EQ(a.records[k].pose.yaw, b.records[k].pose.yaw);
    EXPECT_EQ(a.records[k].command.angular, b.records[k].command.angular);
  }
  CollectConfig other = shortDrive();
  other.seed = 2;
  EXPECT_NE(collectExploration(other, "a").records[500].pose.x, a.records[500].pose.x);
}

TEST(Exploration, DrivesThePlantItIsGiven) {
  // The same commands on a robot that turns at 1.5x the commanded rate: the recorded motion is
  // that robot's, so a policy trained on it learns how it moves.
  const Recording plain = collectExploration(shortDrive(), "a");
  core::RobotConfig fast_turning;
  fast_turning.turn_efficiency = 1.5;
  const Recording fast = collectExploration(shortDrive(), "a", fast_turning);
  ASSERT_EQ(plain.records.size(), fast.records.size());
  const auto turned = [](const Recording& r) {
    double sum = 0.0;
    for (std::size_t k = 1; k < r.records.size(); ++k)
      sum += std::abs(std::remainder(r.records[k].pose.yaw - r.records[k - 1].pose.yaw, 2.0 * M_PI));
    return sum;
  };
  for (std::size_t k = 0; k < plain.records.size(); ++k)
    ASSERT_EQ(plain.records[k].command.angular, fast.records[k].command.angular);
  EXPECT_GT(turned(fast), 1.35 * turned(plain));
  EXPECT_LT(turned(fast), 1.6 * turned(plain));
  // Each recording names its plant.
  EXPECT_EQ(plain.plant_hash, sim::plantHash({}, {}));
  EXPECT_EQ(fast.plant_hash, sim::plantHash(fast_turning, {}));
}

TEST(Exploration, RecordingFileRoundTripsExactly) {
  const Recording r = collectExploration(shortDrive(), "short");
  const fs::path path = recordingPath(tempDir("roundtrip"), "short");
  writeRecording(path, r);
  const Recording back = readRecording(path);
  EXPECT_EQ(back.name, "short");
  EXPECT_EQ(back.collect_hash, collectHash(shortDrive()));
  EXPECT_EQ(back.plant_hash, sim::plantHash({}, {}));
  ASSERT_EQ(back.records.size(), r.records.size());
  for (std::size_t k = 0; k < r.records.size(); ++k) {
    EXPECT_EQ(back.records[k].pose.y, r.records[k].pose.y);
    EXPECT_EQ(back.records[k].vy, r.records[k].vy);
    EXPECT_EQ(back.records[k].command.linear, r.records[k].command.linear);
  }
}

TEST(Exploration, MalformedRecordingNamesTheFileAndLine) {
  const fs::path dir = tempDir("malformed");
  const auto errorOf = [&](const std::string& text) {
    core::writeFileAtomic(dir / "r.csv", text);
    try {
      readRecording(dir / "r.csv");
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string header = "# barnbench lflh exploration 1\n# name: x\n# collect_hash: 0x1f\n# rate: 50\nt,x,y,yaw,v,vy,w,cmd_v,cmd_w\n";
  EXPECT_THAT(errorOf("t,x\n"), HasSubstr("r.csv:1: not an LfLH recording"));
  EXPECT_THAT(errorOf(header + "0,0,0,0,0,0,0,0,0\n0,0,0,0,0,0,0,0\n"), HasSubstr("r.csv:7: expected 9"));
  EXPECT_THAT(errorOf(header + "0,0,0,0,0,0,0,0,0\n0,0,0,0,0,0,0,0,0,0\n"), HasSubstr("r.csv:7: column 9"));
  EXPECT_THAT(errorOf(header + "0,0,0,0,abc,0,0,0,0\n"), HasSubstr("r.csv:6: column 5: expected a finite number"));
  EXPECT_THAT(errorOf(header + "0,0,0,0,0,0,0,0,0\n"), HasSubstr("fewer than 2 records"));
  std::string planted = header;
  planted.insert(planted.find("# rate"), "# plant_hash: 0x0\n");
  EXPECT_THAT(errorOf(planted + "0,0,0,0,0,0,0,0,0\n1,0,0,0,0,0,0,0,0\n"), HasSubstr("r.csv:4: plant_hash: expected a nonzero"));
}

TEST(Exploration, ARecordingWrittenBeforeThePlantHashReadsWithAnUnknownPlant) {
  const fs::path dir = tempDir("unplanted");
  core::writeFileAtomic(dir / "r.csv", "# barnbench lflh exploration 1\n# name: x\n# collect_hash: 0x1f\n# rate: 50\n"
                                       "t,x,y,yaw,v,vy,w,cmd_v,cmd_w\n0,0,0,0,0,0,0,0,0\n0.02,0,0,0,0,0,0,0,0\n");
  const Recording r = readRecording(dir / "r.csv");
  EXPECT_EQ(r.plant_hash, 0u);
  EXPECT_EQ(r.records.size(), 2u);
}

TEST(LflhPipelineConfig, UnknownKeysAndBadValuesAreReportedWithTheirPath) {
  const auto errorOf = [](const std::string& yaml) {
    try {
      LflhPipelineConfig c = core::readConfig<LflhPipelineConfig>(core::ConfigNode::parseString(yaml, "lflh.yaml"));
      core::Errors errors("lflh.yaml");
      validate(c, errors);
      errors.throwIfAny();
    } catch (const core::InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(errorOf("name: x\ncollect: {max_speed: 2.0}\n"), "no error");
  EXPECT_THAT(errorOf("train: {epochz: 3}\n"), HasSubstr("train.epochz: unknown key"));
  EXPECT_THAT(errorOf("collect: {max_speed: 3.0}\n"), HasSubstr("collect.max_speed: must be in"));
  EXPECT_THAT(errorOf("hallucination: {clearance_min: 0.2, clearance_max: 0.1}\n"), HasSubstr("hallucination.clearance_max"));
  EXPECT_THAT(errorOf("train: {batch_size: 0}\n"), HasSubstr("train.batch_size"));
  EXPECT_EQ(errorOf("train: {activation: leaky_relu, leaky_slope: 0.01}\n"), "no error");
  EXPECT_THAT(errorOf("train: {activation: tanh}\n"), HasSubstr("train.activation: expected one of relu, leaky_relu"));
  EXPECT_THAT(errorOf("train: {leaky_slope: 1.0}\n"), HasSubstr("train.leaky_slope: must be in (0, 1)"));
}

TEST(LflhPipelineConfig, ShippedConfigsLoadAndDifferInSpeed) {
  const LflhPipelineConfig slow = readLflhPipelineConfig(std::string(BARN_SOURCE_DIR) + "/configs/lflh/1ms.yaml");
  const LflhPipelineConfig fast = readLflhPipelineConfig(std::string(BARN_SOURCE_DIR) + "/configs/lflh/2ms.yaml");
  EXPECT_EQ(slow.name, "lflh_1ms");
  EXPECT_EQ(fast.name, "lflh_2ms");
  EXPECT_EQ(slow.collect.max_speed, 1.0);
  EXPECT_EQ(fast.collect.max_speed, 2.0);
  EXPECT_NE(configHash(slow), configHash(fast));
}

TEST(LflhPipelineConfig, TheShippedConfigsTrainAsThePublishedPipeline) {
  const std::string dir = std::string(BARN_SOURCE_DIR) + "/configs/lflh/";
  const LflhPipelineConfig slow = readLflhPipelineConfig(dir + "1ms.yaml");
  const LflhPipelineConfig fast = readLflhPipelineConfig(dir + "2ms.yaml");
  for (const LflhPipelineConfig* c : {&slow, &fast}) {
    EXPECT_EQ(c->train.activation, Activation::LeakyRelu);
    EXPECT_EQ(c->train.leaky_slope, 0.01);
    EXPECT_EQ(c->train.learning_rate, 3e-4);
    EXPECT_EQ(c->train.batch_size, 32);
    EXPECT_EQ(c->train.epochs, 1000);
    EXPECT_EQ(c->train.batches_per_epoch, 100);
    EXPECT_EQ(c->train.flip_probability, 0.5);
    EXPECT_EQ(c->train.range_noise, 0.03);
    // The alternatives of the constraining placement reach the speed limit.
    EXPECT_EQ(c->hallucination.alternative_speed, c->collect.max_speed);
  }
  EXPECT_EQ(slow.train.range_clip, 2.0);
  EXPECT_EQ(fast.train.range_clip, 2.5);
  EXPECT_TRUE(slow.also_train_on.empty());
  // The 2 m/s policy also learns from the 1 m/s data; the file it names exists and differs.
  ASSERT_EQ(fast.also_train_on, (std::vector<std::string>{"1ms.yaml"}));
  EXPECT_EQ(readLflhPipelineConfig(dir + fast.also_train_on[0]).name, slow.name);
}

}  // namespace
}  // namespace barn::learning
