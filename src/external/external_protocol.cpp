#include "barn/external/external_protocol.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <variant>

#include <nlohmann/json.hpp>

#include "barn/core/base64.hpp"

namespace barn::external {

namespace {

// Members keep the order they are written in, as the protocol's documentation shows them.
using Json = nlohmann::ordered_json;

Json pose(const core::Pose2& p) { return Json::array({p.x, p.y, p.yaw}); }

// The answer as quoted in a message: garbage can be long, and the message ends up in a CSV cell.
std::string quoted(std::string_view line) {
  constexpr std::size_t kShown = 200;  // [characters]
  return "'" + std::string(line.substr(0, kShown)) + (line.size() > kShown ? "...'" : "'");
}

Json costGrid(const controllers::CostGrid& grid) {
  const std::size_t cells = static_cast<std::size_t>(grid.width) * static_cast<std::size_t>(grid.height);
  return Json{{"origin", Json::array({grid.origin.x(), grid.origin.y()})},
              {"resolution", grid.resolution},
              {"width", grid.width},
              {"height", grid.height},
              {"costs", core::base64Encode({grid.costs, cells})}};
}

// An answer is one flat JSON object of a few members, plus, in a command, the object "params"
// of numbers. Read as SAX events, so duplicates, nesting and an oversized answer are refused at
// the first offending token instead of after building a tree.
using Scalar = std::variant<std::nullptr_t, bool, double, std::string>;

struct AnswerReader : nlohmann::json_sax<Json> {
  static constexpr std::size_t kMaxMembers = 8;  // more than any answer has

  std::vector<std::pair<std::string, Scalar>> members;
  std::vector<std::pair<std::string, double>> params;
  std::string error;

  bool null() override { return value(nullptr); }
  bool boolean(bool b) override { return value(b); }
  bool number_integer(number_integer_t n) override { return value(static_cast<double>(n)); }
  bool number_unsigned(number_unsigned_t n) override { return value(static_cast<double>(n)); }
  bool number_float(number_float_t x, const string_t&) override { return value(x); }
  bool string(string_t& s) override { return value(std::move(s)); }
  bool binary(binary_t&) override { return fail("unexpected binary value"); }
  bool start_object(std::size_t) override {
    ++depth_;
    if (depth_ == 1) return true;
    if (depth_ == 2 && pending_key_ == "params") {
      in_params_ = true;
      params_seen_ = true;
      return true;
    }
    return fail("\"" + pending_key_ + "\" must not be an object");
  }
  bool end_object() override {
    if (depth_ == 2) in_params_ = false;
    --depth_;
    return true;
  }
  bool start_array(std::size_t) override {
    if (depth_ == 0) return fail("the answer must be a JSON object");
    return fail("\"" + pending_key_ + "\" must not be an array");
  }
  bool end_array() override { return true; }
  bool key(string_t& name) override {
    if (name.size() > kMaxNameBytes) return fail("a member name is longer than 128 bytes");
    if (in_params_) {
      if (params.size() == kMaxParams) return fail("more than 64 parameters in \"params\"");
      for (const auto& p : params)
        if (p.first == name) return fail("duplicate parameter \"" + name + "\" in \"params\"");
    } else {
      if (members.size() + (params_seen_ ? 1 : 0) == kMaxMembers) return fail("too many members");
      for (const auto& m : members)
        if (m.first == name) return fail("duplicate member \"" + name + "\"");
      if (name == "params" && params_seen_) return fail("duplicate member \"params\"");
    }
    pending_key_ = std::move(name);
    return true;
  }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) override {
    if (error.empty()) error = "malformed answer at byte " + std::to_string(position) + " (" + shortReason(e.what()) + ")";
    return false;
  }

 private:
  bool value(Scalar v) {
    if (depth_ == 0) return fail("the answer must be a JSON object");
    if (std::holds_alternative<double>(v) && !std::isfinite(std::get<double>(v)))
      return fail("\"" + pending_key_ + "\": number out of range");
    if (depth_ == 1 && pending_key_ == "params") return fail("\"params\" must be an object of numbers");
    if (in_params_) {
      if (!std::holds_alternative<double>(v)) return fail("parameter \"" + pending_key_ + "\" must be a number");
      params.emplace_back(std::move(pending_key_), std::get<double>(v));
      return true;
    }
    members.emplace_back(std::move(pending_key_), std::move(v));
    return true;
  }
  bool fail(std::string message) {
    if (error.empty()) error = std::move(message);
    return false;
  }
  // nlohmann's message without its "[json.exception.parse_error.101] parse error at line 1,
  // column 5: " prefix, cut to kShownReason: it ends with the token last read ("last read:
  // '...'"), which is as long as the answer for an unterminated string or a number of many
  // digits.
  static std::string shortReason(std::string what) {
    constexpr std::size_t kShownReason = 200;  // [characters]
    const std::size_t colon = what.find(": ", what.find("column"));
    if (colon != std::string::npos) what.erase(0, colon + 2);
    if (what.size() > kShownReason) what = what.substr(0, kShownReason) + "...";
    return what;
  }

