#pragma once
/// `ut_amrl`: UT AMRL's 2023 BARN entry (ut-amrl/BARN_CHALLENGE_2023, the April 2023 `data`
/// tag a3368cf, its simulation configuration), three ROS nodes in one controller:
///
///  1. The LiDAR-Voronoi global planner (voronoi_planner.hpp) every plan_period: a path from
///     the robot to a goal 10 m along the first heading, through the widest gaps of the
///     Voronoi diagram of every LiDAR return seen so far.
///  2. The local goal (localgoal_2023.py) on each new path: the path moved so that its first
///     pose is the robot's position now, then its first pose farther than 0.3 m.
///  3. graph_navigation (its Run loop, at 40 Hz) toward that local goal on an empty map: a
///     straight plan from the robot to the local goal, a carrot on it at most carrot_dist
///     away; the carrot more than local_fov off the heading: turn in place (braking first);
///     else the constant-curvature arcs and linear evaluator of arc_planner.hpp, with 1-D
///     time-optimal speed. Within 0.1 m of the local goal and nearly stopped it turns to the
///     goal's heading and stops until the next local goal arrives.
///
/// What barnbench replaces: ENML (the team's localisation, used as odometry) by barnbench's
/// odometry; scipy's Qhull Voronoi by Boost.Polygon's; the team's hard-coded laser offset in the
/// global planner (x - 0.055 in the odom frame) by the true sensor pose.
///
/// graph_navigation's latency model: each command is taken to act system_latency after it is
/// sent. The planner starts from the last command as the robot's velocity, and moves the
/// scan's points by the commands that act within one control period of the scan's stamp (its
/// ForwardPredict(now + system_latency)); the carrot is taken from the current pose.

#include <array>
#include <deque>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/controllers/arc_planner.hpp"
#include "barn/controllers/controller.hpp"
#include "barn/controllers/voronoi_planner.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"

namespace barn::controllers {

/// graph_navigation's navigation parameters (navigation.lua at the `data` tag, unless noted).
struct GraphNavConfig {
  double rate = 40.0;
  double system_latency = 0.24;
  double max_linear_speed = 2.0;
  double max_linear_accel = 0.5;
  double max_linear_decel = 0.5;
  double max_angular_speed = 5.0;
  double max_angular_accel = 5.0;
  double max_angular_decel = 5.0;
  double carrot_dist = 3.0;
  double local_fov_deg = 30.0;
  double laser_x = 0.12;
  double target_dist_tolerance = 0.1;
  double target_vel_tolerance = 0.1;
  double target_angle_tolerance = 0.05;
  double max_plan_deviation = 0.5;
  double max_turn_speed = 0.1;
  // Whether the arcs see the scan. The `data` tag's navigation.lua subscribes to
  // "/velodyne_2dscan" (UT's own Jackal), which the BARN simulation does not publish (its scan
  // is front/scan), and nothing in the team's launch files remaps it; false is graph_navigation
  // as that configuration ran in BARN, blind (docs/systems/ut_amrl.md, "What ran in 2023").
  bool see_obstacles = true;
  ArcPlannerConfig arcs;

  template <class V> void visit(V& v) {
    v("rate", rate, {.unit = "Hz", .range = core::kPositive, .doc = "team: dt 0.025"});
    v("system_latency", system_latency, {.unit = "s", .range = core::kNonNegative, .doc = "team"});
    v("max_linear_speed", max_linear_speed, {.unit = "m/s", .range = core::kPositive, .doc = "team"});
    v("max_linear_accel", max_linear_accel, {.unit = "m/s^2", .range = core::kPositive, .doc = "team"});
    v("max_linear_decel", max_linear_decel, {.unit = "m/s^2", .range = core::kPositive, .doc = "team"});
    v("max_angular_speed", max_angular_speed, {.unit = "rad/s", .range = core::kPositive, .doc = "team"});
    v("max_angular_accel", max_angular_accel, {.unit = "rad/s^2", .range = core::kPositive, .doc = "team"});
    v("max_angular_decel", max_angular_decel, {.unit = "rad/s^2", .range = core::kPositive, .doc = "team"});
    v("carrot_dist", carrot_dist, {.unit = "m", .range = core::kPositive, .doc = "team"});
    v("local_fov_deg", local_fov_deg,
      {.unit = "deg", .range = core::openClosed(0.0, 180.0), .doc = "team: turn in place when the carrot is farther off"});
    v("laser_x", laser_x, {.unit = "m", .doc = "team: laser_loc.x (barnbench's sensor, like Gazebo's, is at 0.055)"});
    v("target_dist_tolerance", target_dist_tolerance,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: the local goal counts as reached within this ..."});
    v("target_vel_tolerance", target_vel_tolerance,
      {.unit = "m/s", .range = core::kNonNegative, .doc = "team: ... below this speed"});
    v("target_angle_tolerance", target_angle_tolerance,
      {.unit = "rad", .range = core::kPositive, .doc = "team: then it turns to the goal's heading to within this"});
    v("max_plan_deviation", max_plan_deviation,
      {.unit = "m", .range = core::kPositive, .doc = "graph_navigation's default: re-plan when farther from the plan"});
    v("max_turn_speed", max_turn_speed,
      {.unit = "m/s", .range = core::kNonNegative, .doc = "graph_navigation: TurnInPlace brakes above this speed"});
    v("see_obstacles", see_obstacles, {.doc = "our choice: the configuration's evident intent"});
    v("arcs", arcs);
  }
  MotionLimits linear() const { return {max_linear_speed, max_linear_accel, max_linear_decel}; }
  MotionLimits angular() const { return {max_angular_speed, max_angular_accel, max_angular_decel}; }
};

struct UtAmrlConfig {
  // [s] our choice: the Python Voronoi node ran as fast as its cycle allowed (a few hundred
  // points through Qhull, a Python A* and two searches); a whole number of control periods.
  double plan_period = 0.1;
  double local_goal_distance = 0.3;
  VoronoiPlannerConfig voronoi;
  GraphNavConfig navigation;

