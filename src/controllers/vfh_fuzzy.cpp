#include "barn/controllers/vfh_fuzzy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace barn::controllers {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// numpy's sum of a contiguous float64 block (np.add.reduce from its identity 0): pairwise
// summation with eight accumulators. The team's histogram divides such sums by 8, and a
// sector's blocked flag compares the result with 2.9, so the order of the additions matters
// at the boundary.
double pairwiseSum(const double* a, std::size_t n) {
  if (n < 8) {
    double sum = -0.0;
    for (std::size_t i = 0; i < n; ++i) sum += a[i];
    return sum;
  }
  if (n <= 128) {
    double r[8];
    for (std::size_t j = 0; j < 8; ++j) r[j] = a[j];
    std::size_t i = 8;
    for (; i < n - n % 8; i += 8)
      for (std::size_t j = 0; j < 8; ++j) r[j] += a[i + j];
    double sum = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
    for (; i < n; ++i) sum += a[i];
    return sum;
  }
  std::size_t half = n / 2;
  half -= half % 8;
  return pairwiseSum(a, half) + pairwiseSum(a + half, n - half);
}

double numpySum(const double* a, std::size_t n) { return 0.0 + pairwiseSum(a, n); }

// scikit-fuzzy's trimf on one point.
double triangle(double x, double a, double b, double c) {
  if (x == b) return 1.0;
  if (a != b && a < x && x < b) return (x - a) / (b - a);
  if (b != c && b < x && x < c) return (c - x) / (c - b);
  return 0.0;
}

// scikit-fuzzy's trapmf on one point: trimf(a, b, b) up to b, trimf(c, c, d) from c, zero
// outside [a, d], one between.
double trapezoid(double x, double a, double b, double c, double d) {
  if (x < a || x > d) return 0.0;
  double y = 1.0;
  if (x <= b) y = triangle(x, a, b, b);
  if (x >= c) y = triangle(x, c, c, d);
  return y;
}

// scikit-fuzzy's _interp_universe_fast: where the sampled set crosses `level`, by linear
// interpolation (at a zero level, where it leaves or returns to zero).
void appendCrossings(std::span<const double> xs, std::span<const double> mf, double level, std::vector<double>& out) {
  for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
    const bool here = level == 0.0 ? mf[i] > level : mf[i] >= level;
    const bool next = level == 0.0 ? mf[i + 1] > level : mf[i + 1] >= level;
    if (here == next) continue;
    out.push_back(xs[i] + (level - mf[i]) * (xs[i + 1] - xs[i]) / (mf[i + 1] - mf[i]));
  }
}

// interpolate() at every point of the sorted `queries`, walking the universe once.
void interpolateSorted(std::span<const double> xs, std::span<const double> ys, std::span<const double> queries,
                       std::vector<double>& out) {
  std::size_t j = 0;
  for (std::size_t i = 0; i < queries.size(); ++i) {
    const double x = queries[i];
    if (xs.empty() || x < xs.front() || x > xs.back()) {
      out[i] = 0.0;
      continue;
    }
    if (x == xs.back()) {
      out[i] = ys.back();
      continue;
    }
    while (xs[j + 1] <= x) ++j;  // xs[j] <= x < xs[j + 1]
    out[i] = xs[j] == x ? ys[j] : (ys[j + 1] - ys[j]) / (xs[j + 1] - xs[j]) * (x - xs[j]) + ys[j];
  }
}

