#pragma once
/// The benchmark's contract: run.py's rules for when an episode ends and what its time AT is,
/// in one plain type that bench::Episode asks after every physics step. Nothing here knows
/// about physics, LiDARs or controllers, so the rules are tested on hand-made pose sequences.
///
/// The rules (the official harness, run.py; the numbers are core::Protocol's):
///   - Collision: any contact ends the episode at once (run.py polls; we see contacts at
///     physics rate). AT is the time since the timer started (0 if it never did).
///   - The timer starts at the end of the first physics step that leaves the robot centre
///     `start_distance` (0.1 m) or more from the start.
///   - Before that, a robot still at the start at `timeout` (100 s) of simulated time times
///     out with AT = timeout.
///   - After that, the status is checked every `check_period` (0.1 s) of simulated time since
///     the timer started. At a check, elapsed = whole checks x check_period: at or beyond the
///     timeout the episode times out; else within `success_radius` (1 m) of the goal it
///     succeeds. AT is that elapsed time.

#include <optional>
#include <string_view>

#include <Eigen/Core>

#include "barn/core/protocol.hpp"

namespace barn::bench {

enum class Outcome {
  Success,    ///< reached the goal radius before the timeout, without contact
  Collision,  ///< a robot fixture touched a cylinder
  Timeout,    ///< 100 s elapsed (or the robot never left the start)
  Error,      ///< the controller threw or returned a non-finite command
};
std::string_view toString(Outcome outcome);

/// The number of physics steps of `dt` in `period`, if it is a whole number (at least 1).
std::optional<long> wholeStepsIn(double period, double dt);

class ProtocolMonitor {
 public:
  /// `dt`: the physics step [s]. Throws core::InputError unless the protocol's check period
  /// is a whole number of steps.
  ProtocolMonitor(const core::Protocol& protocol, double dt);

  /// After one more physics step: `time` is the simulated time then [s], `position` the robot
  /// centre (world frame), `collided` whether it touched anything. The outcome if the episode
  /// ends with this step, else none. Not to be called once it has ended.
  std::optional<Outcome> afterPhysicsStep(double time, const Eigen::Vector2d& position, bool collided);

  /// [s] AT, once afterPhysicsStep() has returned an outcome.
  double actualTime() const { return actual_time_; }
  /// Whether the robot has left the start (the timer runs).
  bool timerStarted() const { return timer_start_step_.has_value(); }

 private:
  /// [s] the time at `checks` whole checks since the timer started.
  double elapsedAt(long checks) const;

  core::Protocol protocol_;
  double dt_;         // [s]
  long check_steps_;  // physics steps per status check
  long max_steps_;    // a guard: steps after the timer started beyond which an episode cannot run
  long steps_ = 0;    // physics steps taken
  std::optional<long> timer_start_step_;  // the steps taken when the timer started
  double actual_time_ = 0.0;
};

}  // namespace barn::bench
