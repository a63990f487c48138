#pragma once
/// Protocol v1 of the `external` controller: the JSON lines barn writes to a controller
/// program and the answers it reads back (docs/external_controller.md is the specification).
///
/// Every message is one JSON object on one line. Numbers are written in the shortest form that
/// reads back as the same double, so a program sees exactly the doubles a built-in controller
/// would. Pure functions: the process handling is in child_process.hpp.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "barn/controllers/controller.hpp"
#include "barn/core/types.hpp"

namespace barn::external {

inline constexpr int kProtocolVersion = 1;

/// What one command may set, in every route (the external protocol's "params" member, a Python
/// controller's dict, Env.step's params): at most kMaxParams parameters, each named in at most
/// kMaxNameBytes bytes. Our bounds, well above the stack's settable keys (docs/controllers.md).
inline constexpr std::size_t kMaxParams = 64;
inline constexpr std::size_t kMaxNameBytes = 128;  // [bytes] a member or parameter name

/// An answer that is not what protocol v1 allows; the message says what is wrong.
class ProtocolError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The "reset" message opening an episode: start, goal, tolerance, seed, control `period` [s],
/// LiDAR geometry and robot limits. The reference path is not sent (it is for test fixtures).
std::string resetMessage(const controllers::EpisodeInfo& info, double period);

/// The costmap versions a program was last sent in an episode (none at its start).
struct CostmapsSent {
  std::optional<std::uint64_t> local;
  std::optional<std::uint64_t> global;
};

/// The "observation" message of one control tick: time, scan (null for no return), odometry
/// pose and twist, goal; the global plan when the observation has one, and each costmap it
/// has that changed since `sent` (which is updated).
std::string observationMessage(const controllers::Observation& observation, CostmapsSent& sent);

/// Checks the answer to a reset: {"ok": true}. {"ok": false, "error": "why"} becomes a
/// ProtocolError carrying the program's reason.
void readResetAnswer(std::string_view line);

/// A command answer: {"v": number, "w": number} plus an optional "state": string and an
/// optional "params": {key: number} of stack parameters to set.
struct CommandAnswer {
  core::Twist command;  // [m/s], [rad/s] robot frame
  std::string state;    // the program's state label ("" if none)
  std::vector<std::pair<std::string, double>> params;  // in the order given
};

/// Parses a command answer strictly: both numbers present and finite, no other keys, no
/// duplicates, at most 64 parameters.
CommandAnswer readCommandAnswer(std::string_view line);

}  // namespace barn::external
