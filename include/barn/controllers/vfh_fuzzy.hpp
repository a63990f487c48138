#pragma once
/// VFH* with fuzzy speed and turn rate: the local planner of Michigan Tech RRSL's BARN 2025
/// entry (`rrsl_vfh`), which IN2BOT's 2026 entry (`in2bot`) reuses behind an A* path.
///
/// One control tick (VfhFuzzy::step), in the team's order:
///   1. The scan reversed (index 0 = the leftmost beam, +135 deg) and clipped at max_range.
///   2. Polar histogram: danger 4 - r per beam, its mean over sectors of 8 beams (90 sectors of
///      3 deg); a sector is blocked when its mean danger exceeds threshold + 2 (mean range
///      < 1.1 m).
///   3. The target sector: the target's bearing relative to the heading (positive to the right),
///      clipped to +-135 deg, mapped to 1..90.
///   4. Valleys: runs of free sectors at least sectToClear wide; per valley a candidate heading
///      (its middle, or the target clamped into a wide valley shrunk by 12 sectors a side).
///   5. "VFH*": a depth-2 search over the candidates, each step costing
///      step + 0.1 |c - target| + 0.2 |c - previous heading|; the cheapest leaf's root wins.
///   6. Heading smoothing (RRSL: 0.5 candidate + 0.5 previous; IN2BOT: none).
///   7. Two Mamdani fuzzy systems (scikit-fuzzy: min implication, max aggregation, centroid on
///      the discretised universe): speed from the least danger in the central +-30 deg, turn
///      rate from the smoothed heading.
///   8. Clear path: the central 121 beams all at max_range and the heading within 5 sectors of
///      the target -> 2.0 m/s. Safety bubble: a beam of the central 181 nearer than 0.45 m ->
///      back off at 0.4 m/s turning at 0.5 rad/s toward the clearer half.
///
/// Sector and beam numbers are the team's: sectors are numbered 1..90 from the left as in
/// their code (valleys on the left edge start at 0, their quirk, kept).
///
/// Sources: MazenMTULab/the-barn-challenge@6072114 navigation_pkg/scripts/{Nav-VFH.py,
/// navigation_utils.py}; scikit-fuzzy 0.5.0 (control/controlsystem.py, defuzzify/defuzz.py,
/// membership/generatemf.py, fuzzymath/fuzzy_ops.py) for the fuzzy arithmetic. No code copied.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/types.hpp"

namespace barn::controllers {

// ---------------------------------------------------------------------------------------------
// Fuzzy systems, as scikit-fuzzy computes them
// ---------------------------------------------------------------------------------------------

/// A discretised universe: numpy's arange(start, stop, step), value for value (numpy fills
/// x_i = start + i * ((start + step) - start), which is not start + i * step).
struct FuzzyUniverse {
  double start = 0.0;  // [unit of the variable]
  double stop = 1.0;   // [unit] excluded, as in arange
  double step = 0.1;   // [unit]
  template <class V> void visit(V& v) { v("start", start); v("stop", stop); v("step", step); }
};
void validate(const FuzzyUniverse& universe, core::Errors& errors, const std::string& prefix);
/// The universe's points.
std::vector<double> arange(const FuzzyUniverse& universe);

/// One rule: "if the input is `input` then the output is `output`". A set of three points is
/// scikit-fuzzy's trimf [a, b, c], of four its trapmf [a, b, c, d].
struct FuzzyRule {
  std::vector<double> input;   // [unit of the input]
  std::vector<double> output;  // [unit of the output]
  template <class V> void visit(V& v) { v("input", input); v("output", output); }
};

/// A one-input, one-output Mamdani system: the rules in the team's order.
struct FuzzySystemConfig {
  FuzzyUniverse input;
  FuzzyUniverse output;
  std::vector<FuzzyRule> rules;
  template <class V> void visit(V& v) {
    v("input", input);
    v("output", output);
    v("rules", rules);
  }
};
void validate(const FuzzySystemConfig& config, core::Errors& errors, const std::string& prefix);

/// scikit-fuzzy's trimf (3 points) or trapmf (4 points) sampled on `universe`.
std::vector<double> membership(std::span<const double> universe, std::span<const double> points);
/// numpy.interp(x, xs, ys) with zero outside [xs.front(), xs.back()] (scikit-fuzzy's
/// interp_membership).
double interpolate(std::span<const double> xs, std::span<const double> ys, double x);
/// scikit-fuzzy's centroid of the piecewise linear function through (xs, mf): the exact
/// moment over area of each segment's trapezoid. std::nullopt when the function is zero
/// everywhere (scikit-fuzzy raises "Crisp output cannot be calculated" there).
std::optional<double> centroid(std::span<const double> xs, std::span<const double> mf);

/// A Mamdani system evaluated the way scikit-fuzzy's ControlSystemSimulation does: the input
/// is clipped to its universe and fuzzified by interpolation; each rule cuts its output set at
/// its firing strength (min); the output universe gains the points where each set crosses its
/// cut; the cut sets are combined by max and defuzzified by centroid.
class MamdaniSystem {
 public:
  explicit MamdaniSystem(const FuzzySystemConfig& config);
  /// The crisp output for `input`; std::nullopt when the aggregate is zero everywhere (no rule
  /// fires): scikit-fuzzy raises an error there, which ends the team's ROS node.
  std::optional<double> compute(double input) const;

