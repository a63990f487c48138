#include "barn/bench/protocol_monitor.hpp"

#include <cmath>

#include "barn/core/errors.hpp"

namespace barn::bench {

std::string_view toString(Outcome outcome) {
  switch (outcome) {
    case Outcome::Success: return "success";
    case Outcome::Collision: return "collision";
    case Outcome::Timeout: return "timeout";
    case Outcome::Error: return "error";
  }
  return "unknown";
}

std::optional<long> wholeStepsIn(double period, double dt) {
  const double steps = period / dt;
  const long rounded = std::lround(steps);
  if (rounded < 1 || std::abs(steps - static_cast<double>(rounded)) > 1e-6) return std::nullopt;
  return rounded;
}

ProtocolMonitor::ProtocolMonitor(const core::Protocol& protocol, double dt)
    : protocol_(protocol), dt_(dt), check_steps_(0), max_steps_(std::lround((protocol.timeout + 1.0) / dt)) {
  const std::optional<long> check_steps = wholeStepsIn(protocol.check_period, dt);
  if (!check_steps) throw core::InputError("the status check period must be a whole number of physics steps");
  check_steps_ = *check_steps;
}

double ProtocolMonitor::elapsedAt(long checks) const {
  // Divided by the checks per second (10) when the period is their inverse, so that 189 checks
  // give 18.9, not 18.900000000000002 (checks x 0.1).
  const double whole = static_cast<double>(checks);
  const double per_second = std::round(1.0 / protocol_.check_period);
  return std::abs(per_second * protocol_.check_period - 1.0) < 1e-12 ? whole / per_second : whole * protocol_.check_period;
}

std::optional<Outcome> ProtocolMonitor::afterPhysicsStep(double time, const Eigen::Vector2d& position, bool collided) {
  const long step = steps_++;
  if (collided) {
    actual_time_ = timer_start_step_ ? time - static_cast<double>(*timer_start_step_) * dt_ : 0.0;
    return Outcome::Collision;
  }
  if (!timer_start_step_) {
    if ((position - protocol_.start()).norm() >= protocol_.start_distance) {
      timer_start_step_ = step + 1;
    } else if (time >= protocol_.timeout) {
      actual_time_ = protocol_.timeout;  // never left the start
      return Outcome::Timeout;
    }
    return std::nullopt;
  }
  const long since_start = step + 1 - *timer_start_step_;
  if (since_start % check_steps_ != 0) return std::nullopt;
  actual_time_ = elapsedAt(since_start / check_steps_);
  std::optional<Outcome> outcome;
  if (actual_time_ >= protocol_.timeout - 1e-9) outcome = Outcome::Timeout;
  else if ((position - protocol_.goal()).norm() <= protocol_.success_radius) outcome = Outcome::Success;
  if (since_start > max_steps_) outcome = Outcome::Timeout;  // cannot happen with the rules above; a guard against a hang
  return outcome;
}

}  // namespace barn::bench
