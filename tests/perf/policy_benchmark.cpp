// Google Benchmark of one LfLH policy call (built with -DBARN_BUILD_BENCHMARKS=ON):
//   BM_PolicyAct   Policy::act on a 720-beam scan: clip, 722-256-256-2 MLP in float (goal < 50 us)
// Run: build-bench/tests/perf/barn_policy_benchmark --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <limits>

#include <benchmark/benchmark.h>

#include "barn/core/lidar_config.hpp"
#include "barn/learning/policy.hpp"

namespace {

using namespace barn;

void BM_PolicyAct(benchmark::State& state) {
  const learning::Policy policy = learning::Policy::load(std::string(BARN_SOURCE_DIR) + "/configs/policies/lflh_1ms.policy");
  // A scan with returns on every third beam (the rest +inf), so clipping sees both cases.
  core::LaserScan scan;
  const core::LidarConfig lidar;
  scan.angle_min = lidar.angle_min;
  scan.angle_increment = lidar.angleIncrement();
  scan.ranges.assign(720, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < 720; i += 3) scan.ranges[i] = 0.5 + 0.004 * static_cast<double>(i);
  double turn = 0.0;
  for (auto _ : state) {
    const core::Twist twist = policy.act(scan, {1.0, 0.2 + 1e-9 * turn});
    turn += twist.angular;
    benchmark::DoNotOptimize(turn);
  }
}
BENCHMARK(BM_PolicyAct)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
