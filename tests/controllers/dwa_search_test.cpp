#include "controllers/dwa_search.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include "barn/core/rect.hpp"

namespace barn::controllers {
namespace {

// A small deterministic generator (the test's own, so it does not depend on the library's).
struct Lcg {
  std::uint64_t state;
  double uniform() {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  }
  double between(double a, double b) { return a + (b - a) * uniform(); }
};

// What TrajectoryPlanner::findBestPath picks when every sample is scored point by point
// (rollOut), in upstream's order: the forward arcs (the straight one first, then the turn rates
// from the bottom of the window), the lowest cost winning and the earlier one on a tie; then
// each in-place rotation that costs no more and whose end looks nearer the local goal
// heading_lookahead ahead; else the blind back-up (cost -1 counting as 1). The window's
// samples are made by repeated addition, as upstream makes them.
DwaTrajectory exhaustiveBestPath(DwaSearch& search, const nav::Costmap& map, const DwaConfig& config,
                                 const core::Pose2& pose, const core::Twist& velocity) {
  const DwaSearch::SampleWindow w = search.sampleWindow(velocity);
  std::optional<DwaTrajectory> best;
  const auto consider = [&](const DwaTrajectory& t) {
    if (t.cost >= 0.0 && (!best || t.cost < best->cost)) best = t;
  };
  double vx = w.min_x;
  for (int i = 0; i < config.vx_samples; ++i, vx += w.dvx) {
    consider(search.rollOut(pose, velocity, vx, 0.0));
    double vth = w.min_th;
    for (int j = 0; j < config.vtheta_samples - 1; ++j, vth += w.dvth) consider(search.rollOut(pose, velocity, vx, vth));
  }
  double heading_distance = std::numeric_limits<double>::max();
  double sample = w.min_th;
  for (int j = 0; j < config.vtheta_samples; ++j, sample += w.dvth) {
    if (!(std::abs(sample) > w.dvth)) continue;  // a fresh search is stuck neither way
    const double vth = sample > 0 ? std::max(sample, config.min_in_place_vel_theta)
                                  : std::min(sample, -config.min_in_place_vel_theta);
    const DwaTrajectory t = search.rollOut(pose, velocity, 0.0, vth);
    if (t.cost < 0.0 || (best && t.cost > best->cost)) continue;
    nav::CellIndex ahead;
    const Eigen::Vector2d look = t.end.position() + config.heading_lookahead * Eigen::Vector2d(std::cos(t.end.yaw), std::sin(t.end.yaw));
    if (!map.toCell(look, ahead)) continue;
    const double ahead_distance = search.goalDistance(ahead);
    if (!(ahead_distance < heading_distance)) continue;
    best = t;
    heading_distance = ahead_distance;
  }
  if (best) return *best;
  DwaTrajectory escape = search.rollOut(pose, velocity, config.escape_vel, 0.0);
  if (escape.cost == -1.0) escape.cost = 1.0;
  return escape;
}

TEST(DwaSearch, PrunedSearchPicksWhatScoringEverySamplePicks) {
  // Random cluttered local costmaps (BARN's DWA inflation), random robot headings and
  // velocities, a straight global path to a random goal 2-4 m away: the bounded search must
  // choose the sample, and give the cost, that rolling out every sample does.
  const DwaConfig config;
  nav::CostmapConfig c = config.nav.local_costmap;
  c.rolling = false;
  c.width = c.height = 6.0;
  c.origin_x = c.origin_y = -3.0;
  Lcg rng{42};
  int compared = 0, forward = 0, rotations = 0, escapes = 0;
  for (int trial = 0; trial < 300; ++trial) {
    nav::Costmap map(c, config.nav.inscribedRadius(c));
    const int obstacles = static_cast<int>(rng.between(0, 60));
    for (int k = 0; k < obstacles; ++k) {
      const Eigen::Vector2d p(rng.between(-2.8, 2.8), rng.between(-2.8, 2.8));
      if (p.norm() > 0.45) map.markObstacle(p);  // nothing under the robot
    }
    map.update();
    const core::Pose2 pose{0.0, 0.0, rng.between(-std::numbers::pi, std::numbers::pi)};
    const double bearing = pose.yaw + rng.between(-2.0, 2.0), length = rng.between(2.0, 4.0) * (trial % 7 == 0 ? 0.2 : 1.0);
    nav::Path path;
    for (double s = 0.0; s <= length; s += 0.025) path.push_back(s * Eigen::Vector2d(std::cos(bearing), std::sin(bearing)));
    const core::Twist velocity{rng.between(0.0, config.max_vel_x), rng.between(-config.max_vel_theta, config.max_vel_theta)};
    const core::Rect body = core::Rect::centred(config.nav.footprint_length, config.nav.footprint_width)
                                .grownBy(config.nav.footprint_padding);
    const auto corners = body.corners();
    const std::vector<Eigen::Vector2d> footprint(corners.begin(), corners.end());

    DwaSearch pruned(config, footprint);
    pruned.updateDistanceMaps(map, &path, pose);
    const DwaTrajectory got = pruned.findBestPath(map, pose, velocity);
    DwaSearch reference(config, footprint);
    reference.updateDistanceMaps(map, &path, pose);
    const DwaTrajectory want = exhaustiveBestPath(reference, map, config, pose, velocity);
    SCOPED_TRACE("trial " + std::to_string(trial));
    EXPECT_EQ(got.vx, want.vx);
    EXPECT_EQ(got.vtheta, want.vtheta);
    EXPECT_EQ(got.cost, want.cost);
    ++compared;
    if (want.vx > 0.0) ++forward;
    else if (want.vx == 0.0) ++rotations;
    else ++escapes;
  }
  EXPECT_EQ(compared, 300);
  // The scenes exercise every branch of the search.
  EXPECT_GT(forward, 50);
  EXPECT_GT(rotations, 5);
  EXPECT_GT(escapes, 2);
}

}  // namespace
}  // namespace barn::controllers
