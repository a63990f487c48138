#include "barn/learning/hallucination.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "barn/core/errors.hpp"
#include "barn/learning/policy.hpp"
#include "barn/sim/obstacle_field.hpp"

namespace barn::learning {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();

double uniform(core::Rng& rng, double lo, double hi) { return lo + (hi - lo) * rng.uniform01(); }

// The pose `b` in the frame of pose `a`.
core::Pose2 relative(const core::Pose2& a, const core::Pose2& b) {
  const Eigen::Vector2d p = a.inverseTransform(b.position());
  return {p.x(), p.y(), core::wrapAngle(b.yaw - a.yaw)};
}

// Distance from q to the circular sector with apex `apex`, axis angle `heading`, radius
// `radius` and half-angle `half` <= pi/2 (a convex set): 0 inside.
double sectorDistance(const Eigen::Vector2d& q, const Eigen::Vector2d& apex, double heading, double radius, double half) {
  const Eigen::Vector2d d = q - apex;
  const double rho = d.norm();
  const double off_axis = std::abs(core::wrapAngle(std::atan2(d.y(), d.x()) - heading));
  if (off_axis <= half) return std::max(0.0, rho - radius);
  // Nearest point on the closer edge segment apex -> apex + radius e.
  const double side = core::wrapAngle(std::atan2(d.y(), d.x()) - heading) > 0.0 ? 1.0 : -1.0;
  const Eigen::Vector2d e(std::cos(heading + side * half), std::sin(heading + side * half));
  const double t = std::clamp(d.dot(e), 0.0, radius);
  return (d - t * e).norm();
}

// A random obstacle shape at the origin: a circle of radius U[size_min, size_max] with
// probability circle_share, else an ellipse with a ~ U[size_min, size_max] and
// b ~ U[max(size_min, a / max_aspect), a] at a random orientation.
Obstacle randomShape(core::Rng& rng, double circle_share, double size_min, double size_max, double max_aspect) {
  const double a = uniform(rng, size_min, size_max);
  if (rng.uniform01() < circle_share) return makeObstacle(Eigen::Vector2d::Zero(), a, a, 0.0);
  const double b = uniform(rng, std::min(a, std::max(size_min, a / max_aspect)), a);
  return makeObstacle(Eigen::Vector2d::Zero(), a, b, uniform(rng, 0.0, kPi));
}

// An obstacle placed at a gap `clearance` from the swept footprint.
struct Placed {
  Obstacle obstacle;
  double clearance = 0.0;  // [m]
};

// Draws obstacles that hug a swept footprint (steps 2 and 2b of the header), from `rng`.
class Placer {
 public:
  Placer(const SweptFootprint& swept, const HallucinationConfig& config, core::Rng& rng)
      : swept_(swept), poses_(swept.poses()), config_(config), rng_(rng) {}

  // One hugging obstacle: from a random pose of the sweep, pushed out sideways (path normal,
  // left or right, +- direction_jitter).
  std::optional<Placed> hugging() {
    const core::Pose2& anchor = poses_[static_cast<std::size_t>(rng_.below(poses_.size()))];
    const double side = rng_.uniform01() < 0.5 ? 1.0 : -1.0;
    const double direction = anchor.yaw + side * 0.5 * kPi + uniform(rng_, -config_.direction_jitter, config_.direction_jitter);
    return pushed(anchor.position(), direction);
  }

  // One blocking obstacle (the same push, but forward): it explains why the motion slows or
  // turns. Half start at a random pose of the sweep and are pushed along that pose's heading
  // (the last pose gives a wall just past where the motion ends); half are pushed straight ahead
  // of the robot (x axis), so on a turning motion they land where going straight would collide.
  std::optional<Placed> blocking() {
    const bool along_pose = rng_.uniform01() < 0.5;
    // Anchors biased to the later part of the motion (the square root of a uniform draw).
    const double u = std::sqrt(rng_.uniform01());
    const std::size_t index = std::min(poses_.size() - 1, static_cast<std::size_t>(u * static_cast<double>(poses_.size())));
    const core::Pose2& anchor = along_pose ? poses_[index] : poses_[static_cast<std::size_t>(rng_.below(poses_.size()))];
    const double direction = (along_pose ? anchor.yaw : 0.0) + uniform(rng_, -config_.blocking_jitter, config_.blocking_jitter);
    return pushed(anchor.position(), direction);
  }