 private:
  std::vector<double> input_universe_;
  std::vector<double> output_universe_;
  std::vector<std::vector<double>> input_sets_;   // (rules x input points)
  std::vector<std::vector<double>> output_sets_;  // (rules x output points)
};

// ---------------------------------------------------------------------------------------------
// The vector field histogram and the candidate choice
// ---------------------------------------------------------------------------------------------

/// The scan reversed (index 0 = the last beam, the leftmost) with every range above
/// `max_range` (and +inf) set to max_range.
std::vector<double> reversedRanges(const core::LaserScan& scan, double max_range);
/// The polar histogram h: per sector of `sector_beams` consecutive beams, the mean of the
/// danger max_range - r (0 for r >= max_range + 0.5, which clipped ranges never reach).
/// Beams past the last whole sector are dropped. Sums are numpy's (pairwise for 8 beams).
std::vector<double> polarHistogram(std::span<const double> reversed, double max_range, int sector_beams);
/// Sectors whose mean danger exceeds threshold + 2 (the team's calc_Hb).
std::vector<bool> blockedSectors(std::span<const double> histogram, double threshold);
/// sectToClear = floor(2 asin(robot_size / (2 threshold)) [deg] / 3): the free sectors a valley
/// needs (12 for 0.6 m and 0.9).
int sectorsToClear(double robot_size, double threshold);

/// A valley: sectors begin..end in the team's numbering (1-based; a valley on the left edge
/// begins at 0, as the team's find_valleys gives it).
struct Valley {
  int begin = 0;
  int end = 0;
  friend bool operator==(const Valley&, const Valley&) = default;
};
/// Runs of free sectors whose width (end - begin + 1) is at least `min_width`, left to right.
std::vector<Valley> findValleys(const std::vector<bool>& blocked, int min_width);
/// The team's pick_heading: a valley of width (end - begin) <= wide_valley_min gives its middle
/// (rounded half to even), a wider one the target clamped into [begin + b, end - b] with
/// b = ceil(wide_valley_min / 2) + 1.
int valleyHeading(int target, const Valley& valley, int wide_valley_min);
/// One candidate per valley, sorted, duplicates removed; {target} when there is no valley.
std::vector<int> candidateHeadings(std::span<const Valley> valleys, int target, int wide_valley_min);

/// The weights of the team's depth-limited search over the candidates.
struct VfhSearch {
  double step = 0.6;           // [m] projected step per depth (the team's ds)
  int depth = 2;               // [-] ng
  double target_weight = 0.1;  // [1/sector] cost per sector between candidate and target
  double switch_weight = 0.2;  // [1/sector] cost per sector between candidate and previous heading
};
/// The root candidate of the cheapest sequence of `depth` candidates, each step costing
/// step + target_weight |c - target| + switch_weight |c - previous|. Exact ties (which the
/// team's code settles by Python's set and heap order) go to the candidate nearer the target,
/// then to the lower sector.
int chooseCandidate(std::span<const int> candidates, int target, double previous, const VfhSearch& search);

/// The target's bearing relative to the heading [deg], positive when the target is to the
/// right (the team's Th), wrapped to (-180, 180].
double relativeBearingDeg(const core::Pose2& pose, const Eigen::Vector2d& target);
/// The team's calc_Target: round((clip(Th, -fov/2, fov/2) + fov/2) * (sectors - 1) / fov + 1),
/// half to even: 1 = the leftmost sector, straight ahead 46 of 90.
int targetSector(double relative_bearing_deg, int sectors, double fov_deg);

// ---------------------------------------------------------------------------------------------
// One control tick
// ---------------------------------------------------------------------------------------------

/// RRSL's speed system: danger (least in the central sectors) -> speed [m/s].
FuzzySystemConfig rrslSpeedFuzzy();
/// RRSL's turn system: heading [sector] -> turn rate [rad/s], left sectors turning left.
FuzzySystemConfig rrslTurnFuzzy();

struct VfhConfig {
  double max_range = 4.0;
  int sector_beams = 8;
  double threshold = 0.9;
  double robot_size = 0.6;
  int wide_valley_min = 22;
  double fov_deg = 270.0;
  double step = 0.6;
  int depth = 2;
  double target_weight = 0.1;
  double switch_weight = 0.2;
  // Heading smoothing: heading = alpha * candidate + (1 - alpha) * previous heading, the
  // previous heading also feeding the switching penalty (RRSL). Without it the heading is the
  // candidate and the penalty's previous heading stays the target sector (IN2BOT, whose
  // prev_heading is never set).
  bool smoothing = true;
  double smoothing_alpha = 0.5;
  int speed_sector_begin = 35;
  int speed_sector_end = 55;
  int clear_half_beams = 60;
  double clear_alignment = 5.0;
  double clear_speed = 2.0;
  int bubble_beams = 180;
  double bubble_distance = 0.45;
  double bubble_speed = -0.4;
  double bubble_turn = 0.5;
  FuzzySystemConfig speed_fuzzy = rrslSpeedFuzzy();
  FuzzySystemConfig turn_fuzzy = rrslTurnFuzzy();

