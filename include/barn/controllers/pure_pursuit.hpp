#pragma once
/// `pure_pursuit`: follows the world's A* reference path (UsesReferencePath) with
/// the pure-pursuit law. A TEST FIXTURE: it is the one controller that is handed the world's
/// path, so the pipeline can be exercised end to end before real planners exist. Its scores
/// say how the simulator treats a robot on BARN's own path, not how good a method is.

#include "barn/controllers/controller.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"

namespace barn::controllers {

struct PurePursuitConfig {
  double speed = 0.5;      // our choice
  double lookahead = 0.5;  // our choice
  double rate = 20.0;      // our choice
  template <class V> void visit(V& v) {
    v("speed", speed, {.unit = "m/s", .range = core::kPositive, .doc = "forward speed"});
    v("lookahead", lookahead, {.unit = "m", .range = core::kPositive, .doc = "distance of the pursued point along the path"});
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = "control rate"});
  }
};
void validate(const PurePursuitConfig& config, core::Errors& errors, const std::string& prefix);

class PurePursuitController : public Controller, public UsesReferencePath {
 public:
  explicit PurePursuitController(const PurePursuitConfig& config) : config_(config) {}
  void setReferencePath(std::vector<Eigen::Vector2d> path) override { reference_path_ = std::move(path); }
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.rate; }

 private:
  PurePursuitConfig config_;
  std::vector<Eigen::Vector2d> reference_path_;  // the world's A* path, odom frame
  std::vector<Eigen::Vector2d> path_;  // reference path then the goal, odom frame
  std::size_t progress_ = 0;           // index of the closest path point so far (never decreases)
  double max_angular_ = 4.0;           // [rad/s]
};

}  // namespace barn::controllers