 private:
  // A random shape with a random clearance, pushed from `from` along `direction`.
  std::optional<Placed> pushed(const Eigen::Vector2d& from, double direction) {
    const double clearance = uniform(rng_, config_.clearance_min, config_.clearance_max);
    const Obstacle shape = randomShape(rng_, config_.circle_share, config_.size_min, config_.size_max, config_.max_aspect);
    std::optional<Obstacle> placed = pushOut(shape, from, direction, clearance);
    if (!placed) return std::nullopt;
    return Placed{std::move(*placed), clearance};
  }

  // Slides `shape` from `from` along `direction` until its gap to the sweep is the clearance
  // (+ the sweep's bulge allowance): each step covers the clearance still missing, so it stops
  // at the first valid spot. One that has not arrived within kMaxPush (a ray grazing the
  // sweep) is dropped.
  std::optional<Obstacle> pushOut(const Obstacle& shape, const Eigen::Vector2d& from, double direction,
                                  double clearance) const {
    constexpr int kMaxIterations = 200;
    constexpr double kMaxPush = 4.0;     // [m]
    constexpr double kOvershoot = 1e-7;  // [m] each step goes this far past the estimate
    const Eigen::Vector2d ray(std::cos(direction), std::sin(direction));
    const double target = clearance + swept_.inflation();
    double push = 0.0;
    Obstacle placed = translated(shape, from);
    double missing = target - swept_.gap(placed);
    for (int it = 0; it < kMaxIterations && missing > 0.0 && push < kMaxPush; ++it) {
      push += missing + kOvershoot;
      placed = translated(shape, from + push * ray);
      missing = target - swept_.gap(placed);
    }
    if (missing > 0.0) return std::nullopt;
    return placed;
  }

  const SweptFootprint& swept_;
  const std::vector<core::Pose2>& poses_;
  const HallucinationConfig& config_;
  core::Rng& rng_;
};

// Step 3: distractors, kept clear of the sweep and of the velocity sector along the motion.
void addDistractors(Demonstration& demo, const SweptFootprint& swept, const Recording& recording, std::size_t record,
                    const HallucinationConfig& config, core::Rng& rng) {
  constexpr int kSectorPoses = 10;
  constexpr int kTries = 10;
  constexpr double kBearingLimit = 0.75 * kPi;  // +-135 degrees, the LiDAR's field of view
  const std::size_t horizon_steps = demo.motion.size() - 1;
  for (int n = 0; n < config.distractors; ++n) {
    for (int attempt = 0; attempt < kTries; ++attempt) {
      const double distance = uniform(rng, 0.0, config.distractor_distance);
      const double bearing = uniform(rng, -kBearingLimit, kBearingLimit);
      const Obstacle candidate = translated(
          randomShape(rng, config.circle_share, config.distractor_size_min, config.distractor_size_max, config.max_aspect),
          distance * Eigen::Vector2d(std::cos(bearing), std::sin(bearing)));
      bool ok = swept.gap(candidate) >= config.clearance_min + swept.inflation();
      for (int m = 0; ok && m < kSectorPoses; ++m) {
        const std::size_t k = static_cast<std::size_t>(std::lround(static_cast<double>(m * horizon_steps) / (kSectorPoses - 1)));
        const core::Pose2& pose = demo.motion[k];
        const double v = recording.records[record + k].v;
        const double heading = v >= 0.0 ? pose.yaw : pose.yaw + kPi;
        for (const Disk& d : candidate.disks) {
          if (sectorDistance(d.centre, pose.position(), heading, std::abs(v) * config.sector_time, config.sector_half_angle) <
              d.radius) {
            ok = false;
            break;
          }
        }
      }
      if (ok) {
        demo.obstacles.push_back(candidate);
        break;
      }
    }
  }
}

}  // namespace

// ---------------------------------------------------------------------------
// Constraining placement