void validateSet(const std::vector<double>& points, core::Errors& errors, const std::string& where) {
  errors.check(points.size() == 3 || points.size() == 4, where, "needs 3 points (triangle) or 4 (trapezoid)");
  errors.check(std::is_sorted(points.begin(), points.end()), where, "points must not decrease");
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Fuzzy systems
// ---------------------------------------------------------------------------------------------

void validate(const FuzzyUniverse& u, core::Errors& errors, const std::string& prefix) {
  errors.check(u.step > 0.0, prefix + ".step", "must be > 0");
  errors.check(u.stop > u.start, prefix + ".stop", "must be > start");
  if (u.step > 0.0 && u.stop > u.start)
    errors.check((u.stop - u.start) / u.step <= 1e5, prefix + ".step", "gives more than 100000 points");
}

std::vector<double> arange(const FuzzyUniverse& u) {
  const double length = std::ceil((u.stop - u.start) / u.step);
  if (!(length > 0.0)) return {};
  const auto n = static_cast<std::size_t>(length);
  std::vector<double> xs(n);
  xs[0] = u.start;
  if (n > 1) xs[1] = u.start + u.step;
  const double delta = n > 1 ? xs[1] - xs[0] : 0.0;
  for (std::size_t i = 2; i < n; ++i) xs[i] = u.start + static_cast<double>(i) * delta;
  return xs;
}

void validate(const FuzzySystemConfig& c, core::Errors& errors, const std::string& prefix) {
  validate(c.input, errors, prefix + ".input");
  validate(c.output, errors, prefix + ".output");
  errors.check(!c.rules.empty(), prefix + ".rules", "needs at least one rule");
  for (std::size_t i = 0; i < c.rules.size(); ++i) {
    const std::string where = prefix + ".rules[" + std::to_string(i) + "]";
    validateSet(c.rules[i].input, errors, where + ".input");
    validateSet(c.rules[i].output, errors, where + ".output");
  }
}

std::vector<double> membership(std::span<const double> universe, std::span<const double> p) {
  std::vector<double> mf(universe.size(), 0.0);
  for (std::size_t i = 0; i < universe.size(); ++i)
    mf[i] = p.size() == 3 ? triangle(universe[i], p[0], p[1], p[2]) : trapezoid(universe[i], p[0], p[1], p[2], p[3]);
  return mf;
}

double interpolate(std::span<const double> xs, std::span<const double> ys, double x) {
  if (xs.empty() || x < xs.front() || x > xs.back()) return 0.0;
  if (x == xs.back()) return ys.back();
  // The j with xs[j] <= x < xs[j + 1].
  const std::size_t j = static_cast<std::size_t>(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin()) - 1;
  if (xs[j] == x) return ys[j];
  const double slope = (ys[j + 1] - ys[j]) / (xs[j + 1] - xs[j]);
  return slope * (x - xs[j]) + ys[j];
}

std::optional<double> centroid(std::span<const double> xs, std::span<const double> mf) {
  double total = 0.0;
  for (double m : mf) total += m;
  if (total == 0.0) return std::nullopt;
  if (xs.size() == 1) return xs[0] * mf[0] / std::max(mf[0], std::numeric_limits<double>::epsilon());
  double moment_area = 0.0, area_sum = 0.0;
  for (std::size_t i = 1; i < xs.size(); ++i) {
    const double x1 = xs[i - 1], x2 = xs[i], y1 = mf[i - 1], y2 = mf[i];
    if ((y1 == 0.0 && y2 == 0.0) || x1 == x2) continue;
    double moment = 0.0, area = 0.0;
    if (y1 == y2) {  // rectangle
      moment = 0.5 * (x1 + x2);
      area = (x2 - x1) * y1;
    } else if (y1 == 0.0) {  // triangle rising to y2
      moment = 2.0 / 3.0 * (x2 - x1) + x1;
      area = 0.5 * (x2 - x1) * y2;
    } else if (y2 == 0.0) {  // triangle falling from y1
      moment = 1.0 / 3.0 * (x2 - x1) + x1;
      area = 0.5 * (x2 - x1) * y1;
    } else {  // trapezoid
      moment = (2.0 / 3.0 * (x2 - x1) * (y2 + 0.5 * y1)) / (y1 + y2) + x1;
      area = 0.5 * (x2 - x1) * (y1 + y2);
    }
    moment_area += moment * area;
    area_sum += area;
  }
  return moment_area / std::max(area_sum, std::numeric_limits<double>::epsilon());
}

MamdaniSystem::MamdaniSystem(const FuzzySystemConfig& config)
    : input_universe_(arange(config.input)), output_universe_(arange(config.output)) {
  for (const FuzzyRule& rule : config.rules) {
    input_sets_.push_back(membership(input_universe_, rule.input));
    output_sets_.push_back(membership(output_universe_, rule.output));
  }
}

std::optional<double> MamdaniSystem::compute(double input) const {
  if (input_universe_.empty() || output_universe_.empty()) return std::nullopt;
  // clip_to_bounds (scikit-fuzzy's default). Below the universe scikit-fuzzy 0.5.0 fails
  // (np.var.universe); neither team's input gets there.
  const double x = std::clamp(input, input_universe_.front(), input_universe_.back());
  std::vector<double> firing(input_sets_.size());
  for (std::size_t r = 0; r < input_sets_.size(); ++r) firing[r] = interpolate(input_universe_, input_sets_[r], x);

  // The output universe upsampled with the points where each set crosses its cut.
  std::vector<double> cuts;
  for (std::size_t r = 0; r < output_sets_.size(); ++r) appendCrossings(output_universe_, output_sets_[r], firing[r], cuts);
  std::sort(cuts.begin(), cuts.end());
  std::vector<double> xs(output_universe_.size() + cuts.size());
  std::merge(output_universe_.begin(), output_universe_.end(), cuts.begin(), cuts.end(), xs.begin());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());

  std::vector<double> aggregate(xs.size(), 0.0), sampled(xs.size());
  for (std::size_t r = 0; r < output_sets_.size(); ++r) {
    interpolateSorted(output_universe_, output_sets_[r], xs, sampled);
    for (std::size_t i = 0; i < xs.size(); ++i) aggregate[i] = std::max(aggregate[i], std::min(firing[r], sampled[i]));
  }
  return centroid(xs, aggregate);
}

