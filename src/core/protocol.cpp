#include "barn/core/protocol.hpp"

#include <algorithm>

#include "barn/core/errors.hpp"

namespace barn::core {

std::vector<std::string> protocolNames() { return {"barn2023", "barn2024"}; }

Protocol protocolPreset(std::string_view name) {
  Protocol p;  // defaults are barn2023: BARN 2022 and 2023 (run.py until TBC d17f00d)
  if (name == "barn2023") return p;
  if (name == "barn2024") {
    // From 2024 the start is on the corridor centre line and the lower clip is 2 * OT.
    p.name = "barn2024";
    p.start_x = -2.25;
    p.clip_low = 2.0;
    return p;
  }
  throw InputError("unknown protocol '" + std::string(name) + "' (known: barn2023, barn2024)");
}

Eigen::Vector2d otPathPoint(Cell cell) {
  return {-4.575 + 0.15 * cell.row, 5.075 + 0.15 * cell.col};
}

double referencePathLength(const std::vector<Cell>& path, const Protocol& protocol) {
  double length = 0.0;
  Eigen::Vector2d previous = protocol.start();
  for (const Cell& cell : path) {
    const Eigen::Vector2d point = otPathPoint(cell);
    length += (point - previous).norm();
    previous = point;
  }
  length += (protocol.goal() - previous).norm();
  return length;
}

double optimalTime(const std::vector<Cell>& path, const Protocol& protocol) {
  return referencePathLength(path, protocol) / protocol.reference_speed;
}

double barnScore(bool success, double actual_time, double optimal_time, const Protocol& protocol) {
  if (!success) return 0.0;
  const double clipped = std::clamp(actual_time, protocol.clip_low * optimal_time,
                                    protocol.clip_high * optimal_time);
  return optimal_time / clipped;
}

}  // namespace barn::core