std::vector<SweptFootprint> alternativeSweeps(const HallucinationConfig& config, double horizon, const core::Rect& footprint) {
  // Poses every kPoseStep of travel along each constant (v, w) motion from the origin; the sweep
  // fills in between them.
  constexpr double kPoseStep = 0.05;  // [m]
  std::vector<SweptFootprint> sweeps;
  for (int i = 1; i <= config.alternative_speeds; ++i) {
    const double v = config.alternative_speed * i / config.alternative_speeds;
    for (int j = 0; j < config.alternative_turns; ++j) {
      const double w = config.alternative_turns == 1
                           ? 0.0
                           : config.alternative_turn_rate * (-1.0 + 2.0 * j / (config.alternative_turns - 1));
      const int steps = std::max(1, static_cast<int>(std::ceil(v * horizon / kPoseStep)));
      std::vector<core::Pose2> motion;
      for (int k = 0; k <= steps; ++k) {
        const double t = horizon * k / steps;
        // The exact arc (a straight line in the limit w -> 0).
        const double yaw = w * t;
        const double x = std::abs(w) < 1e-9 ? v * t : v / w * std::sin(yaw);
        const double y = std::abs(w) < 1e-9 ? 0.0 : v / w * (1.0 - std::cos(yaw));
        motion.push_back({x, y, yaw});
      }
      sweeps.emplace_back(motion, footprint, config.sweep_step * 2.5);
    }
  }
  return sweeps;
}

std::vector<std::size_t> mostConstraining(const std::vector<Obstacle>& candidates,
                                          const std::vector<SweptFootprint>& alternatives, std::size_t most) {
  // Which alternatives each candidate blocks, as bits.
  std::vector<std::uint64_t> blocks(candidates.size(), 0);
  for (std::size_t c = 0; c < candidates.size(); ++c)
    for (std::size_t a = 0; a < alternatives.size() && a < 64; ++a)
      if (alternatives[a].gap(candidates[c]) < 0.0) blocks[c] |= std::uint64_t{1} << a;
  std::vector<std::size_t> chosen;
  std::uint64_t covered = 0;
  while (chosen.size() < most) {
    std::size_t best = candidates.size();
    int best_gain = 0;
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      const int gain = std::popcount(blocks[c] & ~covered);
      if (gain > best_gain) {  // ties: the earlier draw
        best_gain = gain;
        best = c;
      }
    }
    if (best == candidates.size()) break;  // nothing left to rule out
    chosen.push_back(best);
    covered |= blocks[best];
  }
  return chosen;
}

// ---------------------------------------------------------------------------
// Shapes

std::vector<Disk> ellipseDisks(const Eigen::Vector2d& centre, double a, double b, double orientation) {
  if (a - b <= 1e-9 * a) return {{centre, a}};
  const double focal2 = a * a - b * b;          // a^2 - b^2
  const double medial = focal2 / a;             // half-length of the medial axis
  const double vertex_radius = b * b / a;       // radius of the end disks
  const int count = 1 + static_cast<int>(std::ceil(2.0 * medial / vertex_radius));
  const Eigen::Vector2d axis(std::cos(orientation), std::sin(orientation));
  std::vector<Disk> disks;
  disks.reserve(static_cast<std::size_t>(count));
  for (int j = 0; j < count; ++j) {
    const double x = medial * (-1.0 + 2.0 * j / (count - 1));
    const double r = b * std::sqrt(std::max(0.0, 1.0 - x * x / focal2));
    disks.push_back({centre + x * axis, r});
  }
  return disks;
}

Obstacle makeObstacle(const Eigen::Vector2d& centre, double a, double b, double orientation) {
  Obstacle o;
  o.centre = centre;
  o.semi_major = a;
  o.semi_minor = b;
  o.orientation = orientation;
  o.disks = ellipseDisks(centre, a, b, orientation);
  return o;
}

Obstacle translated(const Obstacle& obstacle, const Eigen::Vector2d& offset) {
  Obstacle o = obstacle;
  o.centre += offset;
  for (Disk& d : o.disks) d.centre += offset;
  return o;
}

std::vector<Obstacle> mirrored(const std::vector<Obstacle>& obstacles) {
  std::vector<Obstacle> out = obstacles;
  for (Obstacle& o : out) {
    o.centre.y() = -o.centre.y();
    o.orientation = -o.orientation;
    for (Disk& d : o.disks) d.centre.y() = -d.centre.y();
  }
  return out;
}

// ---------------------------------------------------------------------------
// Swept footprint

