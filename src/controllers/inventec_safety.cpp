#include "inventec_safety.hpp"

#include <cmath>
#include <numbers>

namespace barn::controllers {

namespace {

double degrees(double d) { return d * std::numbers::pi / 180.0; }

// What the rollout checks share: a turn in place is unsafe when the rotation is, or, in the
// code, when the LiDAR ring is hit; an aligning turn stops when the rotation is unsafe.
class RolloutSafety : public InventecSafety {
 public:
  RolloutSafety(const InventecSafetyConfig& s, bool ring) : ring_(ring), ring_front_(s.ring_front), ring_edge_(s.ring_edge) {}
  bool turnUnsafe(const SafetyScene& scene, const core::Twist& turn) const override {
    return rotationUnsafe(scene, turn) || (ring_ && ringHit(scene.scan, ring_front_, ring_edge_));
  }
  bool alignmentAborted(const SafetyScene& scene, const core::Twist& turn) const override {
    return rotationUnsafe(scene, turn);
  }

 protected:
  virtual bool rotationUnsafe(const SafetyScene& scene, const core::Twist& turn) const = 0;

 private:
  bool ring_;
  double ring_front_, ring_edge_;  // [m]
};

// The simulation code: the front check plus the 0.2 s final-pose rollout on commands; the
// rollout, the ring and the rotate check (the footprint turned against the LiDAR, the tail's
// strip against the local costmap) on turns in place; the rotate check alone on aligning turns.
class FrontSafety : public RolloutSafety {
 public:
  FrontSafety(const InventecSafetyConfig& s, const InventecConfig& config, bool code_turns, const EpisodeInfo& info)
      : RolloutSafety(s, code_turns && s.ring), lidar_(info.lidar), rotate_check_(code_turns && s.rotate_check) {
    front_.front_angle = degrees(s.front_angle_deg);
    front_.half_width = info.robot.footprint_width / 2;
    front_.half_length = info.robot.footprint_length / 2;
    front_.pad_x = s.front_pad_x;
    front_.pad_front = s.front_pad_y;
    front_.speed_gain = s.front_speed_gain;
    front_.rotate_gain = s.front_rotate_gain;
    rotate_.body = core::Rect::centred(info.robot.footprint_length, info.robot.footprint_width);
    rotate_.rotate_gain = s.front_rotate_gain;
    rotate_.rear_centre = s.rear_strip_centre;
    rotate_.rear_depth = s.rear_strip_depth;
    rotate_.rear_width = s.rear_strip_width;
    rotate_.rear_weight = config.rear_weight;
    // The code's final-pose rollout (`_bch_safety_check`), as it computed it: beams against the
    // L1 length of 40 points on the costmap footprint's rectangle (safety_checks.hpp).
    final_pose_ = s.rollout.check(config.nav.footprint());
  }
  bool commandUnsafe(const SafetyScene& scene, const core::Twist& command) const override {
    return beamRolloutHit(scene.scan, command, final_pose_) || forwardUnsafe(scene, command);
  }
  // The code's Forward looks at the front check only.
  bool forwardUnsafe(const SafetyScene& scene, const core::Twist& nudge) const override {
    return frontCheckHit(scene.scan, lidar_, beams_, nudge, front_);
  }
  bool turnUnsafe(const SafetyScene& scene, const core::Twist& turn) const override {
    return RolloutSafety::turnUnsafe(scene, turn) || rotateCheckFires(scene, turn);
  }
  // The code's aligning turns stop on the rotate check's flag alone.
  bool alignmentAborted(const SafetyScene& scene, const core::Twist& turn) const override {
    return rotate_check_ ? rotateCheckFires(scene, turn) : rotationUnsafe(scene, turn);
  }

 protected:
  bool rotationUnsafe(const SafetyScene& scene, const core::Twist& turn) const override {
    return beamRolloutHit(scene.scan, turn, final_pose_);
  }