// ---------------------------------------------------------------------------------------------
// Histogram, valleys, candidates
// ---------------------------------------------------------------------------------------------

std::vector<double> reversedRanges(const core::LaserScan& scan, double max_range) {
  std::vector<double> reversed(scan.ranges.rbegin(), scan.ranges.rend());
  for (double& r : reversed)
    if (r > max_range) r = max_range;
  return reversed;
}

std::vector<double> polarHistogram(std::span<const double> reversed, double max_range, int sector_beams) {
  const std::size_t width = static_cast<std::size_t>(sector_beams);
  const std::size_t sectors = reversed.size() / width;
  std::vector<double> danger(sectors * width);
  for (std::size_t i = 0; i < danger.size(); ++i)
    danger[i] = reversed[i] >= max_range + 0.5 ? 0.0 : max_range - reversed[i] * 1.0;
  std::vector<double> h(sectors);
  for (std::size_t s = 0; s < sectors; ++s) h[s] = numpySum(&danger[s * width], width) / static_cast<double>(width);
  return h;
}

std::vector<bool> blockedSectors(std::span<const double> histogram, double threshold) {
  std::vector<bool> blocked(histogram.size());
  for (std::size_t i = 0; i < histogram.size(); ++i) blocked[i] = histogram[i] > threshold + 2;
  return blocked;
}

int sectorsToClear(double robot_size, double threshold) {
  const double clearance_deg = 2 * std::asin(robot_size / (2 * threshold)) * 180 / std::numbers::pi;
  return static_cast<int>(std::floor(clearance_deg / 3));
}

std::vector<Valley> findValleys(const std::vector<bool>& blocked, int min_width) {
  const int n = static_cast<int>(blocked.size());
  if (n == 0) return {};
  // The team's bounds: a free run starting after a blocked sector i begins at i + 2 and one
  // ending before a blocked sector i + 1 ends at i + 1 (1-based), but a run from the left edge
  // begins at 0.
  std::vector<int> begins, ends;
  if (!blocked[0]) begins.push_back(0);
  for (int i = 0; i + 1 < n; ++i) {
    if (blocked[i] && !blocked[i + 1]) begins.push_back(i + 2);
    if (!blocked[i] && blocked[i + 1]) ends.push_back(i + 1);
  }
  if (!blocked[n - 1]) ends.push_back(n);
  std::vector<Valley> valleys;
  for (std::size_t k = 0; k < begins.size() && k < ends.size(); ++k)
    if (ends[k] - begins[k] + 1 >= min_width) valleys.push_back({begins[k], ends[k]});
  return valleys;
}

int valleyHeading(int target, const Valley& valley, int wide_valley_min) {
  const int buffer = (wide_valley_min + 1) / 2 + 1;  // ceil(wide / 2) + 1
  if (valley.end - valley.begin <= wide_valley_min)
    return static_cast<int>(std::nearbyint((static_cast<double>(valley.begin) + valley.end) / 2.0));
  const int low = valley.begin + buffer, high = valley.end - buffer;
  return target < low ? low : (target > high ? high : target);
}

std::vector<int> candidateHeadings(std::span<const Valley> valleys, int target, int wide_valley_min) {
  if (valleys.empty()) return {target};
  std::vector<int> candidates;
  for (const Valley& v : valleys) candidates.push_back(valleyHeading(target, v, wide_valley_min));
  std::sort(candidates.begin(), candidates.end());
  candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
  return candidates;
}

