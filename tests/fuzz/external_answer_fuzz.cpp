// Fuzz target: the answers an external controller program sends back (protocol v1,
// external::readCommandAnswer and readResetAnswer): one line of JSON, read as SAX
// events with at most 8 members and 64 parameters of at most 128-byte names.
//
// Bad input must end in external::ProtocolError, the reader's documented rejection (the
// controller turns it into the episode's error), with a message short enough for a CSV cell. An
// answer that reads must keep the protocol's bounds (finite v and w, at most 64 distinct
// parameters of finite values), must say what a plain JSON parser says the line holds, and must
// read again to the same answer when written back as JSON.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <set>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "barn/external/external_protocol.hpp"
#include "fuzz_check.hpp"

namespace {

using namespace barn::controllers;
namespace external = barn::external;
using Json = nlohmann::ordered_json;

// A refusal's message: the answer is quoted up to 200 characters and names up to 128 bytes,
// so a longer message carries the input unbounded (it ends up in episodes.csv's error column).
constexpr std::size_t kMaxMessageBytes = 1024;

void checkMessage(const external::ProtocolError& e, const std::string& line) {
  const std::string message = e.what();
  if (message.size() > kMaxMessageBytes)
    barn::fuzz::propertyFailed("a refusal's message is longer than 1024 bytes", line, message.substr(0, 4096));
}

std::string describe(const external::CommandAnswer& a) {
  std::string text = "v=" + std::to_string(a.command.linear) + " w=" + std::to_string(a.command.angular) +
                     " state='" + a.state + "' params:";
  for (const auto& [key, value] : a.params) text += " " + key + "=" + std::to_string(value);
  return text;
}

bool same(const external::CommandAnswer& a, const external::CommandAnswer& b) {
  return a.command.linear == b.command.linear && a.command.angular == b.command.angular && a.state == b.state &&
         a.params == b.params;
}

// The answer as a plain (DOM) JSON parse reads it; false if that parse refuses the line or
// the line is not an object of the answer's shape.
bool readPlain(const std::string& line, external::CommandAnswer& out) {
  const Json j = Json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded() || !j.is_object() || !j.contains("v") || !j.contains("w")) return false;
  if (!j.at("v").is_number() || !j.at("w").is_number()) return false;
  out.command = {j.at("v").get<double>(), j.at("w").get<double>()};
  if (j.contains("state")) {
    if (!j.at("state").is_string()) return false;
    out.state = j.at("state").get<std::string>();
  }
  if (j.contains("params")) {
    if (!j.at("params").is_object()) return false;
    for (const auto& [key, value] : j.at("params").items()) {
      if (!value.is_number()) return false;
      out.params.emplace_back(key, value.get<double>());
    }
  }
  return true;
}

void commandAnswer(const std::string& line) {
  external::CommandAnswer answer;
  try {
    answer = external::readCommandAnswer(line);
  } catch (const external::ProtocolError& e) {
    checkMessage(e, line);
    return;
  }
  // The protocol's bounds.
  if (!std::isfinite(answer.command.linear) || !std::isfinite(answer.command.angular))
    barn::fuzz::propertyFailed("an accepted answer has a number that is not finite", line, describe(answer));
  if (answer.params.size() > 64)
    barn::fuzz::propertyFailed("an accepted answer has more than 64 parameters", line, describe(answer));
  std::set<std::string> keys;
  for (const auto& [key, value] : answer.params) {
    if (!keys.insert(key).second)
      barn::fuzz::propertyFailed("an accepted answer repeats a parameter", line, describe(answer));
    if (key.size() > 128) barn::fuzz::propertyFailed("an accepted parameter name is over 128 bytes", line, key);
    if (!std::isfinite(value))
      barn::fuzz::propertyFailed("an accepted parameter is not finite", line, describe(answer));
  }
  // What a plain JSON parser reads from the same line (no duplicates were accepted, so it has
  // nothing to choose between).
  external::CommandAnswer plain;
  if (!readPlain(line, plain))
    barn::fuzz::propertyFailed("the reader accepted a line a JSON parser refuses", line, describe(answer));
  if (!same(plain, answer)) barn::fuzz::propertyFailed("the reader and a JSON parser disagree", describe(plain), describe(answer));
  // Written back as JSON, the answer reads again to itself.
  Json written = {{"v", answer.command.linear}, {"w", answer.command.angular}};
  if (!answer.state.empty()) written["state"] = answer.state;
  if (!answer.params.empty()) {
    written["params"] = Json::object();
    for (const auto& [key, value] : answer.params) written["params"][key] = value;
  }
  const std::string text = written.dump();
  external::CommandAnswer again;
  try {
    again = external::readCommandAnswer(text);
  } catch (const external::ProtocolError& e) {
    barn::fuzz::propertyFailed("an accepted answer written back does not read", text, e.what());
  }
  if (!same(answer, again))
    barn::fuzz::propertyFailed("an accepted answer written back reads differently", describe(answer), describe(again));
}

void resetAnswer(const std::string& line) {
  try {
    external::readResetAnswer(line);
  } catch (const external::ProtocolError& e) {
    checkMessage(e, line);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string line(reinterpret_cast<const char*>(data), size);
  commandAnswer(line);
  resetAnswer(line);
  return 0;
}
