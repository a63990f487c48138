// Google Benchmark of the simulator's hot paths (built with -DBARN_BUILD_BENCHMARKS=ON):
//   BM_Scan/fast      one 720-beam scan with LidarCaster (the simulator's caster)
//   BM_Scan/box2d     the same scan with one b2World::RayCast per beam (the reference)
//   BM_SimulatedSecond  one simulated second: physics at the configured rate + 50 Hz LiDAR
//   BM_CostmapUpdate/{global,local}/{read,unread}  one scan folded into a costmap as a robot drives
//                     through a dense world, with or without reading a cost afterwards (the
//                     inflation is brought up to date only when read)
//   BM_GlobalPlan     one global plan from scratch on a dense world (dijkstra: a new A* field;
//                     navfn: a full propagation)
//   BM_GlobalReplan   one dijkstra replan after a costmap change: one cell on the path (the
//                     field repaired, or searched again past a few dozen changed cells), or a
//                     cylinder appearing 2 m ahead (searched again from what it cannot touch)
// Run: build-bench/tests/perf/barn_sim_benchmark --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <cmath>
#include <vector>

#include <benchmark/benchmark.h>

#include "barn/bench/episode.hpp"
#include "barn/core/world_file.hpp"
#include "barn/sim/lidar.hpp"
#include "barn/nav/global_planner.hpp"
#include "barn/nav/nav_stack.hpp"
#include "barn/sim/simulator.hpp"

