#pragma once
/// LfLH step 1: drive the simulated Jackal with random smooth commands in empty space and log
/// its motion, as the original explorer did on the real robot.
///
/// The recording file (`exploration_<name>.csv` in the data folder) is plain CSV:
///
///     # barnbench lflh exploration 1
///     # name: lflh_1ms
///     # collect_hash: 0x1234abcd...        (FNV-1a of the effective `collect` section)
///     # plant_hash: 0x5678ef01...          (sim::plantHash() of the robot and physics driven)
///     # rate: 50
///     t,x,y,yaw,v,vy,w,cmd_v,cmd_w
///     0,0,0,0,0,0,0,0.04,-0.08
///
/// plant_hash is optional on reading (recordings written before it read as 0, unknown).
/// t [s], pose x y [m] yaw [rad] in the start frame, body velocity v (forward) vy (sideways)
/// [m/s] and w [rad/s], and the cmd_vel in force from that record on, cmd_v [m/s] cmd_w [rad/s].

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "barn/core/robot_config.hpp"
#include "barn/core/types.hpp"
#include "barn/learning/lflh_config.hpp"
#include "barn/sim/simulator.hpp"

namespace barn::learning {

/// One logged instant.
struct MotionRecord {
  double t = 0.0;        // [s]
  core::Pose2 pose;      // [m, m, rad] start frame
  double v = 0.0;        // [m/s] forward body speed
  double vy = 0.0;       // [m/s] sideways body speed (slip)
  double w = 0.0;        // [rad/s] yaw rate
  core::Twist command;   // the cmd_vel sent at this record (held until the next one)
};

/// A continuous drive at a fixed record rate.
struct Recording {
  std::string name;              // the config's name
  std::uint64_t collect_hash = 0;  // collectHash() of the settings that made it
  std::uint64_t plant_hash = 0;  // sim::plantHash() of the robot it drove (0: unknown)
  double rate = 50.0;            // [Hz] records per second
  std::vector<MotionRecord> records;
};

/// Drives the Jackal (by default core::RobotConfig, sim::PhysicsConfig: the default plant) in an
/// empty world for `config.duration` seconds. A policy learns how this robot moves, so it is
/// trained on the plant it will drive. Deterministic: the same configs give the same records bit
/// for bit.
Recording collectExploration(const CollectConfig& config, const std::string& name, const core::RobotConfig& robot = {},
                             const sim::PhysicsConfig& physics = {});

/// The recording file of config `name` inside `dir`.
std::filesystem::path recordingPath(const std::filesystem::path& dir, const std::string& name);
/// Writes the CSV (atomically; numbers round-trip exactly).
void writeRecording(const std::filesystem::path& path, const Recording& recording);
/// Reads a recording; InputError naming the file and line for anything malformed.
Recording readRecording(const std::filesystem::path& path);

/// Statistics of the commands, to compare with the original logs.
struct ExplorationStats {
  std::size_t records = 0;
  double duration = 0.0;          // [s]
  double cmd_v_min = 0.0, cmd_v_max = 0.0;  // [m/s]
  double top_speed_share = 0.0;   // [-] records whose cmd_v is within 1 % of the maximum
  double cmd_w_min = 0.0, cmd_w_max = 0.0;  // [rad/s]
  double mean_speed = 0.0;        // [m/s] of the body
  double distance = 0.0;          // [m] driven
};
ExplorationStats explorationStats(const Recording& recording);

}  // namespace barn::learning
