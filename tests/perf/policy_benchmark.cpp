// Google Benchmark of one policy call (built with -DBARN_BUILD_BENCHMARKS=ON):
//   BM_PolicyAct              Policy::act on a 720-beam scan: clip, 722-256-256-2 MLP in float (goal < 50 us)
//   BM_TransformerPolicyAct   TransformerPolicy::act, the LiCS-KI network's shape (36 patches of 20, width 32,
//                             4 heads, feed-forward 256, 3 + 3 blocks) with random weights: clip and forward
//                             pass in float (20 Hz control: well under 50 ms; goal < 1 ms)
// Run: build-bench/tests/perf/barn_policy_benchmark --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <limits>

#include <benchmark/benchmark.h>

#include "barn/core/lidar_config.hpp"
#include "barn/core/rng.hpp"
#include "barn/learning/policy.hpp"
#include "barn/learning/transformer_policy.hpp"

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

void BM_TransformerPolicyAct(benchmark::State& state) {
  // The published shape with random weights (the published ones are not shipped; the time does
  // not depend on the values): N(0, 0.2) everywhere, LayerNorm gains around 1.
  learning::TransformerPolicyInfo info;
  learning::TransformerWeights weights = learning::TransformerWeights::zeros(info.shape);
  core::Rng rng(3);
  weights.forEachTensor([&](const std::string& name, auto& tensor) {
    const bool gain = name.find("layer_norm.weight") != std::string::npos;
    for (Eigen::Index i = 0; i < tensor.size(); ++i)
      tensor.data()[i] = static_cast<float>((gain ? 1.0 : 0.0) + 0.2 * rng.normal());
  });
  const learning::TransformerPolicy policy(info, std::move(weights));
  core::LaserScan scan;
  scan.ranges.assign(720, std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < 720; i += 3) scan.ranges[i] = 0.5 + 0.004 * static_cast<double>(i);
  double turn = 0.0;
  for (auto _ : state) {
    const Eigen::Vector2d y = policy.act(scan, {1.0, 0.2 + 1e-9 * turn});
    turn += y.y();
    benchmark::DoNotOptimize(turn);
  }
}
BENCHMARK(BM_TransformerPolicyAct)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
