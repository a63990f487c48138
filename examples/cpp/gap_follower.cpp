// The gap follower of examples/external/gap_follower.py as a C++ controller: the same steps in
// the same order with the same floating-point operations, so it gives the same record as the
// Python class and the external program (src/python/tests checks the three agree).
//
// A controller for barn is a Controller subclass (include/barn/controllers/controller.hpp). To
// make one available to `barn run`, register it in src/controllers/registry.cpp with a config
// struct; this example instead runs itself (example_runner.hpp), the way a researcher can try a
// controller before wiring it in:
//
//   build/examples/gap_follower WORLDS OUT [SEED]     e.g.  build/examples/gap_follower 0:300:30 /tmp/gap

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <numbers>
#include <string>
#include <string_view>
#include <vector>

#include "barn/controllers/controller.hpp"
#include "example_runner.hpp"

namespace {

using namespace barn;

// The parameters of gap_follower.py (its command-line defaults).
struct GapFollowerConfig {
  double max_speed = 1.0;       // [m/s]
  double max_turn_rate = 2.0;   // [rad/s]
  double margin = 0.1;          // [m] added to the robot's half width
  double horizon = 2.5;         // [m] scan points farther away are ignored
  double lookahead = 1.5;       // [m] free distance a direction needs
  double slow_distance = 1.0;   // [m] full speed beyond this much room
  double turn_gain = 2.0;       // [1/s] yaw rate per radian of heading
  double step_degrees = 3.0;    // [deg] between candidate directions
  double rate = 10.0;           // [Hz]
};

class GapFollower : public controllers::Controller {
 public:
  explicit GapFollower(const GapFollowerConfig& config) : config_(config) {}

  void reset(const controllers::EpisodeInfo& info) override {
    angle_min_ = info.lidar.angle_min;
    angle_increment_ = info.lidar.angleIncrement();
    offset_x_ = info.lidar.mount_x;
    offset_y_ = info.lidar.mount_y;
    max_w_ = std::min(config_.max_turn_rate, info.robot.max_angular_speed);
    max_v_ = std::min(config_.max_speed, info.robot.max_linear_speed);
    half_width_ = info.robot.footprint_width / 2 + config_.margin;
    front_ = info.robot.footprint_length / 2;
    heading_ = 0.0;
    const double step = config_.step_degrees * (std::numbers::pi / 180.0);  // Python's math.radians
    const int count = static_cast<int>(std::numbers::pi / 2 / step);
    candidates_.clear();
    for (int i = -count; i <= count; ++i) candidates_.push_back(i * step);
  }

  core::Twist act(const controllers::Observation& obs) override {
    const double dx = obs.goal.x() - obs.odom_pose.x, dy = obs.goal.y() - obs.odom_pose.y;
    const double goal_distance = std::sqrt(dx * dx + dy * dy);
    double goal_angle = std::atan2(dy, dx) - obs.odom_pose.yaw;
    goal_angle = std::atan2(std::sin(goal_angle), std::cos(goal_angle));

    points(obs.scan->ranges);
    const double need = std::min(goal_distance, config_.lookahead);
    bool found = false;
    double best = 0.0, best_cost = std::numeric_limits<double>::infinity(), best_free = 0.0;
    double fallback = 0.0, fallback_free = -1.0;
    for (const double angle : candidates_) {
      const double free = freeDistance(angle);
      if (free > fallback_free) {
        fallback = angle;
        fallback_free = free;
      }
      if (free < need) continue;
      // Closest to the goal, with a little hysteresis against dithering between two gaps.
      const double cost = std::abs(angle - goal_angle) + 0.3 * std::abs(angle - heading_);
      if (cost < best_cost) {
        found = true;
        best = angle;
        best_cost = cost;
        best_free = free;
      }
    }
    if (!found) {
      if (fallback_free < front_ + 0.15) {
        // Boxed in: turn on the spot toward the most open direction.
        heading_ = fallback;
        state_ = "turn";
        return {0.0, std::copysign(max_w_ * 0.6, fallback != 0.0 ? fallback : 1.0)};
      }
      best = fallback;
      best_free = fallback_free;
    }
    heading_ = best;
    state_ = "gap";
    const double w = std::max(-max_w_, std::min(max_w_, config_.turn_gain * best));
    // Slow down for sharp turns and when the free distance ahead is short.
    const double ahead = freeDistance(0.0);
    const double room = std::max(0.0, std::min(1.0, (std::min(best_free, ahead + 0.5) - front_) / config_.slow_distance));
    const double v = max_v_ * room * std::pow(std::max(0.0, std::cos(best)), 2.0);
    return {v, w};
  }

  double period() const override { return 1.0 / config_.rate; }
  std::string_view stateLabel() const override { return state_; }

 private:
  // Scan returns within the horizon as (x, y) in the robot frame (every 2nd beam).
  void points(const std::vector<double>& scan) {
    points_.clear();
    for (std::size_t i = 0; i < scan.size(); i += 2) {
      const double r = scan[i];
      if (std::isinf(r) || r > config_.horizon) continue;
      const double a = angle_min_ + static_cast<double>(i) * angle_increment_;
      points_.push_back({offset_x_ + r * std::cos(a), offset_y_ + r * std::sin(a)});
    }
  }

  // How far a corridor of half_width along `angle` stays free of points [m].
  double freeDistance(double angle) const {
    const double c = std::cos(angle), s = std::sin(angle);
    double free = config_.horizon;
    for (const Point& p : points_) {
      const double along = p.x * c + p.y * s;
      if (along <= 0.0 || along >= free) continue;
      if (std::abs(-p.x * s + p.y * c) < half_width_) free = along;
    }
    return free;
  }

  struct Point {
    double x, y;
  };
  GapFollowerConfig config_;
  double angle_min_ = 0.0, angle_increment_ = 0.0, offset_x_ = 0.0, offset_y_ = 0.0;
  double max_w_ = 0.0, max_v_ = 0.0, half_width_ = 0.0, front_ = 0.0;
  double heading_ = 0.0;  // [rad] the direction chosen last tick, robot frame
  std::vector<double> candidates_;
  std::vector<Point> points_;
  std::string state_;
};

}  // namespace

int main(int argc, char** argv) {
  return barn::examples::runExample(argc, argv, [] { return std::make_unique<GapFollower>(GapFollowerConfig{}); });
}
