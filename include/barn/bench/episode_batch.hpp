#pragma once
/// N episodes stepped together, for reinforcement learning (barnbench.VecEnv in Python).
///
/// Each of the N sub-environments runs one episode at a time on a world drawn from a list, at
/// an action repeat of `dt` seconds, optionally with move_base's stack beside it (a
/// GlobalPlanFeed, as a `global_plan` block gives a controller). step() applies one (v, w) per
/// sub-environment, advances all of them in worker threads (a small pool of the batch's own,
/// see episode_batch.cpp: OpenMP's barrier stalls a step per call when the machine has more
/// runnable threads than cores) and writes the observations,
/// rewards and flags into arrays this object owns, row i for sub-environment i, so a caller
/// (numpy) can read them in place. A sub-environment whose episode ended is reset at once:
/// its row then holds the new episode's first observation, and the ended episode's last
/// observation and result are kept in the `final` arrays (Gymnasium's autoreset convention).
///
/// Seeds: sub-environment i's k-th episode (k = 0, 1, ... since the last reset(seed)) has the
/// episode seed episodeSeedOf(seed, i, k) and the world worlds[worldIndexOf(seed, i, k, W)],
/// whatever the thread count or the other sub-environments do, so the batches are identical
/// for 1 or 2 threads.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "barn/bench/episode.hpp"
#include "barn/controllers/global_plan_feed.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/world.hpp"

namespace barn::bench {

/// The reward of one step:
///   progress * (d_before - d_after) + step + (success | collision | timeout on the last step)
/// d is the distance from the odometry pose to the goal [m] (as barnbench.Env's default reward
/// computes it). A step that ends in an error (a non-finite action) gets no end term.
struct RewardConfig {
  double progress = 1.0;
  double step = 0.0;
  double success = 10.0;
  double collision = -10.0;
  double timeout = 0.0;
  template <class V> void visit(V& v) {
    v("progress", progress,
      {.unit = "1/m", .doc = "per metre the goal came closer (Env's default; E2E's goal_reward 1)"});
    v("step", step, {.doc = "every step (E2E's slack_reward; 0 there)"});
    v("success", success, {.doc = "on success (Env's default; E2E: 20)"});
    v("collision", collision, {.doc = "on a collision (Env's default; E2E: -1)"});
    v("timeout", timeout, {.doc = "on a timeout or truncation (E2E's failure_reward; 0 there)"});
  }
};
void validate(const RewardConfig& config, core::Errors& errors, const std::string& prefix);

struct EpisodeBatchConfig {
  int num_envs = 1;          // [-] sub-environments
  double dt = 0.05;          // [s] action repeat: one step is this much simulated time
  long max_steps = 0;        // [-] truncate an episode after this many steps (0: the protocol's timeout only)
  RewardConfig reward;
  EpisodeConfig episode;     // the sim config (robot, LiDAR, physics, protocol, success radius)
  std::optional<controllers::GlobalPlanConfig> global_plan;  // move_base's stack beside each episode
  int plan_points = 0;       // [-] with global_plan: the plan resampled at this many points (0: only its end)
  double plan_spacing = 0.25;  // [m] ... this far apart along it, from its first pose
  int threads = 0;           // [-] threads stepping the batch, the caller's included (0: all cores); never changes a result
};
/// Checks the fields; `prefix` names them in messages.
void validate(const EpisodeBatchConfig& config, core::Errors& errors, const std::string& prefix);

/// The seed of sub-environment `index`'s episode number `count` after reset(seed).
std::uint64_t episodeSeedOf(std::uint64_t seed, int index, std::uint64_t count);
/// The world that episode runs on: an index into a list of `worlds` (uniform, seeded).
std::size_t worldIndexOf(std::uint64_t seed, int index, std::uint64_t count, std::size_t worlds);

/// An episode's outcome as the batch reports it (Outcome, and Running before the end).
enum class BatchOutcome : std::int8_t { Running = 0, Success = 1, Collision = 2, Timeout = 3, Error = 4 };

/// One set of observation arrays: row i belongs to sub-environment i. Row-major, contiguous.
struct BatchObservation {
  std::vector<float> scan;        // N x beams [m], +inf for no return
  std::vector<double> pose;       // N x 3 odom frame (x, y, yaw)
  std::vector<double> scan_pose;  // N x 3 the odometry when the scan was taken
  std::vector<double> twist;      // N x 2 (v, w)
  std::vector<double> goal;       // N x 2 odom frame
  std::vector<double> time;       // N [s] simulated, since the episode began
  // With global_plan: the plan's last pose (x, y; the goal while no plan was found), when it
  // was made (-1: none yet), and plan_points poses resampled along it (x, y, yaw).
  std::vector<double> plan_end;    // N x 2
  std::vector<double> plan_stamp;  // N
  std::vector<double> plan;        // N x plan_points x 3
  // With send_local_costmap / send_global_costmap: the maps (costs, rows from the lower edge
  // up) and their lower-left corners in the odom frame.
  std::vector<std::uint8_t> local_costmap;   // N x height x width
  std::vector<double> local_costmap_origin;  // N x 2
  std::vector<std::uint8_t> global_costmap;
  std::vector<double> global_costmap_origin;
};

/// What a sub-environment's episode is (or was, in `final`) beyond its observation.
struct BatchInfo {
  std::vector<std::int8_t> outcome;      // N BatchOutcome
  std::vector<double> score;             // N BARN score (0 unless success)
  std::vector<double> actual_time;       // N [s] AT, the protocol's elapsed time at the end
  std::vector<std::int32_t> world;       // N world id
  std::vector<std::uint64_t> seed;       // N episode seed
  std::vector<std::int32_t> length;      // N steps taken in the episode
  std::vector<double> episode_return;    // N sum of its rewards
};

class EpisodeBatch {
 public:
  /// `worlds` must be non-empty; InputError for a bad config (naming the field) or a world a
  /// robot cannot start in.
  EpisodeBatch(std::vector<core::WorldSpec> worlds, const EpisodeBatchConfig& config);
  ~EpisodeBatch();
  EpisodeBatch(const EpisodeBatch&) = delete;
  EpisodeBatch& operator=(const EpisodeBatch&) = delete;

