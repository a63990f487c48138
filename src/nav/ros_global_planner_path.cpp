// global_planner/GlobalPlanner: the traceback (GridPath, GradientPath) and the
// OrientationFilter. As in ros_global_planner.cpp, ROS's types are kept (float path points,
// float gradients, a double literal where ROS has one).
#include <algorithm>
#include <climits>
#include <cmath>
#include <numbers>

#include "barn/nav/ros_global_planner.hpp"

namespace barn::nav {

namespace {
constexpr float kPathStep = 0.5f;  // [cells] GradientPath pathStep_

// float -> int as x86 converts it: out of range (an unreached cell's 1e10) gives INT_MIN.
// GradientPath keeps its running minimum potential in an int.
int toIntLikeX86(float value) {
  if (!(value > static_cast<float>(INT_MIN) - 1.0f && value < static_cast<float>(INT_MAX))) return INT_MIN;
  return static_cast<int>(value);
}
}  // namespace

std::span<const std::string_view> enumNames(OrientationMode) {
  static constexpr std::string_view kNames[] = {"none",     "forward",  "interpolate", "forward_then_interpolate",
                                                "backward", "leftward", "rightward"};
  return kNames;
}

// ---------------------------------------------------------------------------------------------
// GridPath

bool RosGlobalPlanner::gridPath(double start_x, double start_y, double end_x, double end_y) {
  // From the goal's (fractional) map point, step to the lowest of the 8 neighbours (x offset
  // outer, y inner, first found on ties) until in the start's cell. A lowest neighbour at cell
  // (0, 0), or none below 1e10, ends it as a failure.
  points_.clear();
  Eigen::Vector2f current(static_cast<float>(end_x), static_cast<float>(end_y));
  const int start_index = static_cast<int>(start_x) + nx_ * static_cast<int>(start_y);
  points_.push_back(current);
  int c = 0;
  while (static_cast<int>(current.x()) + nx_ * static_cast<int>(current.y()) != start_index) {
    float min_val = 1e10f;
    int min_x = 0, min_y = 0;
    for (int xd = -1; xd <= 1; ++xd) {
      for (int yd = -1; yd <= 1; ++yd) {
        if (xd == 0 && yd == 0) continue;
        const int x = static_cast<int>(current.x() + static_cast<float>(xd));
        const int y = static_cast<int>(current.y() + static_cast<float>(yd));
        const int index = x + nx_ * y;
        if (index < -pad_ || index >= ns_ + pad_) continue;  // past the margin: ROS reads memory there
        if (pot_[index] < min_val) {
          min_val = pot_[index];
          min_x = x;
          min_y = y;
        }
      }
    }
    if (min_x == 0 && min_y == 0) return false;
    current = Eigen::Vector2f(static_cast<float>(min_x), static_cast<float>(min_y));
    points_.push_back(current);
    if (c++ > ns_ * 4) return false;
  }
  return true;
}

// ---------------------------------------------------------------------------------------------
// GradientPath

bool RosGlobalPlanner::gradientPath(double start_x, double start_y, double goal_x, double goal_y) {
  points_.clear();
  for (const int n : grad_cells_) gradx_[n] = grady_[n] = 0.0f;  // ROS zeroes both arrays
  grad_cells_.clear();
  int stc = static_cast<int>(goal_x) + nx_ * static_cast<int>(goal_y);
  float dx = static_cast<float>(goal_x - static_cast<int>(goal_x));
  float dy = static_cast<float>(goal_y - static_cast<int>(goal_y));
  int c = 0;
  while (c++ < ns_ * 4) {
    // Within half a cell of the start (on both axes): the start's own point ends the path.
    const double px = static_cast<float>(stc % nx_) + dx;
    const double py = static_cast<float>(stc / nx_) + dy;
    if (std::fabs(px - start_x) < .5 && std::fabs(py - start_y) < .5) {
      points_.emplace_back(static_cast<float>(start_x), static_cast<float>(start_y));
      return true;
    }
    if (stc < nx_ || stc > ns_ - nx_) return false;  // out of bounds
    points_.emplace_back(static_cast<float>(px), static_cast<float>(py));
    const std::size_t np = points_.size();
    const bool oscillation = np > 2 && points_[np - 1].x() == points_[np - 3].x() && points_[np - 1].y() == points_[np - 3].y();
    const int down = stc + nx_;  // stcnx
    const int up = stc - nx_;    // stcpx
    if (pot_[stc] >= kPotHigh || pot_[stc + 1] >= kPotHigh || pot_[stc - 1] >= kPotHigh || pot_[down] >= kPotHigh ||
        pot_[down + 1] >= kPotHigh || pot_[down - 1] >= kPotHigh || pot_[up] >= kPotHigh || pot_[up + 1] >= kPotHigh ||
        pot_[up - 1] >= kPotHigh || oscillation) {
      // Grid fallback: to the lowest of the 8 neighbours. The running minimum is an int, so
      // each potential it takes is truncated (and an unreached current cell's 1e10 becomes
      // INT_MIN, which nothing is below: the descent stays and fails).
      int minc = stc;
      int minp = toIntLikeX86(pot_[stc]);
      for (const int st : {up - 1, up, up + 1, stc - 1, stc + 1, down - 1, down, down + 1}) {
        if (pot_[st] < static_cast<float>(minp)) {
          minp = toIntLikeX86(pot_[st]);
          minc = st;
        }
      }
      stc = minc;
      dx = 0.0f;
      dy = 0.0f;
      if (pot_[stc] >= kPotHigh) return false;  // no path: unreached
    } else {
      // Blend the normalised gradients of the 4 cells spanning the offset (weights use dx, dy
      // even when negative) and step 0.5 cell along the result.
      gradCell(stc);
      gradCell(stc + 1);
      gradCell(down);
      gradCell(down + 1);
      const float x1 = (1.0 - dx) * gradx_[stc] + dx * gradx_[stc + 1];
      const float x2 = (1.0 - dx) * gradx_[down] + dx * gradx_[down + 1];
      const float x = (1.0 - dy) * x1 + dy * x2;
      const float y1 = (1.0 - dx) * grady_[stc] + dx * grady_[stc + 1];
      const float y2 = (1.0 - dx) * grady_[down] + dx * grady_[down + 1];
      const float y = (1.0 - dy) * y1 + dy * y2;
      if (x == 0.0f && y == 0.0f) return false;  // zero gradient
      const float ss = kPathStep / std::hypot(x, y);
      dx += x * ss;
      dy += y * ss;
      if (dx > 1.0f) { ++stc; dx -= 1.0f; }
      if (dx < -1.0f) { --stc; dx += 1.0f; }
      if (dy > 1.0f) { stc += nx_; dy -= 1.0f; }
      if (dy < -1.0f) { stc -= nx_; dy += 1.0f; }
    }
  }
  return false;  // out of steps
}

void RosGlobalPlanner::gradCell(int n) {
  if (gradx_[n] + grady_[n] > 0.0f) return;  // cached (ROS's test: other signs are recomputed)
  if (n < nx_ || n > ns_ - nx_) return;        // would read out of bounds
  const float cv = pot_[n];
  float dx = 0.0f;
  float dy = 0.0f;
  if (cv >= kPotHigh) {
    // Unreached: lethal_cost towards a reached neighbour (left before right, up before down).
    if (pot_[n - 1] < kPotHigh) dx = -lethal_;
    else if (pot_[n + 1] < kPotHigh) dx = lethal_;
    if (pot_[n - nx_] < kPotHigh) dy = -lethal_;
    else if (pot_[n + nx_] < kPotHigh) dy = lethal_;
  } else {
    // Downhill, over the reached neighbours: (left - right, up - down), "up" = row - 1.
    if (pot_[n - 1] < kPotHigh) dx += pot_[n - 1] - cv;
    if (pot_[n + 1] < kPotHigh) dx += cv - pot_[n + 1];
    if (pot_[n - nx_] < kPotHigh) dy += pot_[n - nx_] - cv;
    if (pot_[n + nx_] < kPotHigh) dy += cv - pot_[n + nx_];
  }
  float norm = std::hypot(dx, dy);
  if (norm > 0) {
    norm = static_cast<float>(1.0 / norm);
    gradx_[n] = norm * dx;
    grady_[n] = norm * dy;
    grad_cells_.push_back(n);
  }
}

// ---------------------------------------------------------------------------------------------
// OrientationFilter

double normalizeAngle(double angle) {
  const double result = std::fmod(angle + std::numbers::pi, 2.0 * std::numbers::pi);
  if (result <= 0.0) return result + std::numbers::pi;
  return result - std::numbers::pi;
}

void applyOrientationFilter(OrientationMode mode, int window, double start_yaw, const std::vector<Eigen::Vector2d>& position,
                            std::vector<double>& yaw) {
  const int n = static_cast<int>(position.size());
  if (n == 0) return;
  // setAngleBasedOnPositionDerivative: the direction from pose i - window to pose i + window
  // (clamped to the path).
  const auto forward = [&](int i) {
    const Eigen::Vector2d& p0 = position[static_cast<std::size_t>(std::max(0, i - window))];
    const Eigen::Vector2d& p1 = position[static_cast<std::size_t>(std::min(n - 1, i + window))];
    return std::atan2(p1.y() - p0.y(), p1.x() - p0.x());
  };
  const auto at = [&](int i) -> double& { return yaw[static_cast<std::size_t>(i)]; };
  // interpolate: from the yaw at start_index to the one at end_index by the shortest turn.
  // ROS adds increment * i, not increment * (i - start_index), so from a start_index above 0
  // the blend overshoots; kept. Angles are stored normalised, as a quaternion holds them.
  const auto interpolate = [&](int start_index, int end_index) {
    const double start = at(start_index);
    const double diff = normalizeAngle(at(end_index) - start);
    const double increment = diff / (end_index - start_index);
    for (int i = start_index; i <= end_index; ++i) at(i) = normalizeAngle(start + increment * i);
  };
  // The last pose (the goal) keeps its yaw in every mode but the interpolations.
  switch (mode) {
    case OrientationMode::None:
      break;
    case OrientationMode::Forward:
      for (int i = 0; i < n - 1; ++i) at(i) = forward(i);
      break;
    case OrientationMode::Backward:
      for (int i = 0; i < n - 1; ++i) at(i) = normalizeAngle(forward(i) + std::numbers::pi);
      break;
    case OrientationMode::Leftward:
      for (int i = 0; i < n - 1; ++i) at(i) = normalizeAngle(forward(i) - std::numbers::pi / 2);
      break;
    case OrientationMode::Rightward:
      for (int i = 0; i < n - 1; ++i) at(i) = normalizeAngle(forward(i) + std::numbers::pi / 2);
      break;
    case OrientationMode::Interpolate:
      at(0) = normalizeAngle(start_yaw);
      if (n > 1) interpolate(0, n - 1);
      break;
    case OrientationMode::ForwardThenInterpolate: {
      for (int i = 0; i < n - 1; ++i) at(i) = forward(i);
      // Walk back from the third-last pose while the heading stays within 0.35 rad of it; the
      // blend starts there. (ROS starts at n - 3 even below 3 poses, reading before the
      // array; here it starts at 0.)
      int i = std::max(0, n - 3);
      const double last = at(i);
      while (i > 0) {
        const double diff = std::fabs(normalizeAngle(last - at(i - 1)));
        if (diff > 0.35) break;
        --i;
      }
      at(0) = normalizeAngle(start_yaw);
      if (n - 1 > i) interpolate(i, n - 1);
      break;
    }
  }
}

}  // namespace barn::nav