namespace {

using namespace barn;

// World 150 (fill 0.25): a typical dense world. Poses along the corridor centre line.
struct Fixture {
  core::WorldSpec world = core::readWorldFile(std::string(BARN_SOURCE_DIR) + "/worlds/world_150.yaml");
  sim::ObstacleField field = sim::ObstacleField::fromWorld(world);
  core::LidarConfig lidar;
  std::vector<core::Pose2> poses;
  Fixture() {
    for (int i = 0; i < 64; ++i) poses.push_back({-2.25, 3.0 + 0.1 * i, 1.57 + 0.01 * i});
  }
};

void BM_ScanFast(benchmark::State& state) {
  Fixture f;
  sim::LidarCaster caster(f.lidar, f.field);
  std::vector<double> ranges;
  std::size_t i = 0;
  for (auto _ : state) {
    caster.cast(f.lidar.sensorPose(f.poses[i++ % f.poses.size()]), ranges);
    benchmark::DoNotOptimize(ranges.data());
  }
  state.SetItemsProcessed(state.iterations() * f.lidar.beams);
}
BENCHMARK(BM_ScanFast)->Name("BM_Scan/fast");

void BM_ScanBox2D(benchmark::State& state) {
  Fixture f;
  const sim::Simulator simulator(f.field, core::RobotConfig{}, sim::PhysicsConfig{}, f.poses[0]);
  std::size_t i = 0;
  for (auto _ : state) {
    auto scan = simulator.referenceScan(f.lidar, f.lidar.sensorPose(f.poses[i++ % f.poses.size()]));
    benchmark::DoNotOptimize(scan.ranges.data());
  }
  state.SetItemsProcessed(state.iterations() * f.lidar.beams);
}
BENCHMARK(BM_ScanBox2D)->Name("BM_Scan/box2d");

// Physics + LiDAR for one simulated second, driving forward and turning gently through the
// start area and into the field (the robot is reset when it collides).
void BM_SimulatedSecond(benchmark::State& state) {
  Fixture f;
  sim::PhysicsConfig physics;
  physics.rate = static_cast<double>(state.range(0));
  sim::LidarCaster caster(f.lidar, f.field);
  core::FastNoise noise(1);
  auto simulator = std::make_unique<sim::Simulator>(f.field, core::RobotConfig{}, physics, f.poses[0]);
  const long steps_per_second = std::lround(physics.rate);
  const long steps_per_scan = std::lround(physics.rate / f.lidar.rate);
  long step = 0;
  for (auto _ : state) {
    for (long k = 0; k < steps_per_second; ++k, ++step) {
      if (step % steps_per_scan == 0) {
        auto scan = caster.scan(simulator->pose(), simulator->time(), &noise);
        benchmark::DoNotOptimize(scan.ranges.data());
        simulator->command({0.5, 0.3 * std::sin(0.1 * static_cast<double>(step / steps_per_scan))});
      }
      simulator->step();
      if (simulator->collision() || simulator->time() > 8.0) {
        simulator = std::make_unique<sim::Simulator>(f.field, core::RobotConfig{}, physics, f.poses[0]);
      }
    }
  }
  state.counters["real_time_factor"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SimulatedSecond)->Arg(200)->Arg(1000)->Unit(benchmark::kMicrosecond);

// One scan folded into the global (fixed) or local (rolling) costmap while the robot drives up
// the corridor of a dense world; with `read`, one cost is read after it, which brings the
// inflation up to date (a map nobody reads pays only for its ray traces).
void BM_CostmapUpdate(benchmark::State& state) {
  Fixture f;
  const bool local = state.range(0) > 0;
  const bool read = state.range(1) > 0;
  // The scans along the corridor, cast beforehand (casting is BM_Scan's); driven up and back
  // down so the rolling window never jumps.
  sim::LidarCaster caster(f.lidar, f.field);
  core::FastNoise noise(7);
  const Eigen::Vector2d odom_origin(-2.25, 3.0);
  std::vector<std::pair<core::LaserScan, core::Pose2>> drive;
  for (std::size_t k = 0; k < 2 * f.poses.size(); ++k) {
    const core::Pose2 pose = f.poses[k < f.poses.size() ? k : 2 * f.poses.size() - 1 - k];
    drive.emplace_back(caster.scan(pose, 0.0, &noise), core::Pose2{pose.x - odom_origin.x(), pose.y - odom_origin.y(), pose.yaw});
  }
  nav::Costmap costmap(local ? nav::NavStackConfig::defaultLocalCostmap() : nav::NavStackConfig::defaultGlobalCostmap(), nav::NavStackConfig{}.inscribedRadius({}));
  std::size_t i = 0;
  long cost_sum = 0;
  for (auto _ : state) {
    const auto& [scan, odom] = drive[i++ % drive.size()];
    costmap.integrateScan(scan, f.lidar.sensorPose(odom), odom.position());
    if (read) {  // a map that is read is updated first (the inflation folded in)
      costmap.update();
      cost_sum += costmap.costAt(odom.position());
    }
  }
  benchmark::DoNotOptimize(cost_sum);
}
// Args: local map, update and read a cost after each scan (else the ray traces alone).
BENCHMARK(BM_CostmapUpdate)->Args({0, 1})->Args({1, 1})->Args({1, 0})->Unit(benchmark::kMicrosecond);

// The default global costmap with every cylinder of a world marked.
nav::Costmap worldCostmap(int world_id, bool lflh_inflation) {
  const core::WorldSpec world = core::readWorldFile(std::string(BARN_SOURCE_DIR) + "/worlds/world_" +
                                                    std::to_string(world_id) + ".yaml");
  const sim::ObstacleField field = sim::ObstacleField::fromWorld(world);
  nav::CostmapConfig config = nav::NavStackConfig::defaultGlobalCostmap();
  if (lflh_inflation) {  // the LfLH / Inventec inflation (LflhConfig::lflhNav: inscribed radius 0.165 + 0.075; cost 0 past 2.1 m)
    config.inflation_radius = 5.0;
    config.cost_scaling_factor = 3.0;
  }
  nav::Costmap costmap(config, lflh_inflation ? 0.24 : nav::NavStackConfig{}.inscribedRadius(config));
  const Eigen::Vector2d odom_origin(-2.0, 3.0);
  for (const auto& c : field.centres) costmap.markObstacle(c - odom_origin);
  costmap.update();
  return costmap;
}

// One global plan from scratch (a new field) on a dense world: the planner's worst case.
void BM_GlobalPlan(benchmark::State& state) {
  const nav::Costmap costmap = worldCostmap(static_cast<int>(state.range(0)), state.range(1) > 0);
  nav::PlannerConfig planner_config;
  if (state.range(2) > 0) planner_config.algorithm = nav::PlannerAlgorithm::NavFn;  // a full propagation every plan
  nav::GlobalPlanner planner(planner_config);
  std::size_t plans = 0;
  std::size_t found = 0;
  for (auto _ : state) {
    // Alternate between two goals so each plan recomputes the whole field.
    const Eigen::Vector2d goal(plans % 2 ? 0.12 : 0.02, 10.0);
    auto plan = planner.plan(costmap, {0.0, 0.0}, goal);
    benchmark::DoNotOptimize(plan.path.data());
    found += plan.found ? 1 : 0;
    ++plans;
  }
  state.counters["expanded_cells"] = static_cast<double>(planner.lastExpanded());
  state.counters["found"] = plans > 0 ? static_cast<double>(found) / static_cast<double>(plans) : 0.0;
}
// Args: world id, LfLH inflation, navfn (0 = dijkstra).
BENCHMARK(BM_GlobalPlan)
    ->Args({299, 0, 0})->Args({299, 1, 0})->Args({150, 1, 0})
    ->Args({299, 0, 1})->Args({299, 1, 1})->Args({150, 1, 1})
    ->Unit(benchmark::kMicrosecond);

// One ROS global_planner/GlobalPlanner plan (algorithm global_planner, its ROS defaults: a
// full expansion every plan, as ROS does) on the same costmaps and goals as BM_GlobalPlan, to
// compare with its navfn rows. "reached": the expansion reached the goal; "found": a path was
// also traced (GradientPath on A*'s sparse potentials often runs out of steps instead).
// Args: world id, LfLH inflation, use_dijkstra (0 = A*), use_grid_path.
void BM_RosGlobalPlan(benchmark::State& state) {
  const nav::Costmap costmap = worldCostmap(static_cast<int>(state.range(0)), state.range(1) > 0);
  nav::PlannerConfig planner_config;
  planner_config.algorithm = nav::PlannerAlgorithm::GlobalPlanner;
  planner_config.global_planner.use_dijkstra = state.range(2) > 0;
  planner_config.global_planner.use_grid_path = state.range(3) > 0;
  nav::RosGlobalPlanner planner(planner_config.global_planner);
  std::size_t plans = 0;
  std::size_t found = 0;
  std::size_t reached = 0;
  for (auto _ : state) {
    const Eigen::Vector2d goal(plans % 2 ? 0.12 : 0.02, 10.0);
    auto plan = planner.plan(costmap, core::Pose2{0.0, 0.0, 1.57}, goal, 0.0);
    benchmark::DoNotOptimize(plan.path.data());
    found += plan.found ? 1 : 0;
    reached += planner.lastReached() ? 1 : 0;
    ++plans;
  }
  const double n = plans > 0 ? static_cast<double>(plans) : 1.0;
  state.counters["expanded_cells"] = static_cast<double>(planner.lastExpanded());
  state.counters["found"] = static_cast<double>(found) / n;
  state.counters["reached"] = static_cast<double>(reached) / n;
}
BENCHMARK(BM_RosGlobalPlan)
    ->Args({299, 0, 1, 0})->Args({299, 1, 1, 0})->Args({150, 1, 1, 0})
    ->Args({299, 0, 0, 0})->Args({299, 1, 0, 0})->Args({150, 1, 0, 0})
    ->Args({299, 1, 0, 1})->Args({150, 1, 0, 1})
    ->Unit(benchmark::kMicrosecond);

// One replan after a costmap update that marks (then, next time, clears) an obstacle, as a new
// scan does: either one cell beside the robot, which the dijkstra planner repairs its field for
// (or, past a few dozen changed cells, searches again), or a 0.15 m cylinder 2 m ahead, the
// common case in a run: with the LfLH inflation thousands of cells change cost, so the field is
// searched again from the part the change cannot have touched.
void BM_GlobalReplan(benchmark::State& state) {
  nav::Costmap costmap = worldCostmap(static_cast<int>(state.range(0)), state.range(1) > 0);
  nav::GlobalPlanner planner({});
  const bool cylinder = state.range(2) > 0;
  const Eigen::Vector2d start(0.0, 0.0), goal(0.0, 10.0);
  const Eigen::Vector2d centre = cylinder ? Eigen::Vector2d(0.3, 2.0) : Eigen::Vector2d(0.05, 0.6);
  std::vector<Eigen::Vector2d> marks = {centre};
  if (cylinder) {  // every cell centre inside the cylinder
    marks.clear();
    for (double dy = -0.075; dy <= 0.075; dy += 0.05)
      for (double dx = -0.075; dx <= 0.075; dx += 0.05)
        if (std::hypot(dx, dy) <= 0.08) marks.push_back(centre + Eigen::Vector2d(dx, dy));
  }
  const double half = cylinder ? 0.1 : 0.02;  // of the square cleared again
  planner.plan(costmap, start, goal);
  std::size_t plans = 0;
  for (auto _ : state) {
    state.PauseTiming();
    if (plans % 2 == 0) {
      for (const auto& m : marks) costmap.markObstacle(m);
    } else {
      costmap.clearPolygon({centre + Eigen::Vector2d(-half, -half), centre + Eigen::Vector2d(half, -half),
                            centre + Eigen::Vector2d(half, half), centre + Eigen::Vector2d(-half, half)});
    }
    costmap.update();  // the inflation brought up to date outside the timing
    state.ResumeTiming();
    auto plan = planner.plan(costmap, start, goal);
    benchmark::DoNotOptimize(plan.path.data());
    ++plans;
  }
  state.counters["expanded_cells"] = static_cast<double>(planner.lastExpanded());
}
// Args: world id, LfLH inflation, change (0 = one cell beside the robot, 1 = a cylinder ahead).
BENCHMARK(BM_GlobalReplan)
    ->Args({299, 0, 0})->Args({299, 1, 0})->Args({299, 1, 1})->Args({150, 1, 1})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