  template <class V> void visit(V& v) {
    v("max_range", max_range, {.unit = "m", .range = core::kPositive, .doc = "team: max_range"});
    v("sector_beams", sector_beams, {.unit = "beams", .range = core::atLeast(1), .doc = "team: sector_size"});
    v("threshold", threshold,
      {.range = core::kPositive, .doc = "team: threshold (blocked above threshold + 2 danger)"});
    v("robot_size", robot_size, {.unit = "m", .doc = "team: robotDim (sectToClear)"});
    v("wide_valley_min", wide_valley_min,
      {.unit = "sectors", .range = core::kNonNegative, .doc = "team: WidevalleyMin"});
    v("fov_deg", fov_deg,
      {.unit = "deg", .range = core::openClosed(0.0, 360.0), .doc = "team: calc_Target clips to +-135 and maps 270 deg"});
    v("step", step, {.unit = "m", .range = core::kNonNegative, .doc = "team: ds = robotDim"});
    v("depth", depth, {.range = core::closed(1, 4), .doc = "team: ng"});
    v("target_weight", target_weight,
      {.unit = "1/sector", .range = core::kNonNegative, .doc = "team: cost_trajectory"});
    v("switch_weight", switch_weight,
      {.unit = "1/sector", .range = core::kNonNegative, .doc = "team: cost_trajectory switching penalty"});
    v("smoothing", smoothing, {.doc = "team (RRSL): on"});
    v("smoothing_alpha", smoothing_alpha, {.range = core::kUnit, .doc = "team: alpha"});
    v("speed_sector_begin", speed_sector_begin,
      {.unit = "sector, 0-based", .doc = "team: min(h[35:55]), the central +-30 deg"});
    v("speed_sector_end", speed_sector_end, {.unit = "sector, 0-based", .doc = "excluded"});
    v("clear_half_beams", clear_half_beams,
      {.unit = "beams", .range = core::kNonNegative, .doc = "team: centre +- 60 (121 beams, +-22.5 deg)"});
    v("clear_alignment", clear_alignment,
      {.unit = "sectors", .range = core::kNonNegative, .doc = "team: |heading - target| < 5"});
    v("clear_speed", clear_speed, {.unit = "m/s", .doc = "team"});
    v("bubble_beams", bubble_beams,
      {.unit = "beams", .range = core::kNonNegative, .doc = "team: safety_bubble_width (181 beams, +-33.75 deg)"});
    v("bubble_distance", bubble_distance, {.unit = "m", .range = core::kNonNegative, .doc = "team: safety_distance"});
    v("bubble_speed", bubble_speed, {.unit = "m/s", .doc = "team"});
    v("bubble_turn", bubble_turn,
      {.unit = "rad/s", .range = core::kNonNegative, .doc = "team, toward the clearer half"});
    v("speed_fuzzy", speed_fuzzy);
    v("turn_fuzzy", turn_fuzzy);
  }
};
void validate(const VfhConfig& config, core::Errors& errors, const std::string& prefix);
/// Throws core::InputError if a scan of `beams` beams is too short for the config's sector
/// and beam ranges (the team's numbers assume 720).
void checkVfhBeams(const VfhConfig& config, int beams);

/// What decided a tick's command (the trajectory record's state label).
enum class VfhAction {
  Steer,         ///< the fuzzy speed and turn rate
  ClearPath,     ///< the fuzzy turn rate at the clear-path speed
  SafetyBubble,  ///< backing off from something inside the bubble
  TurnInPlace,   ///< in2bot: the target is too far to the side
  WaitPath,      ///< in2bot: no path received yet
  GoalStop,      ///< rrsl_vfh: within the stop radius of the goal; the node has quit
  Halted,        ///< a fuzzy system had no rule firing: the team's node raised and quit
};
std::span<const std::string_view> enumNames(VfhAction);

/// The tick's command and what led to it (for tests and traces).
struct VfhStep {
  core::Twist command;
  VfhAction action = VfhAction::Steer;
  int target_sector = 0;   // [sector]
  int candidate = 0;       // [sector] the search's choice
  double heading = 0.0;    // [sector] after smoothing: the turn system's input
  double danger = 0.0;     // [-] the speed system's input
};

/// The shared VFH* / fuzzy local planner; remembers the previous heading between ticks.
class VfhFuzzy {
 public:
  explicit VfhFuzzy(const VfhConfig& config);
  /// Forget the previous heading (a new episode).
  void reset() { previous_heading_.reset(); }
  /// One tick toward `target` from `pose` (same frame). action is Halted when a fuzzy system
  /// had no rule firing; the command is then zero.
  VfhStep step(const core::LaserScan& scan, const core::Pose2& pose, const Eigen::Vector2d& target);

 private:
  VfhConfig config_;
  MamdaniSystem speed_;
  MamdaniSystem turn_;
  std::optional<double> previous_heading_;  // [sector] the last smoothed heading
};

}  // namespace barn::controllers
