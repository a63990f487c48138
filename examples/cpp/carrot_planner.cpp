// examples/python/carrot_planner.py as a C++ controller: the same steps in the same order with
// the same floating-point operations, so it gives the same record as the Python class and the
// external program (src/python/tests checks the three agree). It is only a local planner:
// GlobalPlanFedController runs move_base's stack beside it (the `global_plan` block of a
// registered controller's config does the same), and it reads Observation::global_plan.
//
//   build/examples/carrot_planner WORLDS OUT [SEED]

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "barn/controllers/global_plan_feed.hpp"
#include "example_runner.hpp"

namespace {

using namespace barn;

class CarrotPlanner : public controllers::Controller {
 public:
  void reset(const controllers::EpisodeInfo& info) override {
    max_w_ = info.robot.max_angular_speed;
    front_ = info.robot.footprint_length / 2;
    first_ = static_cast<std::size_t>(std::ceil((-0.35 - info.lidar.angle_min) / info.lidar.angleIncrement()));
    last_ = static_cast<std::size_t>(std::floor((0.35 - info.lidar.angle_min) / info.lidar.angleIncrement()));
  }

  core::Twist act(const controllers::Observation& obs) override {
    const double x = obs.odom_pose.x, y = obs.odom_pose.y, yaw = obs.odom_pose.yaw;
    const std::vector<core::Pose2>& plan = obs.global_plan->poses;  // robot -> goal
    double tx = obs.goal.x(), ty = obs.goal.y();                      // no plan yet: the goal
    std::size_t closest = 0;
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < plan.size(); ++i) {
      const double dx = plan[i].x - x, dy = plan[i].y - y;
      if (dx * dx + dy * dy < nearest) {
        closest = i;
        nearest = dx * dx + dy * dy;
      }
    }
    for (std::size_t i = closest; i < plan.size(); ++i) {
      tx = plan[i].x;
      ty = plan[i].y;
      if ((tx - x) * (tx - x) + (ty - y) * (ty - y) >= kLookahead * kLookahead) break;
    }
    double error = std::atan2(ty - y, tx - x) - yaw;
    error = std::atan2(std::sin(error), std::cos(error));
    const double w = std::max(-max_w_, std::min(max_w_, kTurnGain * error));
    const auto& ranges = obs.scan->ranges;
    const double ahead = *std::min_element(ranges.begin() + static_cast<std::ptrdiff_t>(first_),
                                           ranges.begin() + static_cast<std::ptrdiff_t>(last_ + 1));
    const double room = std::max(0.0, std::min(1.0, (ahead - front_ - 0.2) / kSlowDistance));
    return {kMaxSpeed * room * std::max(0.0, std::cos(error)), w};
  }

  double period() const override { return 0.05; }

 private:
  // carrot_planner.py's constructor defaults.
  static constexpr double kLookahead = 1.0;     // [m]
  static constexpr double kMaxSpeed = 1.0;      // [m/s]
  static constexpr double kTurnGain = 2.0;      // [1/s]
  static constexpr double kSlowDistance = 1.0;  // [m]
  double max_w_ = 0.0, front_ = 0.0;
  std::size_t first_ = 0, last_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  return barn::examples::runExample(argc, argv, [] {
    // global_plan: {} in carrot_planner.yaml: BARN's move_base as its DWA baseline ran it.
    return std::make_unique<controllers::GlobalPlanFedController>(controllers::GlobalPlanConfig{},
                                                                   std::make_unique<CarrotPlanner>());
  });
}