SweptFootprint::SweptFootprint(const std::vector<core::Pose2>& motion, const core::Rect& footprint, double step)
    : footprint_(footprint), step_(step) {
  const double corner = footprint.farthestCornerDistance();
  for (std::size_t k = 0; k < motion.size(); ++k) {
    if (k == 0) {
      poses_.push_back(motion[0]);
      continue;
    }
    const core::Pose2& a = motion[k - 1];
    const core::Pose2& b = motion[k];
    const double turn = core::wrapAngle(b.yaw - a.yaw);
    // A footprint point moves at most |dp| + corner |dyaw| between the two poses.
    const double travel = std::hypot(b.x - a.x, b.y - a.y) + corner * std::abs(turn);
    const int pieces = std::max(1, static_cast<int>(std::ceil(travel / step)));
    for (int j = 1; j <= pieces; ++j) {
      const double s = static_cast<double>(j) / pieces;
      poses_.push_back({a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), core::wrapAngle(a.yaw + s * turn)});
    }
  }
  cos_.reserve(poses_.size());
  sin_.reserve(poses_.size());
  for (const core::Pose2& p : poses_) {
    cos_.push_back(std::cos(p.yaw));
    sin_.push_back(std::sin(p.yaw));
  }
}

double SweptFootprint::distance(const Eigen::Vector2d& p) const {
  double best2 = kInf;
  for (std::size_t k = 0; k < poses_.size(); ++k) {
    const double wx = p.x() - poses_[k].x;
    const double wy = p.y() - poses_[k].y;
    const double lx = cos_[k] * wx + sin_[k] * wy;  // p in the frame of pose k
    const double ly = -sin_[k] * wx + cos_[k] * wy;
    best2 = std::min(best2, footprint_.squaredDistance({lx, ly}));
    if (best2 == 0.0) return 0.0;
  }
  return std::sqrt(best2);
}

double SweptFootprint::gap(const Obstacle& obstacle) const {
  double best = kInf;
  for (const Disk& d : obstacle.disks) best = std::min(best, distance(d.centre) - d.radius);
  return best;
}

// ---------------------------------------------------------------------------
// Demonstrations

std::optional<Demonstration> hallucinate(const Recording& recording, std::size_t record, int render,
                                         const HallucinationConfig& config, const core::RobotConfig& robot,
                                         const core::LidarConfig& lidar) {
  const auto& records = recording.records;
  const auto steps = [&](double seconds) { return static_cast<std::size_t>(std::lround(seconds * recording.rate)); };
  const std::size_t goal_steps = steps(config.goal_time);
  const std::size_t lookahead = std::max(goal_steps, steps(config.horizon_max));
  if (record + lookahead >= records.size()) return std::nullopt;

  const core::Pose2 origin = records[record].pose;
  Demonstration demo;
  demo.record = record;
  demo.command = records[record].command;
  const Eigen::Vector2d goal = origin.inverseTransform(records[record + goal_steps].pose.position());
  if (goal.norm() < config.min_goal_distance) return std::nullopt;
  demo.goal = goal.normalized();

  core::Rng rng(core::mixSeed(config.seed, record, static_cast<std::uint64_t>(render)));
  const std::size_t horizon_steps = std::max<std::size_t>(1, steps(uniform(rng, config.horizon_min, config.horizon_max)));
  for (std::size_t k = 0; k <= horizon_steps; ++k) demo.motion.push_back(relative(origin, records[record + k].pose));
  const core::Rect footprint = core::Rect::centred(robot.footprint_length, robot.footprint_width);
  const SweptFootprint swept(demo.motion, footprint, config.sweep_step);

  Placer placer(swept, config, rng);
  const auto keep = [&](Placed placed) {
    demo.obstacles.push_back(std::move(placed.obstacle));
    demo.clearances.push_back(placed.clearance);
  };
  if (config.candidates == 0) {
    const int hugging = config.constraining_min +
                        static_cast<int>(rng.below(static_cast<std::uint64_t>(config.constraining_max - config.constraining_min + 1)));
    for (int n = 0; n < hugging; ++n)
      if (auto placed = placer.hugging()) keep(std::move(*placed));
    const int blocking = config.blocking_max <= 0 ? 0 : config.blocking_min +
                         static_cast<int>(rng.below(static_cast<std::uint64_t>(config.blocking_max - config.blocking_min + 1)));
    for (int n = 0; n < blocking; ++n)
      if (auto placed = placer.blocking()) keep(std::move(*placed));
  } else {
    // Constraining placement: of `candidates` drawn obstacles, keep those that rule out the most
    // alternative motions (hallucination.hpp, step 2c).
    const std::vector<SweptFootprint> alternatives =
        alternativeSweeps(config, static_cast<double>(horizon_steps) / recording.rate, footprint);
    std::vector<Obstacle> candidates;
    std::vector<double> clearances;
    for (int n = 0; n < config.candidates; ++n) {
      std::optional<Placed> placed = rng.uniform01() < 0.5 ? placer.hugging() : placer.blocking();
      if (!placed) continue;
      candidates.push_back(std::move(placed->obstacle));
      clearances.push_back(placed->clearance);
    }
    for (const std::size_t k : mostConstraining(candidates, alternatives, static_cast<std::size_t>(config.constraining_max)))
      keep({candidates[k], clearances[k]});
  }
  demo.hugging = demo.obstacles.size();
  addDistractors(demo, swept, recording, record, config, rng);

  core::FastNoise noise(rng.below(std::numeric_limits<std::uint64_t>::max()));
  demo.ranges = renderScan(demo.obstacles, lidar, &noise);
  return demo;
}

