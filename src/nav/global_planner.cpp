#include "barn/nav/global_planner.hpp"

#include <cmath>
#include <limits>
#include <queue>

namespace barn::nav {

void validate(const PlannerConfig& c, core::Errors& errors, const std::string& prefix) {
  errors.check(c.rate > 0.0, prefix + ".rate", "must be > 0");
  errors.check(c.neutral_cost > 0.0, prefix + ".neutral_cost", "must be > 0");
  errors.check(c.cost_factor >= 0.0, prefix + ".cost_factor", "must be >= 0");
  errors.check(c.smoothing_window >= 0, prefix + ".smoothing_window", "must be >= 0");
}

double GlobalPlanner::cellCost(std::uint8_t c) const {
  if (c == kUnknownCost) return config_.allow_unknown ? config_.neutral_cost : -1.0;
  if (c >= kInscribedCost) return -1.0;
  return config_.neutral_cost + config_.cost_factor * c;
}

Plan GlobalPlanner::plan(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal) {
  Plan result;
  CellIndex s, g;
  if (!costmap.toCell(start, s) || !costmap.toCell(goal, g)) return result;
  if (cellCost(costmap.cost(g.x, g.y)) < 0.0) return result;
  const int w = costmap.widthCells();
  const int h = costmap.heightCells();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  distance_.assign(n, kInf);
  parent_.assign(n, -1);
  const auto flat = [w](int x, int y) { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x); };

  using Entry = std::pair<double, int>;  // (distance, flat index)
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  distance_[flat(s.x, s.y)] = 0.0;
  open.emplace(0.0, static_cast<int>(flat(s.x, s.y)));
  constexpr int kSteps[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};
  const double diagonal = std::sqrt(2.0);
  const std::size_t goal_index = flat(g.x, g.y);
  while (!open.empty()) {
    const auto [d, i] = open.top();
    open.pop();
    if (d > distance_[static_cast<std::size_t>(i)]) continue;  // stale entry
    if (static_cast<std::size_t>(i) == goal_index) break;
    const int x = i % w;
    const int y = i / w;
    for (const auto& step : kSteps) {
      const int nx = x + step[0];
      const int ny = y + step[1];
      if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
      const double enter = cellCost(costmap.cost(nx, ny));
      if (enter < 0.0) continue;
      const bool is_diagonal = step[0] != 0 && step[1] != 0;
      if (is_diagonal && (cellCost(costmap.cost(nx, y)) < 0.0 || cellCost(costmap.cost(x, ny)) < 0.0)) continue;
      const double candidate = d + enter * (is_diagonal ? diagonal : 1.0);
      const std::size_t j = flat(nx, ny);
      if (candidate < distance_[j]) {
        distance_[j] = candidate;
        parent_[j] = i;
        open.emplace(candidate, static_cast<int>(j));
      }
    }
  }
  if (!std::isfinite(distance_[goal_index])) return result;

  std::vector<CellIndex> cells;
  for (int i = static_cast<int>(goal_index); i >= 0; i = parent_[static_cast<std::size_t>(i)]) cells.push_back({i % w, i / w});
  result.found = true;
  result.cost = distance_[goal_index];
  result.path.reserve(cells.size());
  for (auto it = cells.rbegin(); it != cells.rend(); ++it) result.path.push_back(costmap.cellCentre(*it));
  if (config_.smoothing_window > 1 && result.path.size() > 2) {
    // Moving average over the cell path, end points kept: removes the 45-degree staircase.
    const std::vector<Eigen::Vector2d> raw = result.path;
    const int half = config_.smoothing_window / 2;
    const int last = static_cast<int>(raw.size()) - 1;
    for (int i = 1; i < last; ++i) {
      Eigen::Vector2d sum = Eigen::Vector2d::Zero();
      int count = 0;
      for (int k = std::max(0, i - half); k <= std::min(last, i + half); ++k, ++count) sum += raw[static_cast<std::size_t>(k)];
      result.path[static_cast<std::size_t>(i)] = sum / count;
    }
  }
  return result;
}

}  // namespace barn::nav