 private:
  bool rotateCheckFires(const SafetyScene& scene, const core::Twist& turn) const {
    return rotate_check_ && rotateCheckHit(scene.points, scene.nav.localObstacleLayer(), scene.pose, turn.angular, rotate_);
  }

  core::LidarConfig lidar_;
  bool rotate_check_;
  FrontCheck front_;
  RotateCheck rotate_;
  BeamRollout final_pose_;
  mutable core::BeamDirections beams_;  // a cache of the scan's beam directions
};

// The real-world code: the footprint (grown by mpc_offset) rolled out for mpc_steps, every
// pose checked; turns in place against the local costmap's inscribed and lethal cells (which
// remember what lies behind) or against the scan.
class MpcSafety : public RolloutSafety {
 public:
  MpcSafety(const InventecSafetyConfig& s, bool code_turns, const EpisodeInfo& info)
      : RolloutSafety(s, code_turns && s.ring),
        body_(core::Rect::centred(info.robot.footprint_length, info.robot.footprint_width).grownBy(s.mpc_offset)),
        dt_(s.mpc_dt), steps_(s.mpc_steps), costmap_turns_(s.mpc_costmap_turns) {}
  bool commandUnsafe(const SafetyScene& scene, const core::Twist& command) const override {
    return rolloutHit(scene.points, body_, command, dt_, steps_);
  }

 protected:
  bool rotationUnsafe(const SafetyScene& scene, const core::Twist& turn) const override {
    if (!costmap_turns_) return rolloutHit(scene.points, body_, turn, dt_, steps_);
    // Only cells the rolled-out footprint can reach: its farthest corner, plus the drive.
    const double reach = body_.farthestCornerDistance() + std::abs(turn.linear) * dt_ * steps_;
    return rolloutHit(inscribedCellPoints(scene.nav.localObstacleLayer(), scene.pose, reach), body_, turn, dt_, steps_);
  }

 private:
  core::Rect body_;
  double dt_;
  int steps_;
  bool costmap_turns_;
};

// The paper: nothing inside the footprint grown by fi_offset, all around; turns rolled out
// with the plain footprint.
class FiSafety : public RolloutSafety {
 public:
  FiSafety(const InventecSafetyConfig& s, bool code_turns, const EpisodeInfo& info)
      : RolloutSafety(s, code_turns && s.ring),
        footprint_(core::Rect::centred(info.robot.footprint_length, info.robot.footprint_width)),
        inflated_(footprint_.grownBy(s.fi_offset)), dt_(s.rollout.dt), steps_(s.rollout.steps) {}
  bool commandUnsafe(const SafetyScene& scene, const core::Twist&) const override {
    return footprintInflationHit(scene.points, inflated_);
  }

 protected:
  bool rotationUnsafe(const SafetyScene& scene, const core::Twist& turn) const override {
    return rolloutHit(scene.points, footprint_, turn, dt_, steps_);
  }

 private:
  core::Rect footprint_, inflated_;
  double dt_;
  int steps_;
};

// No check: every command is safe (the ablation).
class NoSafety : public InventecSafety {
 public:
  bool commandUnsafe(const SafetyScene&, const core::Twist&) const override { return false; }
  bool turnUnsafe(const SafetyScene&, const core::Twist&) const override { return false; }
  bool alignmentAborted(const SafetyScene&, const core::Twist&) const override { return false; }
};

}  // namespace

std::unique_ptr<InventecSafety> makeInventecSafety(const InventecConfig& config, const InventecRules& rules,
                                                   const EpisodeInfo& info) {
  const InventecSafetyConfig& s = config.safety;
  switch (s.type) {
    case SafetyCheck::Front: return std::make_unique<FrontSafety>(s, config, rules.code_turn_checks, info);
    case SafetyCheck::Mpc: return std::make_unique<MpcSafety>(s, rules.code_turn_checks, info);
    case SafetyCheck::Fi: return std::make_unique<FiSafety>(s, rules.code_turn_checks, info);
    case SafetyCheck::None: return std::make_unique<NoSafety>();
  }
  return std::make_unique<NoSafety>();
}

}  // namespace barn::controllers