std::vector<double> renderScan(const std::vector<Obstacle>& obstacles, const core::LidarConfig& lidar,
                               core::FastNoise* noise) {
  sim::ObstacleField field;
  for (const Obstacle& o : obstacles) {
    for (const Disk& d : o.disks) {
      field.centres.push_back(d.centre);
      field.radii.push_back(d.radius);
    }
  }
  if (field.centres.empty()) {
    // No obstacle at all: every beam misses (an empty `radii` would mean "uniform radius").
    return std::vector<double>(static_cast<std::size_t>(lidar.beams), kInf);
  }
  sim::LidarCaster caster(lidar, field);
  return caster.scan({0.0, 0.0, 0.0}, 0.0, noise).ranges;
}

// ---------------------------------------------------------------------------
// Dataset

void mirrorExample(float* input, float* target, int beams) {
  std::reverse(input, input + beams);
  input[beams + 1] = -input[beams + 1];
  target[1] = -target[1];
}

Dataset buildDataset(const Recording& recording, const HallucinationConfig& config, double range_clip,
                     const core::RobotConfig& robot, const core::LidarConfig& lidar) {
  Dataset data;
  data.beams = lidar.beams;
  data.record_count = recording.records.size();
  data.lookahead = static_cast<std::size_t>(
      std::lround(std::max(config.goal_time, config.horizon_max) * recording.rate));
  const int rows = lidar.beams + 2;
  std::vector<float> inputs, targets;
  for (std::size_t record = 0; record < recording.records.size(); record += static_cast<std::size_t>(config.stride)) {
    for (int render = 0; render < config.renders_per_sample; ++render) {
      const auto demo = hallucinate(recording, record, render, config, robot, lidar);
      if (!demo) continue;
      const std::size_t at = inputs.size();
      inputs.resize(at + static_cast<std::size_t>(rows));
      encodeInput(demo->ranges, demo->goal, range_clip, inputs.data() + at);
      targets.push_back(static_cast<float>(demo->command.linear));
      targets.push_back(static_cast<float>(demo->command.angular));
      data.records.push_back(record);
    }
  }
  const auto n = static_cast<Eigen::Index>(data.records.size());
  data.inputs = Eigen::Map<const Eigen::MatrixXf>(inputs.data(), rows, n);
  data.targets = Eigen::Map<const Eigen::MatrixXf>(targets.data(), 2, n);
  return data;
}

void appendDataset(Dataset& into, const Dataset& more) {
  if (more.beams != into.beams || more.inputs.rows() != into.inputs.rows())
    throw core::InputError("joining datasets of " + std::to_string(into.beams) + " and " + std::to_string(more.beams) + " beams");
  const Eigen::Index before = into.inputs.cols();
  into.inputs.conservativeResize(into.inputs.rows(), before + more.inputs.cols());
  into.inputs.rightCols(more.inputs.cols()) = more.inputs;
  into.targets.conservativeResize(2, before + more.targets.cols());
  into.targets.rightCols(more.targets.cols()) = more.targets;
  for (std::size_t r : more.records) into.records.push_back(into.record_count + r);
  for (std::size_t start : more.recording_starts) into.recording_starts.push_back(into.record_count + start);
  into.record_count += more.record_count;
  into.lookahead = std::max(into.lookahead, more.lookahead);
}

}  // namespace barn::learning
