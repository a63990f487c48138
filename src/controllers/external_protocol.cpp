#include "barn/controllers/external_protocol.hpp"

#include <cmath>
#include <variant>

#include "barn/controllers/flat_json.hpp"

namespace barn::controllers::external {

namespace {

// `"key": ` for the next member of an object being written.
void key(std::string& out, const char* name) {
  if (out.back() != '{') out += ", ";
  json::appendString(out, name);
  out += ": ";
}

void number(std::string& out, const char* name, double value) {
  key(out, name);
  json::appendNumber(out, value);
}

void numbers(std::string& out, const char* name, std::initializer_list<double> values) {
  key(out, name);
  out += '[';
  bool first = true;
  for (const double v : values) {
    if (!first) out += ", ";
    json::appendNumber(out, v);
    first = false;
  }
  out += ']';
}

// The answer as quoted in a message: garbage can be long, and the message ends up in a CSV cell.
std::string quoted(std::string_view line) {
  constexpr std::size_t kShown = 200;  // [characters]
  return "'" + std::string(line.substr(0, kShown)) + (line.size() > kShown ? "...'" : "'");
}

json::FlatObject parse(std::string_view line) {
  try {
    return json::parseFlatObject(line);
  } catch (const json::ParseError& e) {
    throw ProtocolError(std::string("malformed answer (") + e.what() + "): " + quoted(line));
  }
}

}  // namespace

std::string resetMessage(const EpisodeInfo& info, double period) {
  std::string out = "{";
  key(out, "type");
  json::appendString(out, "reset");
  key(out, "protocol");
  out += std::to_string(kProtocolVersion);
  numbers(out, "start", {info.start.x, info.start.y, info.start.yaw});
  numbers(out, "goal", {info.goal.x(), info.goal.y()});
  number(out, "goal_tolerance", info.goal_tolerance);
  key(out, "seed");
  out += std::to_string(info.seed);  // an integer up to 2^64 - 1, written exactly
  number(out, "period", period);

  const core::LidarConfig& lidar = info.lidar;
  key(out, "lidar");
  out += '{';
  number(out, "angle_min", lidar.angle_min);
  number(out, "angle_increment", lidar.angleIncrement());
  key(out, "beams");
  out += std::to_string(lidar.beams);
  number(out, "range_min", lidar.range_min);
  number(out, "range_max", lidar.range_max);
  number(out, "rate", lidar.rate);
  numbers(out, "offset", {lidar.mount_x, lidar.mount_y});
  out += '}';

  const core::RobotConfig& robot = info.robot;
  key(out, "robot");
  out += '{';
  number(out, "max_linear_speed", robot.max_linear_speed);
  number(out, "max_linear_accel", robot.max_linear_accel);
  number(out, "max_angular_speed", robot.max_angular_speed);
  number(out, "max_angular_accel", robot.max_angular_accel);
  number(out, "footprint_length", robot.footprint_length);
  number(out, "footprint_width", robot.footprint_width);
  number(out, "cmd_timeout", robot.cmd_timeout);
  out += '}';
  return out + '}';
}

std::string observationMessage(const Observation& obs) {
  std::string out;
  // 720 beams of up to 24 characters each: reserve once instead of growing the string.
  out.reserve(256 + (obs.scan ? obs.scan->ranges.size() * 24 : 0));
  out += '{';
  key(out, "type");
  json::appendString(out, "observation");
  number(out, "time", obs.time);
  key(out, "scan");
  out += '[';
  if (obs.scan)
    for (std::size_t i = 0; i < obs.scan->ranges.size(); ++i) {
      if (i) out += ", ";
      json::appendNumber(out, obs.scan->ranges[i]);  // +inf (no return) -> null
    }
  out += ']';
  numbers(out, "pose", {obs.odom_pose.x, obs.odom_pose.y, obs.odom_pose.yaw});
  numbers(out, "scan_pose", {obs.scan_odom_pose.x, obs.scan_odom_pose.y, obs.scan_odom_pose.yaw});
  numbers(out, "twist", {obs.odom_twist.linear, obs.odom_twist.angular});
  numbers(out, "goal", {obs.goal.x(), obs.goal.y()});
  return out + '}';
}

void readResetAnswer(std::string_view line) {
  const json::FlatObject answer = parse(line);
  const bool* ok = nullptr;
  const std::string* reason = nullptr;
  for (const auto& [name, value] : answer) {
    if (name == "ok" && std::holds_alternative<bool>(value)) ok = &std::get<bool>(value);
    else if (name == "error" && std::holds_alternative<std::string>(value)) reason = &std::get<std::string>(value);
    else throw ProtocolError("unexpected member \"" + name + "\" in the answer to reset (expected {\"ok\": true})");
  }
  if (!ok) throw ProtocolError("the answer to reset has no \"ok\": true or false");
  if (!*ok) throw ProtocolError("the program refused the episode: " + (reason ? *reason : std::string("no reason given")));
}

CommandAnswer readCommandAnswer(std::string_view line) {
  const json::FlatObject answer = parse(line);
  CommandAnswer result;
  bool has_v = false, has_w = false;
  for (const auto& [name, value] : answer) {
    if (name == "v" || name == "w") {
      if (!std::holds_alternative<double>(value))
        throw ProtocolError("\"" + name + "\" must be a number in the answer " + quoted(line));
      (name == "v" ? result.command.linear : result.command.angular) = std::get<double>(value);
      (name == "v" ? has_v : has_w) = true;
    } else if (name == "state" && std::holds_alternative<std::string>(value)) {
      result.state = std::get<std::string>(value);
    } else {
      throw ProtocolError("unexpected member \"" + name + "\" in the answer " + quoted(line) +
                          " (expected {\"v\": number, \"w\": number} and optionally \"state\": string)");
    }
  }
  if (!has_v || !has_w)
    throw ProtocolError("the answer " + quoted(line) + " lacks \"" + (has_v ? "w" : "v") + "\"");
  return result;
}

}  // namespace barn::controllers::external
