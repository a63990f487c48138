#pragma once
/// The official BARN episode protocol (run.py) as named presets, and the optimal time OT.

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/core/grid.hpp"

namespace barn::core {

/// An edition of the BARN challenge's protocol. Config files name it (`protocol: barn2023`);
/// it is resolved once, when the config is read, and carried as this enum from then on.
enum class ProtocolName {
  Barn2023,  ///< BARN 2022 and 2023 (the default)
  Barn2024,  ///< BARN 2024 on: start on the corridor centre line, lower clip 2 x OT
};
/// The config names, in enum order: "barn2023", "barn2024" (makes ProtocolName a NamedEnum).
std::span<const std::string_view> enumNames(ProtocolName);
/// The config name of `name`, for labels and messages.
std::string_view toString(ProtocolName name);

/// Start, goal and scoring rules of one edition of the BARN challenge.
struct Protocol {
  ProtocolName name = ProtocolName::Barn2023;
  double start_x = -2.0;          // [m] world frame; -2.25 from BARN 2024
  double start_y = 3.0;           // [m]
  double start_yaw = 1.57;        // [rad] run.py uses 1.57, not pi/2
  double goal_dx = 0.0;           // [m] goal relative to the start
  double goal_dy = 10.0;          // [m]
  double success_radius = 1.0;    // [m] robot centre to goal
  double timeout = 100.0;         // [s] of simulated time after the timer starts
  double start_distance = 0.1;    // [m] the timer starts once the robot is this far from the start
  double check_period = 0.1;      // [s] status polled at 10 Hz of simulated time
  double clip_low = 4.0;          // [x OT] lower clip of AT: 4 (2022-23), 2 (2024+)
  double clip_high = 8.0;         // [x OT] upper clip of AT
  double reference_speed = 2.0;   // [m/s] OT = reference path length / this (Jackal max speed)

  Eigen::Vector2d start() const { return {start_x, start_y}; }
  Eigen::Vector2d goal() const { return {start_x + goal_dx, start_y + goal_dy}; }
  /// The best score a trial can get (barnScore clips AT from below at clip_low * OT): 0.25
  /// for barn2023, 0.5 for barn2024.
  double maxScore() const { return 1.0 / clip_low; }
  /// The score of a success at or beyond the upper clip, the least a success scores.
  double minSuccessScore() const { return 1.0 / clip_high; }
};

/// Names of the presets, default first.
std::vector<std::string> protocolNames();
/// The preset of the edition `name`.
Protocol protocolPreset(ProtocolName name);
/// The preset named `name` ("barn2023", "barn2024"), for names given on a command line;
/// throws InputError on an unknown name.
Protocol protocolPreset(std::string_view name);

/// run.py's path_coord_to_gazebo_coord: (-4.575 + 0.15 r, 5.075 + 0.15 c). This is offset by
/// (-0.15, -0.10) m from the true cell centres; BARN uses it for OT only, and so do we.
Eigen::Vector2d otPathPoint(Cell cell);

/// Length of run.py's reference polyline: start -> every path cell (duplicate included) -> goal. [m]
double referencePathLength(const std::vector<Cell>& path, const Protocol& protocol);

/// OT = reference path length / 2 m/s. [s]
double optimalTime(const std::vector<Cell>& path, const Protocol& protocol);

/// BARN score of one trial: success * OT / clip(AT, clip_low * OT, clip_high * OT).
double barnScore(bool success, double actual_time, double optimal_time, const Protocol& protocol);

}  // namespace barn::core
