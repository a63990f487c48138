#include "barn/controllers/vfh_fuzzy.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "barn/controllers/in2bot.hpp"
#include "barn/controllers/rrsl_vfh.hpp"
#include "tests/controllers/scan_fixtures.hpp"

namespace barn::controllers {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

/// A 720-beam scan seeing nothing, with `range` on the beams whose reversed index (0 = the
/// leftmost beam, as the team's code numbers them) is in [first, last].
core::LaserScan scanWithReversedBeams(int first, int last, double range) {
  core::LaserScan scan = uniformScan(core::LidarConfig{}, kInf);
  for (int i = first; i <= last; ++i) scan.ranges[static_cast<std::size_t>(719 - i)] = range;
  return scan;
}

// ---------------------------------------------------------------------------------------------
// Fuzzy arithmetic
// ---------------------------------------------------------------------------------------------

TEST(FuzzyUniverse, FillsLikeNumpysArange) {
  // np.arange(0, 0.7 + 0.01, 0.01): ceil(0.71 / 0.01) = 71 points, the last 0 + 70 * 0.01,
  // which is 0.7000000000000001 in binary.
  const std::vector<double> speed = arange({0.0, 0.7 + 0.01, 0.01});
  ASSERT_EQ(speed.size(), 71u);
  EXPECT_EQ(speed.back(), 70 * 0.01);
  EXPECT_GT(speed.back(), 0.7);
  // np.arange(-pi, pi + 0.01, 0.01): ceil(629.3...) = 630 points; numpy steps by
  // (-pi + 0.01) - (-pi), not by 0.01, so the last is -pi + 629 * that step.
  const double pi = std::numbers::pi;
  const std::vector<double> turn = arange({-pi, pi + 0.01, 0.01});
  ASSERT_EQ(turn.size(), 630u);
  EXPECT_EQ(turn[1], -pi + 0.01);
  EXPECT_EQ(turn.back(), -pi + 629 * ((-pi + 0.01) - (-pi)));
  EXPECT_NE(turn.back(), -pi + 629 * 0.01);
}

TEST(FuzzyMembership, TrapezoidAndTriangleAsScikitFuzzy) {
  // trapmf [-0.9, 0, 0, 0.9]: 1 at 0, ramps of 0.9 either side.
  const std::vector<double> xs = {-1.0, -0.45, 0.0, 0.45, 0.9, 1.0};
  const std::vector<double> trap = membership(xs, std::vector<double>{-0.9, 0.0, 0.0, 0.9});
  const std::vector<double> want_trap = {0.0, 0.5, 1.0, 0.5, 0.0, 0.0};
  for (std::size_t i = 0; i < xs.size(); ++i) EXPECT_DOUBLE_EQ(trap[i], want_trap[i]) << xs[i];
  // trimf [0, 1, 2] at 0.5 and 1.5: half.
  const std::vector<double> tri = membership(std::vector<double>{0.0, 0.5, 1.0, 1.5, 2.0}, std::vector<double>{0.0, 1.0, 2.0});
  EXPECT_EQ(tri, (std::vector<double>{0.0, 0.5, 1.0, 0.5, 0.0}));
  // A triangle with its peak at its right end ([a, b, b]) is 1 at b and 0 past it.
  const std::vector<double> ramp = membership(std::vector<double>{0.5, 1.0, 1.5}, std::vector<double>{0.0, 1.0, 1.0});
  EXPECT_EQ(ramp, (std::vector<double>{0.5, 1.0, 0.0}));
}

TEST(FuzzyCentroid, IsTheExactCentroidOfThePiecewiseLinearShape) {
  // A right triangle on [0, 1] rising to 1: centroid 2/3.
  EXPECT_NEAR(*centroid(std::vector<double>{0.0, 1.0}, std::vector<double>{0.0, 1.0}), 2.0 / 3.0, 1e-15);
  // Rectangle [0, 1] at 0.5 and a triangle falling from 0.5 to 0 on [1, 2]: areas 0.5 and
  // 0.25, centroids 0.5 and 1 + 1/3: (0.25 + 0.25 * 4/3) / 0.75 = 7/9.
  EXPECT_NEAR(*centroid(std::vector<double>{0.0, 1.0, 2.0}, std::vector<double>{0.5, 0.5, 0.0}), 7.0 / 9.0, 1e-15);
}

TEST(FuzzyCentroid, AllZeroHasNoCentroid) {
  // scikit-fuzzy raises "Crisp output cannot be calculated" here.
  EXPECT_FALSE(centroid(std::vector<double>{0.0, 1.0, 2.0}, std::vector<double>{0.0, 0.0, 0.0}).has_value());
}

/// Two rules on grids holding every breakpoint, so the arithmetic can be done by hand.
FuzzySystemConfig twoRuleSystem() {
  FuzzySystemConfig c;
  c.input = {0.0, 2.01, 0.5};   // 0, 0.5, 1, 1.5, 2
  c.output = {0.0, 4.01, 1.0};  // 0, 1, 2, 3, 4
  c.rules = {{{0.0, 0.0, 1.0}, {0.0, 1.0, 2.0}}, {{0.0, 1.0, 2.0}, {2.0, 3.0, 4.0}}};
  return c;
}

TEST(MamdaniSystem, CutsCombinesAndTakesTheCentroidByHand) {
  // Input 0.25, interpolated on the input grid: rule A fires 0.75 (between 1 at 0 and 0.5 at
  // 0.5), rule B 0.25. A's triangle on [0, 2] cut at 0.75 is a trapezoid of area
  // (2 + 0.5) / 2 * 0.75 = 0.9375 about 1; B's on [2, 4] cut at 0.25 one of area
  // (2 + 1.5) / 2 * 0.25 = 0.4375 about 3. The output grid gains the cut points 0.75, 1.25,
  // 2.25, 3.75 so the cuts are exact: centroid (0.9375 * 1 + 0.4375 * 3) / 1.375 = 1.6364.
  const MamdaniSystem system(twoRuleSystem());
  EXPECT_NEAR(*system.compute(0.25), (0.9375 * 1 + 0.4375 * 3) / 1.375, 1e-12);
}

TEST(MamdaniSystem, NoRuleFiringGivesNoOutput) {
  // Input 2: A is 0 past 1 and B's triangle ends at 2; above the universe the input is
  // clipped to 2 first (scikit-fuzzy's clip_to_bounds).
  const MamdaniSystem system(twoRuleSystem());
  EXPECT_FALSE(system.compute(2.0).has_value());
  EXPECT_FALSE(system.compute(7.0).has_value());
}

TEST(MamdaniSystem, TheTeamsSpeedSystem) {
  const MamdaniSystem speed(rrslSpeedFuzzy());
  // Danger 1 fires Near alone: High's triangle [0.35, 0.525, 0.7] sampled every 0.01 is
  // symmetric about 0.525, so its centroid is 0.525.
  EXPECT_NEAR(*speed.compute(1.0), 0.525, 1e-12);
  // Danger 0 (clear) fires Very_Near alone -> Very_High [0.525, 0.7, 0.7537] on a universe
  // ending at 0.7; danger 4 fires Very_Far alone -> Very_Low [-0.175, 0, 0.175] from 0. The two
  // sampled shapes are mirror images about 0.35 (to 1e-14 at 0.7), so the speeds add up to 0.7.
  const double clear = *speed.compute(0.0), blocked = *speed.compute(4.0);
  EXPECT_NEAR(clear + blocked, 0.7, 1e-12);
  // The sampling moves each a little from the continuous triangle's 0.525 + 2/3 * 0.175 =
  // 0.6417: the ramp starts at the grid point 0.52. Reference: a NumPy transcription of
  // scikit-fuzzy 0.5.0's ControlSystemSimulation / defuzz (the package itself cannot be
  // installed here) gives 0.64157150625339876.
  EXPECT_NEAR(clear, 0.64157150625339876, 1e-15);
  EXPECT_LT(clear, 0.525 + 2.0 / 3.0 * 0.175);
  // More danger, less speed.
  EXPECT_GT(*speed.compute(0.5), *speed.compute(1.5));
  EXPECT_GT(*speed.compute(1.5), *speed.compute(2.9));
}

TEST(MamdaniSystem, TheTeamsTurnSystemTurnsLeftForLeftSectors) {
  const MamdaniSystem turn(rrslTurnFuzzy());
  // Sector 45 fires "zero" alone: its triangle [-pi/2, 0, pi/2] is nearly symmetric on the
  // grid -pi + 0.01 k, so about 0 rad/s (the grid misses 0 by 0.0016).
  EXPECT_NEAR(*turn.compute(45.0), 0.0, 1e-5);
  // Left sectors (small numbers) turn left (positive), right ones right.
  EXPECT_GT(*turn.compute(10.0), 1.5);
  EXPECT_LT(*turn.compute(80.0), -1.5);
  // Straight ahead is sector 46 (45.5 rounded to even), which the team's system reads as a
  // little right: the NumPy reference gives -0.098961026048816444 rad/s.
  EXPECT_NEAR(*turn.compute(46.0), -0.098961026048816444, 1e-15);
}

// ---------------------------------------------------------------------------------------------
// Histogram, valleys, candidates
// ---------------------------------------------------------------------------------------------

TEST(VfhHistogram, MeansTheDangerOverSectorsOfEightReversedBeams) {
  // Reversed beams 40..47 (sector 5, 0-based) at 1 m: danger 4 - 1 = 3 each, mean 3. Beam 48
  // at 3 m alone in sector 6: (4 - 3) / 8 = 0.125. Everything else sees nothing: clipped to
  // 4 m, danger 0.
  core::LaserScan scan = scanWithReversedBeams(40, 47, 1.0);
  scan.ranges[719 - 48] = 3.0;
  const std::vector<double> h = polarHistogram(reversedRanges(scan, 4.0), 4.0, 8);
  ASSERT_EQ(h.size(), 90u);
  EXPECT_DOUBLE_EQ(h[5], 3.0);
  EXPECT_DOUBLE_EQ(h[6], 0.125);
  EXPECT_DOUBLE_EQ(h[4], 0.0);
  EXPECT_DOUBLE_EQ(h[89], 0.0);
  // Blocked above 0.9 + 2 = 2.9: sector 5 only.
  const std::vector<bool> blocked = blockedSectors(h, 0.9);
  for (std::size_t i = 0; i < blocked.size(); ++i) EXPECT_EQ(blocked[i], i == 5) << i;
}

TEST(VfhHistogram, TheReversedScanStartsAtTheLeftmostBeam) {
  core::LaserScan scan = uniformScan(core::LidarConfig{}, kInf);
  scan.ranges.front() = 1.0;  // beam 0: -135 deg, the right rear
  const std::vector<double> reversed = reversedRanges(scan, 4.0);
  EXPECT_EQ(reversed.back(), 1.0);
  EXPECT_EQ(reversed.front(), 4.0);  // +inf clipped to max_range
}

TEST(VfhValleys, SectorsToClearForTheTeamsRobot) {
  // 2 asin(0.6 / 1.8) = 38.94 deg over 3 deg sectors: 12.98 -> 12.
  EXPECT_EQ(sectorsToClear(0.6, 0.9), 12);
}

TEST(VfhValleys, UseTheTeamsNumberingWithTheLeftEdgeValleyFromZero) {
  // 0-based sectors 30..39 blocked: free runs 0..29 and 40..89. The team's numbering is
  // 1-based, 1..30 and 41..90, but a run from the left edge begins at 0.
  std::vector<bool> blocked(90, false);
  for (int i = 30; i <= 39; ++i) blocked[static_cast<std::size_t>(i)] = true;
  EXPECT_EQ(findValleys(blocked, 12), (std::vector<Valley>{{0, 30}, {41, 90}}));
  // A free run of 10 sectors (0-based 10..19, team's 11..20): width 10 < 12, no valley.
  std::vector<bool> narrow(90, true);
  for (int i = 10; i <= 19; ++i) narrow[static_cast<std::size_t>(i)] = false;
  EXPECT_TRUE(findValleys(narrow, 12).empty());
  // Twelve free sectors (11..22) are enough.
  narrow[20] = narrow[21] = false;
  EXPECT_EQ(findValleys(narrow, 12), (std::vector<Valley>{{11, 22}}));
}

TEST(VfhValleys, CandidateHeadingIsTheMiddleOrTheClampedTarget) {
  // Width 60 - 41 = 19 <= 22: the middle 50.5, rounded half to even: 50.
  EXPECT_EQ(valleyHeading(46, {41, 60}, 22), 50);
  // Width 49 > 22: the target clamped into [41 + 12, 90 - 12] = [53, 78].
  EXPECT_EQ(valleyHeading(46, {41, 90}, 22), 53);
  EXPECT_EQ(valleyHeading(60, {41, 90}, 22), 60);
  EXPECT_EQ(valleyHeading(85, {41, 90}, 22), 78);
  // The left-edge valley 0..30 (width 30): [12, 18].
  EXPECT_EQ(valleyHeading(46, {0, 30}, 22), 18);
  // No valley: the target itself.
  EXPECT_EQ(candidateHeadings({}, 46, 22), (std::vector<int>{46}));
}

TEST(VfhSearch, PicksTheCheapestCandidateWithTheSwitchingPenalty) {
  const VfhSearch search;  // step 0.6, depth 2, weights 0.1 and 0.2
  const std::vector<int> candidates = {18, 53};
  // Previous heading at the target 46: 18 costs 0.6 + 0.1 * 28 + 0.2 * 28 = 9.0 a step,
  // 53 costs 0.6 + 0.7 + 1.4 = 2.7: 53.
  EXPECT_EQ(chooseCandidate(candidates, 46, 46.0, search), 53);
  // Previous heading 20: 18 costs 0.6 + 2.8 + 0.4 = 3.8, 53 costs 0.6 + 0.7 + 6.6 = 7.9: the
  // penalty keeps the robot on its side.
  EXPECT_EQ(chooseCandidate(candidates, 46, 20.0, search), 18);
  // 40 and 52 cost 0.6 + 0.6 + 1.2 each around target 46: a tie, to the lower sector.
  EXPECT_EQ(chooseCandidate(std::vector<int>{40, 52}, 46, 46.0, search), 40);
}

TEST(VfhTarget, MapsTheRelativeBearingToSectors) {
  // Straight ahead: (0 + 135) * 89 / 270 + 1 = 45.5, rounded half to even: 46.
  EXPECT_EQ(targetSector(0.0, 90, 270.0), 46);
  EXPECT_EQ(targetSector(-135.0, 90, 270.0), 1);   // 135 deg left
  EXPECT_EQ(targetSector(135.0, 90, 270.0), 90);   // 135 deg right
  EXPECT_EQ(targetSector(170.0, 90, 270.0), 90);   // clipped
  // 90 deg right: 225 * 89 / 270 + 1 = 75.17 -> 75.
  EXPECT_EQ(targetSector(90.0, 90, 270.0), 75);
  // Facing +y, a target on +x is 90 deg to the right (positive).
  EXPECT_NEAR(relativeBearingDeg({0.0, 0.0, std::numbers::pi / 2}, {1.0, 0.0}), 90.0, 1e-12);
  EXPECT_NEAR(relativeBearingDeg({0.0, 0.0, std::numbers::pi / 2}, {-1.0, 1.0}), -45.0, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// One tick
// ---------------------------------------------------------------------------------------------

const core::Pose2 kFacingY{0.0, 0.0, std::numbers::pi / 2};
const Eigen::Vector2d kAhead{0.0, 10.0};

TEST(VfhFuzzyStep, AClearFieldAlignedWithTheTargetRunsAtTheClearPathSpeed) {
  VfhFuzzy vfh{VfhConfig{}};
  const VfhStep step = vfh.step(uniformScan(core::LidarConfig{}, kInf), kFacingY, kAhead);
  EXPECT_EQ(step.target_sector, 46);
  EXPECT_EQ(step.candidate, 46);  // one valley, 0..90: the target clamped into [12, 78]
  EXPECT_EQ(step.action, VfhAction::ClearPath);
  EXPECT_EQ(step.command.linear, 2.0);
  EXPECT_NEAR(step.command.angular, -0.098961026048816444, 1e-15);  // sector 46, see above
}

TEST(VfhFuzzyStep, TheSafetyBubbleBacksOffTurningTowardTheClearerSide) {
  // A return at 0.3 m on reversed beam 400 (right of the centre beam 360, inside the bubble
  // 270..450): the left half (270..359) is clear, so turn left while backing off.
  VfhFuzzy right_blocked{VfhConfig{}};
  const VfhStep left = right_blocked.step(scanWithReversedBeams(400, 400, 0.3), kFacingY, kAhead);
  EXPECT_EQ(left.action, VfhAction::SafetyBubble);
  EXPECT_EQ(left.command.linear, -0.4);
  EXPECT_EQ(left.command.angular, 0.5);
  // The mirror image: the return on the left (reversed beam 320) turns right.
  VfhFuzzy left_blocked{VfhConfig{}};
  const VfhStep right = left_blocked.step(scanWithReversedBeams(320, 320, 0.3), kFacingY, kAhead);
  EXPECT_EQ(right.action, VfhAction::SafetyBubble);
  EXPECT_EQ(right.command.angular, -0.5);
  // Equal clearance both sides goes right (the team's `left > right` is false).
  VfhFuzzy both{VfhConfig{}};
  core::LaserScan scan = scanWithReversedBeams(320, 320, 0.3);
  scan.ranges[719 - 400] = 0.3;
  EXPECT_EQ(both.step(scan, kFacingY, kAhead).command.angular, -0.5);
}

TEST(VfhFuzzyStep, SmoothingAveragesWithThePreviousHeading) {
  // Tick 1: a clear field, heading 46. Tick 2: the target 90 deg right (sector 75, inside
  // the clamp [12, 78]) -> candidate 75, smoothed 0.5 * 75 + 0.5 * 46 = 60.5.
  VfhFuzzy vfh{VfhConfig{}};
  const core::LaserScan clear = uniformScan(core::LidarConfig{}, kInf);
  EXPECT_EQ(vfh.step(clear, kFacingY, kAhead).heading, 46.0);
  const VfhStep turned = vfh.step(clear, kFacingY, {10.0, 0.0});
  EXPECT_EQ(turned.candidate, 75);
  EXPECT_EQ(turned.heading, 60.5);
  // Without smoothing (IN2BOT) the heading is the candidate.
  VfhFuzzy plain{In2botConfig::in2botVfh()};
  plain.step(clear, kFacingY, kAhead);
  EXPECT_EQ(plain.step(clear, kFacingY, {10.0, 0.0}).heading, 75.0);
}

TEST(VfhFuzzyStep, AFuzzySystemWithNoRuleFiringHaltsLikeTheTeamsNode) {
  // A turn system covering sectors 0..2 only: heading 46 fires nothing. scikit-fuzzy raises,
  // the node dies, the robot stops: the step says Halted with a zero command.
  VfhConfig config;
  config.turn_fuzzy.rules = {{{0.0, 1.0, 2.0}, {-1.0, 0.0, 1.0}}};
  VfhFuzzy vfh{config};
  const VfhStep step = vfh.step(uniformScan(core::LidarConfig{}, kInf), kFacingY, kAhead);
  EXPECT_EQ(step.action, VfhAction::Halted);
  EXPECT_EQ(step.command.linear, 0.0);
  EXPECT_EQ(step.command.angular, 0.0);
}

TEST(RrslVfh, StopsForGoodWithinHalfAMetreOfTheGoal) {
  RrslVfhController controller{RrslVfhConfig{}};
  EpisodeInfo info;
  controller.reset(info);
  const core::LaserScan scan = uniformScan(core::LidarConfig{}, kInf);
  Observation obs;
  obs.scan = &scan;
  obs.goal = {0.0, 10.0};
  obs.odom_pose = {0.0, 9.6, std::numbers::pi / 2};  // 0.4 m from the goal
  const core::Twist stop = controller.act(obs);
  EXPECT_EQ(stop.linear, 0.0);
  EXPECT_EQ(controller.stateLabel(), "GoalStop");
  obs.odom_pose = {0.0, 5.0, std::numbers::pi / 2};  // the node has quit: still nothing
  EXPECT_EQ(controller.act(obs).linear, 0.0);
  controller.reset(info);
  EXPECT_EQ(controller.act(obs).linear, 2.0);  // a new episode drives again
}

TEST(RrslVfh, RejectsALidarWithTooFewBeamsForTheSpeedSectors) {
  RrslVfhController controller{RrslVfhConfig{}};
  core::LidarConfig lidar;
  lidar.beams = 400;  // 50 sectors of 8; the speed input reads sectors up to 55
  EXPECT_THROW(controller.checkLidar(lidar), core::InputError);
  EXPECT_NO_THROW(controller.checkLidar(core::LidarConfig{}));
}

}  // namespace
}  // namespace barn::controllers