  /// Starts every sub-environment's episode number 0 of `seed`'s streams.
  void reset(std::uint64_t seed);
  /// Starts every sub-environment's next episode of the current streams (abandoning those
  /// running), as reset() without a seed does in Gymnasium.
  void resetNext();
  /// Applies actions[2 i], actions[2 i + 1] = (v, w) to sub-environment i for dt seconds.
  /// Fills reward, terminated, truncated, the observation and info; where an episode ended,
  /// also final_observation/final_info, ended[i] = 1, and starts the next episode.
  void step(const double* actions);

  int size() const { return config_.num_envs; }
  int beams() const { return beams_; }
  /// Costmap shapes (height, width), 0 until the first reset or without the map.
  std::pair<int, int> localCostmapShape() const { return local_shape_; }
  std::pair<int, int> globalCostmapShape() const { return global_shape_; }
  const EpisodeBatchConfig& config() const { return config_; }
  const std::vector<core::WorldSpec>& worlds() const { return worlds_; }
  bool started() const { return started_; }

  BatchObservation observation;
  BatchObservation final_observation;
  BatchInfo info;
  BatchInfo final_info;
  std::vector<double> reward;             // N
  std::vector<std::uint8_t> terminated;   // N success, collision or error
  std::vector<std::uint8_t> truncated;    // N timeout (the protocol's or max_steps)
  std::vector<std::uint8_t> ended;        // N terminated or truncated this step (final_* valid)

 private:
  struct Slot;
  class Pool;
  void startEpisode(int i);
  void writeObservation(int i, BatchObservation& out);
  void writeInfo(int i, BatchInfo& out, BatchOutcome outcome);
  void sizeCostmaps();
  void stepOne(int i, double v, double w);

  EpisodeBatchConfig config_;
  std::vector<core::WorldSpec> worlds_;
  std::vector<sim::ObstacleField> fields_;
  std::vector<std::unique_ptr<Slot>> slots_;
  std::unique_ptr<Pool> pool_;
  int beams_ = 0;
  std::pair<int, int> local_shape_{0, 0}, global_shape_{0, 0};
  std::uint64_t seed_ = 0;
  bool started_ = false;
};

/// The timing reference of a batch (tools/bench_vec_env.py): the same episodes as an
/// EpisodeBatch with `config` (the same worlds, seeds, dt, max_steps and threads; no stack
/// beside them) stepped `steps` times with `action` in every sub-environment, restarted as the
/// batch restarts them, but bench::Episode alone: no observation arrays, rewards or infos.
/// Returns the simulated seconds stepped and the wall and process CPU seconds the stepping took
/// (the episodes' construction included, the worlds' preparation not).
struct BareRun {
  double simulated = 0.0;  // [s]
  double wall = 0.0;       // [s]
  double cpu = 0.0;        // [s] of every thread of the process
};
BareRun runBareEpisodes(const std::vector<core::WorldSpec>& worlds, const EpisodeBatchConfig& config, std::uint64_t seed,
                       const core::Twist& action, long steps);

}  // namespace barn::bench