  template <class V> void visit(V& v) {
    v("plan_period", plan_period);
    v("local_goal_distance", local_goal_distance,
      {.unit = "m", .range = core::kNonNegative, .doc = "team: localgoal_2023.py, mode \"2023\""});
    v("voronoi", voronoi);
    v("navigation", navigation);
  }
};
void validate(const UtAmrlConfig& config, core::Errors& errors, const std::string& prefix);

/// localgoal_2023.py: the path moved by (robot - its first pose), then its first pose farther
/// than `distance` from the robot; empty if none is.
std::optional<Eigen::Vector2d> shiftedLocalGoal(std::span<const Eigen::Vector2d> path, const Eigen::Vector2d& robot,
                                                double distance);

/// graph_navigation's carrot on a plan from `plan_start` to `goal`: the goal if within
/// `carrot_dist` of the robot, else where the circle of that radius around the robot crosses
/// the plan (the crossing nearer the goal); empty if it does not.
std::optional<Eigen::Vector2d> carrotOnPlan(const Eigen::Vector2d& plan_start, const Eigen::Vector2d& goal,
                                            const Eigen::Vector2d& robot, double carrot_dist);

/// What the controller did in a tick (the trajectory label): no local goal yet; drove an arc;
/// turned toward a carrot outside local_fov (braking first); stopped for want of an arc or a
/// carrot; turned to the reached local goal's heading; stood at the reached local goal.
enum class UtAmrlState { Idle, Arcs, TurnInPlace, NoArc, FaceGoal, Stopped };
std::span<const std::string_view> enumNames(UtAmrlState);

class UtAmrlController : public Controller {
 public:
  explicit UtAmrlController(const UtAmrlConfig& config);
  void reset(const EpisodeInfo& info) override;
  core::Twist act(const Observation& observation) override;
  double period() const override { return 1.0 / config_.navigation.rate; }
  std::string_view stateLabel() const override;

  const VoronoiPlanner& globalPlanner() const { return planner_; }
  std::optional<Eigen::Vector2d> localGoal() const { return local_goal_; }

 private:
  /// One graph_navigation cycle toward the local goal.
  ArcCommand navigate(const Observation& observation);
  /// The scan's returns in the robot frame (laser at laser_x), moved by graph_navigation's
  /// latency model.
  void predictPoints(const Observation& observation);

  /// graph_navigation's navigation state: heading for the local goal, turning to its heading
  /// once reached, stopped (also before the first local goal).
  enum class NavState { Stopped, Goto, FaceGoal };

  struct SentCommand {
    double acts_at = 0.0;  // [s] sent time + system_latency
    double linear = 0.0;   // [m/s]
    double angular = 0.0;  // [rad/s]
  };

  UtAmrlConfig config_;
  VoronoiPlanner planner_;
  EpisodeInfo info_;
  int plan_every_ = 1;                               // control ticks per planning cycle
  long tick_ = 0;                                    // control ticks so far
  std::optional<Eigen::Vector2d> local_goal_;        // [m] odom frame
  double goal_heading_ = 0.0;                        // [rad] the local goal's heading
  std::optional<Eigen::Vector2d> plan_start_;        // [m] graph_navigation's plan: from here to the local goal
  NavState state_ = NavState::Stopped;
  UtAmrlState action_ = UtAmrlState::Idle;           // what this tick did
  std::deque<SentCommand> history_;
  std::vector<Eigen::Vector2d> points_;              // [m] robot frame
};

}  // namespace barn::controllers
