// Google Benchmark of the ut_amrl controller's two planners (built with -DBARN_BUILD_BENCHMARKS=ON):
//   BM_VoronoiPlan  one global planning cycle (memory update, Boost.Polygon Voronoi diagram,
//                   both searches, the hysteresis) with the memory a drive along world 150's
//                   corridor leaves; counters: remembered points and graph nodes
//   BM_LocalArcs    one local planning tick: 31 arcs against a 720-beam scan and the evaluator
// Run: build/tests/perf/barn_ut_amrl_benchmark --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <cmath>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "barn/controllers/arc_planner.hpp"
#include "barn/controllers/voronoi_planner.hpp"
#include "barn/core/world_file.hpp"
#include "barn/sim/lidar.hpp"

namespace {

using namespace barn;

// World 150 (fill 0.25), scans from poses along its A* path through the field (cell centres
// (-4.425 + 0.15 r, 5.175 + 0.15 c), heading along the path), in the odom frame of a robot
// that started at (-2, 3) facing +y.
struct Fixture {
  core::WorldSpec world = core::readWorldFile(std::string(BARN_SOURCE_DIR) + "/worlds/world_150.yaml");
  sim::ObstacleField field = sim::ObstacleField::fromWorld(world);
  core::LidarConfig lidar;
  std::vector<core::Pose2> poses;      // world frame
  std::vector<core::LaserScan> scans;
  Fixture() {
    sim::LidarCaster caster(lidar, field);
    std::vector<Eigen::Vector2d> line = {{-2.0, 3.0}};
    for (const core::Cell& c : world.path) line.emplace_back(-4.425 + 0.15 * c.row, 5.175 + 0.15 * c.col);
    for (std::size_t k = 1; k < line.size(); ++k) {
      const Eigen::Vector2d d = line[k] - line[k - 1];
      if (d.norm() < 1e-9) continue;
      poses.push_back({line[k].x(), line[k].y(), std::atan2(d.y(), d.x())});
      core::LaserScan scan;
      scan.angle_min = lidar.angle_min;
      scan.angle_increment = lidar.angleIncrement();
      scan.range_min = lidar.range_min;
      scan.range_max = lidar.range_max;
      caster.cast(lidar.sensorPose(poses.back()), scan.ranges);
      scans.push_back(std::move(scan));
    }
  }
  core::Pose2 odom(std::size_t i) const { return {poses[i].x + 2.0, poses[i].y - 3.0, poses[i].yaw}; }
};

void BM_VoronoiPlan(benchmark::State& state) {
  Fixture f;
  controllers::VoronoiPlanner planner{controllers::VoronoiPlannerConfig{}};
  for (std::size_t i = 0; i < f.scans.size(); ++i) planner.plan(f.scans[i], f.odom(i), f.lidar.sensorPose(f.odom(i)));
  std::size_t i = f.scans.size() - 1;
  for (auto _ : state) {
    // Back and forth over the last few poses: the memory stays at what the drive left.
    i = i == f.scans.size() - 1 ? f.scans.size() - 8 : i + 1;
    benchmark::DoNotOptimize(planner.plan(f.scans[i], f.odom(i), f.lidar.sensorPose(f.odom(i))));
  }
  state.counters["memory"] = static_cast<double>(planner.memory().size());
  state.counters["nodes"] = static_cast<double>(planner.lastGraphNodes());
}
BENCHMARK(BM_VoronoiPlan)->Unit(benchmark::kMicrosecond);

void BM_LocalArcs(benchmark::State& state) {
  Fixture f;
  const core::LaserScan& scan = f.scans.back();
  std::vector<Eigen::Vector2d> points;
  for (std::size_t i = 0; i < scan.ranges.size(); ++i)
    if (std::isfinite(scan.ranges[i]))
      points.emplace_back(0.12 + scan.ranges[i] * std::cos(scan.angle(i)), scan.ranges[i] * std::sin(scan.angle(i)));
  const controllers::ArcPlannerConfig config;
  const Eigen::Vector2d target(1.5, 0.3);
  for (auto _ : state) {
    const auto arcs = controllers::sampleArcs(target, points, 0.8, 0.5, config);
    benchmark::DoNotOptimize(controllers::chooseArc(arcs, target, points, config));
  }
}
BENCHMARK(BM_LocalArcs)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
