#pragma once
// The Inventec controller's safety checks as one object per kind, chosen once per episode
// (makeInventecSafety): what each state asks (is the policy's command safe, the Forward nudge,
// a turn in place, an aligning turn) answered by the front check (the team's simulation code),
// the every-pose MPC rollout (its real-world code), the paper's static footprint inflation, or
// nothing. The state machine never asks which kind it has.

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "barn/controllers/inventec.hpp"
#include "barn/controllers/safety_checks.hpp"
#include "barn/nav/nav_stack.hpp"

namespace barn::controllers {

/// What a check sees at a tick.
struct SafetyScene {
  const core::LaserScan& scan;
  const std::vector<Eigen::Vector2d>& points;  // the scan's returns, robot frame
  const core::Pose2& pose;                     // odom frame
  const nav::NavStack& nav;                    // its local costmap is read only by a check that needs it
};

class InventecSafety {
 public:
  virtual ~InventecSafety() = default;
  /// LfLH: the command would hit.
  virtual bool commandUnsafe(const SafetyScene& scene, const core::Twist& command) const = 0;
  /// Forward: the nudge would hit.
  virtual bool forwardUnsafe(const SafetyScene& scene, const core::Twist& nudge) const {
    return commandUnsafe(scene, nudge);
  }
  /// HardTurn: turning in place is unsafe (the rotation itself, and the code's LiDAR ring and
  /// rotate check).
  virtual bool turnUnsafe(const SafetyScene& scene, const core::Twist& turn) const = 0;
  /// BackTrack's and Wiggle's aligning turns stop early.
  virtual bool alignmentAborted(const SafetyScene& scene, const core::Twist& turn) const = 0;
};

/// The check `config.safety.type` names, sized by the episode's robot and LiDAR; `rules` say
/// whether the code's turn checks (the LiDAR ring, the rotate check) apply.
std::unique_ptr<InventecSafety> makeInventecSafety(const InventecConfig& config, const InventecRules& rules,
                                                   const EpisodeInfo& info);

}  // namespace barn::controllers
