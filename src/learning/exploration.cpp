#include "barn/learning/exploration.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "barn/core/config.hpp"
#include "barn/core/rng.hpp"
#include "barn/core/text_io.hpp"
#include "barn/sim/simulator.hpp"

namespace barn::learning {

namespace {

constexpr const char* kMagic = "# barnbench lflh exploration 1";
constexpr const char* kColumns = "t,x,y,yaw,v,vy,w,cmd_v,cmd_w";

double moveToward(double value, double target, double max_step) {
  return value + std::clamp(target - value, -max_step, max_step);
}

}  // namespace

Recording collectExploration(const CollectConfig& config, const std::string& name, const core::RobotConfig& robot,
                             const sim::PhysicsConfig& physics) {
  const sim::ObstacleField empty;
  sim::Simulator simulator(empty, robot, physics, {0.0, 0.0, 0.0});
  core::Rng rng(config.seed);

  // Physics steps per record and per command: whole numbers, so records fall on physics steps.
  const long steps_per_record = std::max(1L, std::lround(physics.rate / config.record_rate));
  const long records_per_command = std::max(1L, std::lround(config.record_rate / config.command_rate));
  const double record_dt = static_cast<double>(steps_per_record) * physics.dt();
  const double command_dt = static_cast<double>(records_per_command) * record_dt;
  const long record_count = std::lround(config.duration / record_dt) + 1;

  Recording recording;
  recording.name = name;
  recording.collect_hash = collectHash(config);
  recording.plant_hash = sim::plantHash(robot, physics);
  recording.rate = 1.0 / record_dt;
  recording.records.reserve(static_cast<std::size_t>(record_count));

  core::Twist target, command;
  double hold_left = 0.0;  // [s] until a new target is drawn
  const double log_hold_min = std::log(config.min_hold);
  const double log_hold_max = std::log(config.max_hold);
  for (long k = 0; k < record_count; ++k) {
    if (k % records_per_command == 0) {
      if (hold_left <= 0.0) {
        // A new hold: often the top speed (the original 1 m/s log spends 44 % of its time
        // there), otherwise uniform; yaw rate uniform, sometimes straight.
        target.linear = rng.uniform01() < config.top_speed_share
                            ? config.max_speed
                            : config.min_speed + (config.max_speed - config.min_speed) * rng.uniform01();
        target.angular = rng.uniform01() < config.straight_share
                             ? 0.0
                             : config.max_turn_rate * (2.0 * rng.uniform01() - 1.0);
        hold_left = std::exp(log_hold_min + (log_hold_max - log_hold_min) * rng.uniform01());
      }
      hold_left -= command_dt;
      // Smooth transitions: the command ramps toward the target instead of jumping.
      command.linear = moveToward(command.linear, target.linear, config.linear_slew * command_dt);
      command.angular = moveToward(command.angular, target.angular, config.angular_slew * command_dt);
      simulator.command(command);
    }
    MotionRecord record;
    record.t = static_cast<double>(k) * record_dt;
    record.pose = simulator.pose();
    record.v = simulator.forwardSpeed();
    record.vy = simulator.sidewaysSpeed();
    record.w = simulator.yawRate();
    record.command = command;
    recording.records.push_back(record);
    for (long s = 0; s < steps_per_record; ++s) simulator.step();
  }
  return recording;
}

std::filesystem::path recordingPath(const std::filesystem::path& dir, const std::string& name) {
  return dir / ("exploration_" + name + ".csv");
}

void writeRecording(const std::filesystem::path& path, const Recording& recording) {
  std::string text;
  text.reserve(recording.records.size() * 160);
  text += kMagic;
  text += "\n# name: " + recording.name + "\n# collect_hash: " + core::formatHex(recording.collect_hash) + "\n";
  if (recording.plant_hash != 0) text += "# plant_hash: " + core::formatHex(recording.plant_hash) + "\n";
  text += "# rate: " + core::formatDouble(recording.rate) + "\n";
  text += kColumns;
  text += '\n';
  for (const MotionRecord& r : recording.records) {
    for (double value : {r.t, r.pose.x, r.pose.y, r.pose.yaw, r.v, r.vy, r.w, r.command.linear}) {
      text += core::formatDouble(value);
      text += ',';
    }
    text += core::formatDouble(r.command.angular);
    text += '\n';
  }
  core::writeFileAtomic(path, text);
}

Recording readRecording(const std::filesystem::path& path) {
  const std::string text = core::readTextFile(path);
  std::istringstream in(text);
  std::string line;
  int line_number = 0;
  const auto fail = [&](const std::string& message) {
    throw core::InputError(path.string() + ":" + std::to_string(line_number) + ": " + message);
  };
  const auto next = [&] {
    ++line_number;
    return static_cast<bool>(std::getline(in, line));
  };
  if (!next() || line != kMagic) fail(std::string("not an LfLH recording (expected '") + kMagic + "')");
  Recording recording;
  bool has_hash = false, has_rate = false;
  while (next() && line.rfind("# ", 0) == 0) {
    const auto colon = line.find(": ");
    if (colon == std::string::npos) fail("expected '# key: value'");
    const std::string key = line.substr(2, colon - 2);
    const std::string value = line.substr(colon + 2);
    if (key == "name") {
      recording.name = value;
    } else if (key == "collect_hash") {
      if (!core::parseHex(value, recording.collect_hash)) fail("collect_hash: expected a hexadecimal number");
      has_hash = true;
    } else if (key == "plant_hash") {
      if (!core::parseHex(value, recording.plant_hash) || recording.plant_hash == 0) fail("plant_hash: expected a nonzero hexadecimal number");
    } else if (key == "rate") {
      if (!core::parseDouble(value, recording.rate) || !(recording.rate > 0.0)) fail("rate: expected a positive number");
      has_rate = true;
    } else {
      fail("unknown header key '" + key + "'");
    }
  }
  if (!has_hash || !has_rate) fail("header: collect_hash and rate are required");
  if (line != kColumns) fail(std::string("expected the column line '") + kColumns + "'");
  while (next()) {
    if (line.empty()) continue;
    double values[9];
    std::size_t start = 0;
    for (int c = 0; c < 9; ++c) {
      const std::size_t comma = c < 8 ? line.find(',', start) : line.size();
      if (comma == std::string::npos) fail("expected 9 comma-separated numbers");
      // The last field runs to the end of the line, so a tenth column fails to parse here.
      if (!core::parseDouble(std::string_view(line).substr(start, comma - start), values[c]) || !std::isfinite(values[c]))
        fail("column " + std::to_string(c + 1) + ": expected a finite number");
      start = comma + 1;
    }
    MotionRecord r;
    r.t = values[0];
    r.pose = {values[1], values[2], values[3]};
    r.v = values[4];
    r.vy = values[5];
    r.w = values[6];
    r.command = {values[7], values[8]};
    recording.records.push_back(r);
  }
  if (recording.records.size() < 2) throw core::InputError(path.string() + ": fewer than 2 records");
  return recording;
}

ExplorationStats explorationStats(const Recording& recording) {
  ExplorationStats s;
  s.records = recording.records.size();
  if (recording.records.empty()) return s;
  s.duration = recording.records.back().t - recording.records.front().t;
  s.cmd_v_min = s.cmd_v_max = recording.records.front().command.linear;
  s.cmd_w_min = s.cmd_w_max = recording.records.front().command.angular;
  double speed_sum = 0.0;
  for (std::size_t k = 0; k < recording.records.size(); ++k) {
    const MotionRecord& r = recording.records[k];
    s.cmd_v_min = std::min(s.cmd_v_min, r.command.linear);
    s.cmd_v_max = std::max(s.cmd_v_max, r.command.linear);
    s.cmd_w_min = std::min(s.cmd_w_min, r.command.angular);
    s.cmd_w_max = std::max(s.cmd_w_max, r.command.angular);
    speed_sum += r.v;
    if (k > 0) s.distance += (r.pose.position() - recording.records[k - 1].pose.position()).norm();
  }
  std::size_t top = 0;
  for (const MotionRecord& r : recording.records) top += r.command.linear >= 0.99 * s.cmd_v_max ? 1 : 0;
  s.top_speed_share = static_cast<double>(top) / static_cast<double>(s.records);
  s.mean_speed = speed_sum / static_cast<double>(s.records);
  return s;
}

}  // namespace barn::learning
