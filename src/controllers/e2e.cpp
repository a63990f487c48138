#include "barn/controllers/e2e.hpp"

#include <algorithm>
#include <cmath>

#include "barn/core/text_io.hpp"

namespace barn::controllers {

void validate(const E2eEncoding& e, core::Errors& errors, const std::string& prefix) {
  core::validateFields(e, errors, prefix);
  errors.check(e.range_clip > 0.0 && std::isfinite(e.range_clip), prefix + ".range_clip", "must be > 0 m");
  errors.check(e.goal_scale > 0.0 && std::isfinite(e.goal_scale), prefix + ".goal_scale", "must be > 0 m");
  errors.check(std::isfinite(e.min_v) && std::isfinite(e.max_v) && e.min_v < e.max_v, prefix + ".max_v",
               "must be finite and above min_v");
  errors.check(std::isfinite(e.min_w) && std::isfinite(e.max_w) && e.min_w < e.max_w, prefix + ".max_w",
               "must be finite and above min_w");
}

void validate(const E2eConfig& c, core::Errors& errors, const std::string& prefix) {
  errors.check(!c.policy.empty(), prefix + ".policy", "must name a policy file");
  errors.check(c.rate > 0.0 && std::isfinite(c.rate), prefix + ".rate", "must be > 0");
  validate(c.encoding, errors, prefix + ".encoding");
  nav::validate(c.nav, errors, prefix + ".nav");
}

std::string e2eInputText(const E2eEncoding& e) {
  return "e2e frames=" + std::to_string(e.frames) + " range_clip=" + core::formatDouble(e.range_clip) +
         " goal_scale=" + core::formatDouble(e.goal_scale) + " v=" + core::formatDouble(e.min_v) + "," +
         core::formatDouble(e.max_v) + " w=" + core::formatDouble(e.min_w) + "," + core::formatDouble(e.max_w);
}

template <class Range>
void encodeE2eFrame(const Range* ranges, int beams, const Eigen::Vector2d& plan_end_robot, const core::Twist& previous,
                    const E2eEncoding& e, float* out) {
  const double half = e.range_clip / 2.0;
  for (int b = 0; b < beams; ++b) {
    const double r = static_cast<double>(ranges[b]);
    const double clipped = std::isnan(r) ? e.range_clip : std::min(r, e.range_clip);  // +inf -> the clip
    out[b] = static_cast<float>((clipped - half) / half);
  }
  out[beams] = static_cast<float>(plan_end_robot.x() / e.goal_scale - 1.0);
  out[beams + 1] = static_cast<float>(plan_end_robot.y() / e.goal_scale - 1.0);
  const double v_bias = (e.max_v + e.min_v) / 2.0, v_scale = (e.max_v - e.min_v) / 2.0;
  const double w_bias = (e.max_w + e.min_w) / 2.0, w_scale = (e.max_w - e.min_w) / 2.0;
  out[beams + 2] = static_cast<float>((previous.linear - v_bias) / v_scale);
  out[beams + 3] = static_cast<float>((previous.angular - w_bias) / w_scale);
}

template void encodeE2eFrame<double>(const double*, int, const Eigen::Vector2d&, const core::Twist&, const E2eEncoding&, float*);
template void encodeE2eFrame<float>(const float*, int, const Eigen::Vector2d&, const core::Twist&, const E2eEncoding&, float*);

void checkE2ePolicy(const learning::MlpPolicy& policy, const E2eEncoding& encoding, int beams, const std::string& source) {
  const learning::MlpPolicyInfo& info = policy.info();
  const std::string where = source + ": ";
  const std::string expected = e2eInputText(encoding);
  if (info.input != expected)
    throw core::InputError(where + "input '" + info.input + "' is not this controller's encoding '" + expected + "'");
  const int inputs = encoding.frames * e2eFrameSize(beams);
  if (policy.inputs() != inputs)
    throw core::InputError(where + "the actor reads " + std::to_string(policy.inputs()) + " inputs, the encoding of " +
                           std::to_string(beams) + " beams x " + std::to_string(encoding.frames) + " frames makes " +
                           std::to_string(inputs));
  if (policy.outputs() != 2 || info.output != learning::MlpOutput::Tanh)
    throw core::InputError(where + "the actor must have two tanh outputs (v, w)");
  if (info.output_low != std::vector<double>{encoding.min_v, encoding.min_w} ||
      info.output_high != std::vector<double>{encoding.max_v, encoding.max_w})
    throw core::InputError(where + "the actor's output range is not the encoding's action range");
}

E2eController::E2eController(const E2eConfig& config, std::shared_ptr<const learning::MlpPolicy> policy)
    : config_(config), policy_(std::move(policy)), feed_(GlobalPlanConfig{config.nav, false, false}) {}

void E2eController::checkLidar(const core::LidarConfig& lidar) const {
  checkE2ePolicy(*policy_, config_.encoding, lidar.beams, "e2e policy '" + policy_->info().name + "'");
}

void E2eController::reset(const EpisodeInfo& info) {
  feed_.reset(info);
  frames_.clear();
  previous_ = {};
}

core::Twist E2eController::act(const Observation& observation) {
  Observation fed = observation;
  feed_.update(fed);
  const Eigen::Vector2d end = fed.global_plan && !fed.global_plan->poses.empty()
                                  ? Eigen::Vector2d(fed.global_plan->poses.back().x, fed.global_plan->poses.back().y)
                                  : fed.goal;
  const std::vector<double>& ranges = fed.scan->ranges;
  const int beams = static_cast<int>(ranges.size());
  std::vector<float> frame(static_cast<std::size_t>(e2eFrameSize(beams)));
  encodeE2eFrame(ranges.data(), beams, fed.odom_pose.inverseTransform(end), previous_, config_.encoding, frame.data());
  const std::size_t frames = static_cast<std::size_t>(config_.encoding.frames);
  if (frames_.empty()) frames_.assign(frames, frame);  // the env's reset stacks the first frame
  else {
    frames_.pop_front();
    frames_.push_back(std::move(frame));
  }
  input_.clear();
  for (const std::vector<float>& f : frames_) input_.insert(input_.end(), f.begin(), f.end());
  if (static_cast<int>(input_.size()) != policy_->inputs())
    throw core::InputError("e2e: the scan has " + std::to_string(beams) + " beams, the actor reads another count");
  const Eigen::VectorXd action = policy_->forward(input_.data());
  previous_ = {action[0], action[1]};
  return previous_;
}

}  // namespace barn::controllers
