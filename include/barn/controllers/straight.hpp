#pragma once
/// `straight`: a scripted reference controller that turns toward the goal and drives at it,
/// ignoring obstacles. It exercises the pipeline; it is not a navigation method.

#include "barn/controllers/controller.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"

namespace barn::controllers {

struct StraightConfig {
  double speed = 1.0;  // our choice
  double heading_gain = 2.0;  // our choice
  double rate = 20.0;  // our choice
  template <class V> void visit(V& v) {
    v("speed", speed, {.unit = "m/s", .range = core::kPositive, .doc = "forward speed when facing the goal"});
    v("heading_gain", heading_gain, {.unit = "1/s", .range = core::kPositive, .doc = "yaw rate per radian of heading error"});
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = "control rate"});
  }
};
void validate(const StraightConfig& config, core::Errors& errors, const std::string& prefix);

class StraightController : public Controller {
 public:
  explicit StraightController(const StraightConfig& config) : config_(config) {}
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }

 private:
  StraightConfig config_;
  double max_angular_ = 4.0;  // [rad/s]
};

}  // namespace barn::controllers