namespace {

// The cheapest cost of `levels` more steps (the same candidate set at every depth: the team's
// search does not re-project the histogram).
double cheapestTail(std::span<const double> costs, int levels, double sum) {
  if (levels == 0) return sum;
  double best = 0.0;
  bool first = true;
  for (double c : costs) {
    const double total = cheapestTail(costs, levels - 1, sum + c);
    if (first || total < best) best = total;
    first = false;
  }
  return best;
}

}  // namespace

int chooseCandidate(std::span<const int> candidates, int target, double previous, const VfhSearch& search) {
  if (candidates.empty()) return target;
  // Tie order: nearer the target first, then the lower sector.
  std::vector<int> order(candidates.begin(), candidates.end());
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const int da = std::abs(a - target), db = std::abs(b - target);
    return da != db ? da < db : a < b;
  });
  // A step's cost as the team adds it: (progress + 0.1 |c - t|) + 0.2 |c - previous|.
  std::vector<double> costs;
  for (int c : order)
    costs.push_back(search.step + search.target_weight * std::abs(c - target) +
                    search.switch_weight * std::abs(static_cast<double>(c) - previous));
  int best = order.front();
  double best_total = 0.0;
  for (std::size_t i = 0; i < order.size(); ++i) {
    const double total = cheapestTail(costs, search.depth - 1, 0.0 + costs[i]);
    if (i == 0 || total < best_total) {
      best_total = total;
      best = order[i];
    }
  }
  return best;
}

double relativeBearingDeg(const core::Pose2& pose, const Eigen::Vector2d& target) {
  const Eigen::Vector2d d = target - pose.position();
  const double bearing = std::atan2(d.y(), d.x()) * kDegPerRad;
  const double heading = core::wrapAngle(pose.yaw) * kDegPerRad;
  double th = std::fmod(heading - bearing, 360.0);
  if (th > 180.0) th -= 360.0;
  if (th <= -180.0) th += 360.0;
  return th;
}

int targetSector(double relative_bearing_deg, int sectors, double fov_deg) {
  const double half = fov_deg / 2;
  const double th = std::clamp(relative_bearing_deg, -half, half);
  return static_cast<int>(std::nearbyint((th + half) * (sectors - 1) / fov_deg + 1));
}

// ---------------------------------------------------------------------------------------------
// The team's systems and one tick
// ---------------------------------------------------------------------------------------------

FuzzySystemConfig rrslSpeedFuzzy() {
  FuzzySystemConfig c;
  c.input = {0.0, 4.01, 0.01};        // Obstacle_Distance (a danger: 0 = nothing within 4 m)
  c.output = {0.0, 0.7 + 0.01, 0.01};  // Linear_Velocity [m/s]
  c.rules = {
      {{-0.9, 0.0, 0.0, 0.9}, {0.525, 0.7, 0.7537}},  // Very_Near -> Very_High
      {{0.0, 1.0, 2.0}, {0.35, 0.525, 0.7}},          // Near -> High
      {{1.0, 2.0, 3.0}, {0.175, 0.35, 0.525}},        // Midway -> Medium
      {{2.0, 3.0, 4.0}, {0.0, 0.175, 0.35}},          // Far -> Low
      {{3.1, 4.0, 4.0, 4.9}, {-0.175, 0.0, 0.175}},   // Very_Far -> Very_Low
  };
  return c;
}

FuzzySystemConfig rrslTurnFuzzy() {
  constexpr double pi = std::numbers::pi, half_pi = std::numbers::pi / 2;  // the team's 2.5 s, 1.25 s, s = pi / 2.5
  FuzzySystemConfig c;
  c.input = {0.0, 90.01, 0.1};      // Angular_Input [sector]
  c.output = {-pi, pi + 0.01, 0.01};  // Angular_Output [rad/s]
  c.rules = {
      {{-20.25, -2.25, 0.0, 22.5}, {half_pi, pi, pi, pi}},   // very_left -> very_pos
      {{0.0, 22.5, 45.0}, {0.0, half_pi, pi}},               // left -> pos
      {{22.5, 45.0, 67.5}, {-half_pi, 0.0, half_pi}},        // zero -> zero
      {{45.0, 67.5, 90.0}, {-pi, -half_pi, 0.0}},            // right -> neg
      {{67.5, 90.0, 90.0, 110.2}, {-pi, -pi, -pi, -half_pi}},  // very_right -> very_neg
  };
  return c;
}