  int depth_ = 0;
  bool in_params_ = false;
  bool params_seen_ = false;
  std::string pending_key_;
};

AnswerReader read(std::string_view line) {
  AnswerReader reader;
  const bool ok = Json::sax_parse(line.begin(), line.end(), &reader);
  if (!ok) throw ProtocolError(reader.error + " in the answer " + quoted(line));
  return reader;
}

}  // namespace

std::string resetMessage(const controllers::EpisodeInfo& info, double period) {
  const core::LidarConfig& lidar = info.lidar;
  const core::RobotConfig& robot = info.robot;
  const Json message = {
      {"type", "reset"},
      {"protocol", kProtocolVersion},
      {"start", pose(info.start)},
      {"goal", Json::array({info.goal.x(), info.goal.y()})},
      {"goal_tolerance", info.goal_tolerance},
      {"seed", info.seed},  // an integer up to 2^64 - 1, written exactly
      {"period", period},
      {"lidar",
       {{"angle_min", lidar.angle_min},
        {"angle_increment", lidar.angleIncrement()},
        {"beams", lidar.beams},
        {"range_min", lidar.range_min},
        {"range_max", lidar.range_max},
        {"rate", lidar.rate},
        {"offset", Json::array({lidar.mount_x, lidar.mount_y})}}},
      {"robot",
       {{"max_linear_speed", robot.max_linear_speed},
        {"max_linear_accel", robot.max_linear_accel},
        {"max_angular_speed", robot.max_angular_speed},
        {"max_angular_accel", robot.max_angular_accel},
        {"footprint_length", robot.footprint_length},
        {"footprint_width", robot.footprint_width},
        {"cmd_timeout", robot.cmd_timeout}}}};
  return message.dump();
}

std::string observationMessage(const controllers::Observation& obs, CostmapsSent& sent) {
  Json scan = Json::array();
  if (obs.scan) {
    scan.get_ref<Json::array_t&>().reserve(obs.scan->ranges.size());
    for (const double range : obs.scan->ranges) scan.push_back(range);  // +inf (no return) -> null
  }
  Json message = {{"type", "observation"},
                  {"time", obs.time},
                  {"scan", std::move(scan)},
                  {"pose", pose(obs.odom_pose)},
                  {"scan_pose", pose(obs.scan_odom_pose)},
                  {"twist", Json::array({obs.odom_twist.linear, obs.odom_twist.angular})},
                  {"goal", Json::array({obs.goal.x(), obs.goal.y()})}};
  if (obs.global_plan) {
    Json poses = Json::array();
    for (const core::Pose2& p : obs.global_plan->poses) poses.push_back(pose(p));
    message["global_plan"] = {{"stamp", obs.global_plan->stamp}, {"poses", std::move(poses)}};
  }
  // A costmap goes out when it changed since the last one this program was sent.
  const auto costmap = [&](const char* name, const controllers::CostGrid* grid, std::optional<std::uint64_t>& last) {
    if (!grid || last == grid->version) return;
    message[name] = costGrid(*grid);
    last = grid->version;
  };
  costmap("local_costmap", obs.local_costmap, sent.local);
  costmap("global_costmap", obs.global_costmap, sent.global);
  return message.dump();
}

void readResetAnswer(std::string_view line) {
  const AnswerReader answer = read(line);
  const bool* ok = nullptr;
  const std::string* reason = nullptr;
  for (const auto& [name, value] : answer.members) {
    if (name == "ok" && std::holds_alternative<bool>(value)) ok = &std::get<bool>(value);
    else if (name == "error" && std::holds_alternative<std::string>(value)) reason = &std::get<std::string>(value);
    else throw ProtocolError("unexpected member \"" + name + "\" in the answer to reset (expected {\"ok\": true})");
  }
  if (!answer.params.empty()) throw ProtocolError("unexpected member \"params\" in the answer to reset");
  if (!ok) throw ProtocolError("the answer to reset has no \"ok\": true or false");
  if (!*ok) throw ProtocolError("the program refused the episode: " + (reason ? *reason : std::string("no reason given")));
}

CommandAnswer readCommandAnswer(std::string_view line) {
  AnswerReader answer = read(line);
  CommandAnswer result;
  bool has_v = false, has_w = false;
  for (auto& [name, value] : answer.members) {
    if (name == "v" || name == "w") {
      if (!std::holds_alternative<double>(value))
        throw ProtocolError("\"" + name + "\" must be a number in the answer " + quoted(line));
      (name == "v" ? result.command.linear : result.command.angular) = std::get<double>(value);
      (name == "v" ? has_v : has_w) = true;
    } else if (name == "state" && std::holds_alternative<std::string>(value)) {
      result.state = std::move(std::get<std::string>(value));
    } else {
      throw ProtocolError("unexpected member \"" + name + "\" in the answer " + quoted(line) +
                          " (expected {\"v\": number, \"w\": number} and optionally \"state\": string, "
                          "\"params\": {key: number})");
    }
  }
  if (!has_v || !has_w)
    throw ProtocolError("the answer " + quoted(line) + " lacks \"" + (has_v ? "w" : "v") + "\"");
  result.params = std::move(answer.params);
  return result;
}

}  // namespace barn::external
