// What the external protocol costs barn per control tick: encoding an observation (720 beams,
// with and without a 10 m global plan and a changed 10 x 10 m local costmap) and parsing a
// command answer.
//
//   build-bench/tests/perf/barn_protocol_benchmark

#include <benchmark/benchmark.h>

#include <cmath>
#include <limits>
#include <vector>

#include "barn/external/external_protocol.hpp"

namespace {

using namespace barn;

core::LaserScan scan720() {
  core::LaserScan scan;
  for (int i = 0; i < 720; ++i)
    scan.ranges.push_back(i % 7 == 0 ? std::numeric_limits<double>::infinity() : 1.0 + 0.01 * std::sin(0.37 * i) + i * 1e-3);
  return scan;
}

void BM_ObservationMessage(benchmark::State& state) {
  const bool with_plan = state.range(0) != 0;
  const core::LaserScan scan = scan720();
  controllers::GlobalPlan plan;
  for (int i = 0; i < 400; ++i) plan.poses.push_back({0.001 * i, 0.025 * i, 0.0});  // 10 m at half a cell
  std::vector<std::uint8_t> costs(200 * 200, 0);
  controllers::CostGrid grid{{-5.0, -5.0}, 0.05, 200, 200, costs.data(), 0};
  controllers::Observation obs;
  obs.scan = &scan;
  obs.odom_pose = {0.1234567, 2.3456789, 1.5678901};
  if (with_plan) {
    obs.global_plan = &plan;
    obs.local_costmap = &grid;
  }
  external::CostmapsSent sent;
  for (auto _ : state) {
    ++grid.version;  // a new map every tick (the local costmap's 20 Hz updates)
    benchmark::DoNotOptimize(external::observationMessage(obs, sent));
  }
}
BENCHMARK(BM_ObservationMessage)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_CommandAnswer(benchmark::State& state) {
  const std::string line = R"({"v": 0.4182736451, "w": -1.2039481723, "state": "Forward", "params": {"global_costmap.inflation_radius": 0.55}})";
  for (auto _ : state) benchmark::DoNotOptimize(external::readCommandAnswer(line));
}
BENCHMARK(BM_CommandAnswer)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
