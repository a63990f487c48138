#include "barn/core/protocol.hpp"

#include <algorithm>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"

namespace barn::core {

std::span<const std::string_view> enumNames(ProtocolName) {
  static constexpr std::string_view kNames[] = {"barn2023", "barn2024"};
  return kNames;
}

std::string_view toString(ProtocolName name) { return enumNames(name)[static_cast<std::size_t>(name)]; }

std::vector<std::string> protocolNames() {
  const std::span<const std::string_view> names = enumNames(ProtocolName{});
  return {names.begin(), names.end()};
}

Protocol protocolPreset(ProtocolName name) {
  Protocol p;  // defaults are barn2023: BARN 2022 and 2023 (run.py until TBC d17f00d)
  if (name == ProtocolName::Barn2024) {
    // From 2024 the start is on the corridor centre line and the lower clip is 2 * OT.
    p.name = ProtocolName::Barn2024;
    p.start_x = -2.25;
    p.clip_low = 2.0;
  }
  return p;
}

Protocol protocolPreset(std::string_view name) {
  ProtocolName edition{};
  if (enumFromName(name, edition)) return protocolPreset(edition);
  std::string known;
  for (const std::string& n : protocolNames()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown protocol '" + std::string(name) + "' (known: " + known + ")");
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