void validate(const VfhConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.robot_size > 0.0 && c.robot_size <= 2 * c.threshold, prefix + ".robot_size",
               "must be in (0, 2 threshold] (sectToClear takes asin(robot_size / (2 threshold)))");
  errors.check(c.speed_sector_begin >= 0 && c.speed_sector_begin < c.speed_sector_end, prefix + ".speed_sector_begin",
               "must be >= 0 and < speed_sector_end");
  validate(c.speed_fuzzy, errors, prefix + ".speed_fuzzy");
  validate(c.turn_fuzzy, errors, prefix + ".turn_fuzzy");
}

void checkVfhBeams(const VfhConfig& c, int beams) {
  const int sectors = beams / std::max(1, c.sector_beams);
  if (sectors < c.speed_sector_end || sectors < 2)
    throw core::InputError("lidar.beams: " + std::to_string(beams) + " beams give " + std::to_string(sectors) +
                           " VFH sectors of " + std::to_string(c.sector_beams) +
                           " beams; the speed input reads sectors up to " + std::to_string(c.speed_sector_end));
}

std::span<const std::string_view> enumNames(VfhAction) {
  static constexpr std::string_view kNames[] = {"Steer",      "ClearPath", "SafetyBubble", "TurnInPlace",
                                                "WaitPath",   "GoalStop",  "Halted"};
  return kNames;
}

VfhFuzzy::VfhFuzzy(const VfhConfig& config) : config_(config), speed_(config.speed_fuzzy), turn_(config.turn_fuzzy) {}

VfhStep VfhFuzzy::step(const core::LaserScan& scan, const core::Pose2& pose, const Eigen::Vector2d& target) {
  const VfhConfig& c = config_;
  const std::vector<double> ranges = reversedRanges(scan, c.max_range);
  const std::vector<double> h = polarHistogram(ranges, c.max_range, c.sector_beams);
  const std::vector<bool> blocked = blockedSectors(h, c.threshold);
  const int sectors = static_cast<int>(h.size());

  VfhStep out;
  out.target_sector = targetSector(relativeBearingDeg(pose, target), sectors, c.fov_deg);
  const std::vector<Valley> valleys = findValleys(blocked, sectorsToClear(c.robot_size, c.threshold));
  const std::vector<int> candidates = candidateHeadings(valleys, out.target_sector, c.wide_valley_min);
  const double previous = c.smoothing && previous_heading_ ? *previous_heading_ : out.target_sector;
  out.candidate = chooseCandidate(candidates, out.target_sector, previous,
                                  {c.step, c.depth, c.target_weight, c.switch_weight});
  out.heading = out.candidate;
  if (c.smoothing) {
    if (previous_heading_) out.heading = c.smoothing_alpha * out.candidate + (1 - c.smoothing_alpha) * *previous_heading_;
    previous_heading_ = out.heading;
  }

  const auto begin = h.begin() + c.speed_sector_begin, end = h.begin() + std::min(c.speed_sector_end, sectors);
  out.danger = std::min(*std::min_element(begin, end), c.max_range);
  const std::optional<double> speed = speed_.compute(out.danger);
  const std::optional<double> turn = turn_.compute(out.heading);
  if (!speed || !turn) {
    out.action = VfhAction::Halted;
    return out;
  }
  out.command = {*speed, *turn};

  const int n = static_cast<int>(ranges.size());
  const int centre = n / 2;
  const auto front_begin = ranges.begin() + std::max(0, centre - c.clear_half_beams);
  const auto front_end = ranges.begin() + std::min(n, centre + c.clear_half_beams + 1);
  if (std::all_of(front_begin, front_end, [&](double r) { return r >= c.max_range; }) &&
      std::abs(out.heading - out.target_sector) < c.clear_alignment) {
    out.command.linear = c.clear_speed;
    out.action = VfhAction::ClearPath;
  }

  const int half = c.bubble_beams / 2;
  const auto bubble_begin = ranges.begin() + std::max(0, centre - half);
  const auto bubble_end = ranges.begin() + std::min(n, centre + half + 1);
  if (std::any_of(bubble_begin, bubble_end, [&](double r) { return r < c.bubble_distance; })) {
    // Left half (the reversed scan's first beams) against the right half with the centre beam.
    const auto mid = bubble_begin + (bubble_end - bubble_begin) / 2;
    const double left = mid > bubble_begin ? *std::min_element(bubble_begin, mid) : c.max_range;
    const double right = mid < bubble_end ? *std::min_element(mid, bubble_end) : c.max_range;
    out.command = {c.bubble_speed, left > right ? c.bubble_turn : -c.bubble_turn};
    out.action = VfhAction::SafetyBubble;
  }
  return out;
}

}  // namespace barn::controllers
