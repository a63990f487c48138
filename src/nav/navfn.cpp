#include "barn/nav/navfn.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace barn::nav {

namespace {
// NavFn's INVSQRT2: a cell is worth pushing only if its potential exceeds the new value plus
// this fraction of its own cost (a diagonal-ish lower bound of what it could gain).
constexpr double kInvSqrt2 = 0.707106781;
constexpr float kPathStep = 0.5f;  // [cells] NavFn pathStep
}  // namespace

NavFn::NavFn(bool allow_unknown, double neutral_cost, double cost_factor)
    : allow_unknown_(allow_unknown), neutral_(static_cast<float>(neutral_cost)), cost_lut_(256, kCostObs), edge_lut_(256, 0.0f) {
  for (int c = 0; c < 256; ++c) {
    int v = kCostObs;
    if (c < kInscribedCost) {
      // int v = COST_NEUTRAL + COST_FACTOR * c: truncated, 50 + 0.8 * 252 = 251.6 -> 251.
      v = static_cast<int>(neutral_cost + cost_factor * c);
      if (v >= kCostObs) v = kCostObs - 1;
    } else if (c == kUnknownCost && allow_unknown_) {
      v = kCostObs - 1;
    }
    cost_lut_[static_cast<std::size_t>(c)] = v;
    // float(INVSQRT2 * cost), computed in double as NavFn does, for every NavFn cost.
    edge_lut_[static_cast<std::size_t>(c)] = static_cast<float>(kInvSqrt2 * c);
  }
}

void NavFn::resize(int nx, int ny) {
  if (nx == nx_ && ny == ny_) return;
  nx_ = nx;
  ny_ = ny;
  ns_ = nx * ny;
  const std::size_t n = static_cast<std::size_t>(ns_);
  cells_.assign(n, Cell{kPotHigh, static_cast<std::uint8_t>(kCostObs), 0});
  gradx_.assign(n, 0.0f);
  grady_.assign(n, 0.0f);
  for (auto& b : buf_) b.assign(n + 4, 0);  // + updateCell's unkept writes past the end (see there)
  grad_cells_.clear();
  map_ = nullptr;
  cleared_cell_ = -1;
}

void NavFn::setCostmap(const Costmap& costmap) {
  resize(costmap.widthCells(), costmap.heightCells());
  if (map_ == &costmap && map_version_ == costmap.version()) return;
  map_ = &costmap;
  map_version_ = costmap.version();
  cleared_cell_ = -1;
  const std::uint8_t* costs = costmap.costs();
  for (std::size_t i = 0; i < cells_.size(); ++i) cells_[i].cost = static_cast<std::uint8_t>(cost_lut_[costs[i]]);
  // setupNavFn: the outer rows and columns are obstacles.
  for (int x = 0; x < nx_; ++x) cells_[index(x, 0)].cost = cells_[index(x, ny_ - 1)].cost = kCostObs;
  for (int y = 0; y < ny_; ++y) cells_[index(0, y)].cost = cells_[index(nx_ - 1, y)].cost = kCostObs;
}

bool NavFn::propagate(CellIndex robot, CellIndex goal) {
  updates_ = 0;
  cycles_ = 0;
  propagated_ = false;
  if (robot.x <= 0 || robot.y <= 0 || robot.x >= nx_ - 1 || robot.y >= ny_ - 1) return false;  // off map or on the border
  if (goal.x < 0 || goal.y < 0 || goal.x >= nx_ || goal.y >= ny_) return false;                  // off map
  propagated_ = true;
  // clearRobotCell: the robot's cell is free (the border stays an obstacle, excluded above).
  if (cleared_cell_ >= 0) cells_[static_cast<std::size_t>(cleared_cell_)].cost = cleared_cost_;
  robot_ = static_cast<int>(index(robot.x, robot.y));
  cleared_cell_ = robot_;
  cleared_cost_ = cells_[static_cast<std::size_t>(robot_)].cost;
  cells_[static_cast<std::size_t>(robot_)].cost = static_cast<std::uint8_t>(cost_lut_[kFreeCost]);

  for (Cell& cell : cells_) {  // setupNavFn: no potential, nothing pending
    cell.pot = kPotHigh;
    cell.pending = 0;
  }
  // setupNavFn zeroes every gradient; only the cells the last descent computed can be nonzero.
  for (const int c : grad_cells_) gradx_[static_cast<std::size_t>(c)] = grady_[static_cast<std::size_t>(c)] = 0.0f;
  grad_cells_.clear();
  cur_ = buf_[0].data();
  next_ = buf_[1].data();
  over_ = buf_[2].data();
  cur_size_ = next_size_ = over_size_ = 0;
  threshold_ = static_cast<float>(kCostObs);

  const auto push_to = [this](int* buffer, int& size, int n) {
    if (!cells_[static_cast<std::size_t>(n)].pending && cells_[static_cast<std::size_t>(n)].cost < kCostObs) {
      buffer[size++] = n;
      cells_[static_cast<std::size_t>(n)].pending = 1;
    }
  };
  // initCost(robot, 0): potential 0, the 4 neighbours queued.
  cells_[static_cast<std::size_t>(robot_)].pot = 0.0f;
  push_to(cur_, cur_size_, robot_ + 1);
  push_to(cur_, cur_size_, robot_ - 1);
  push_to(cur_, cur_size_, robot_ - nx_);
  push_to(cur_, cur_size_, robot_ + nx_);

  const int goal_cell = static_cast<int>(index(goal.x, goal.y));
  // An impassable goal is never queued, so NavFn would only learn that after propagating
  // over everything reachable; the answer (no plan) is the same.
  if (goal_cell != robot_ && cells_[static_cast<std::size_t>(goal_cell)].cost >= kCostObs) return false;

  const int max_cycles = std::max(nx_ * ny_ / 20, nx_ + ny_);
  const float priority_increment = 2.0f * neutral_;
  for (; cycles_ < max_cycles; ++cycles_) {
    if (cur_size_ == 0 && next_size_ == 0) break;  // buffers empty
    for (int k = 0; k < cur_size_; ++k) cells_[static_cast<std::size_t>(cur_[k])].pending = 0;
    for (int k = 0; k < cur_size_; ++k) updateCell(cur_[k]);
    updates_ += static_cast<std::size_t>(cur_size_);
    // The next buffer becomes the current one; when it is empty the threshold rises and the
    // overflow buffer becomes the current one.
    cur_size_ = next_size_;
    next_size_ = 0;
    std::swap(cur_, next_);
    if (cur_size_ == 0) {
      threshold_ += priority_increment;
      cur_size_ = over_size_;
      over_size_ = 0;
      std::swap(cur_, over_);
    }
    if (cells_[static_cast<std::size_t>(goal_cell)].pot < kPotHigh) {  // atStart: the goal is reached
      ++cycles_;
      break;
    }
  }
  return cells_[static_cast<std::size_t>(goal_cell)].pot < kPotHigh;
}

void NavFn::updateCell(int n) {
  const std::size_t i = static_cast<std::size_t>(n);
  const std::size_t w = static_cast<std::size_t>(nx_);
  // Cells on the border are never queued (they are obstacles), so all 4 neighbours exist.
  const float l = cells_[i - 1].pot;
  const float r = cells_[i + 1].pot;
  const float u = cells_[i - w].pot;
  const float d = cells_[i + w].pot;
  const float tc = l < r ? l : r;  // lowest horizontal neighbour
  const float tv = u < d ? u : d;  // lowest vertical neighbour
  if (cells_[i].cost >= kCostObs) return;  // never propagate into obstacles
  const float hf = static_cast<float>(cells_[i].cost);
  const float dc = std::fabs(tc - tv);    // NavFn: dc = tc - ta, negated if negative ...
  const float ta = tc < tv ? tc : tv;     // ... and then ta = tc: the lowest of all
  // Planar wave: a front arriving from one side only (difference >= h) gives a + h; from
  // both, NavFn's quadratic fit of the 2D solution: a + h (-0.2301 r^2 + 0.5307 r + 0.7040),
  // r = difference / h (r = 0, a diagonal front: 0.704 h ~ h / sqrt 2; r = 1: h).
  // Both branches are computed and one is selected: which applies varies cell by cell, and a
  // mispredicted branch costs more than the polynomial.
  const float rr = dc / hf;
  const float v = static_cast<float>(-0.2301 * rr * rr + 0.5307 * rr + 0.7040);
  const float pot = dc >= hf ? ta + hf : ta + hf * v;
  if (!(pot < cells_[i].pot)) return;
  cells_[i].pot = pot;
  // Queue each neighbour whose potential exceeds pot + cost(neighbour) / sqrt 2 (compared
  // with the values read before this update, as NavFn does), in NavFn's order (left, right,
  // up, down). Branch-free: the index is written at the buffer's end either way and kept only
  // when the neighbour qualifies (the buffers have room for it, see resize).
  const bool above = !(pot < threshold_);
  int* buffer = above ? over_ : next_;
  int& size = above ? over_size_ : next_size_;
  int n_size = size;
  const auto push_if = [&](std::size_t m, bool worse) {
    Cell& cell = cells_[m];
    const bool push = worse & (cell.pending == 0) & (cell.cost < kCostObs);
    buffer[n_size] = static_cast<int>(m);
    n_size += push;
    cell.pending |= static_cast<std::uint8_t>(push);
  };
  push_if(i - 1, l > pot + edge_lut_[cells_[i - 1].cost]);
  push_if(i + 1, r > pot + edge_lut_[cells_[i + 1].cost]);
  push_if(i - w, u > pot + edge_lut_[cells_[i - w].cost]);
  push_if(i + w, d > pot + edge_lut_[cells_[i + w].cost]);
  size = n_size;
}

void NavFn::gradCell(int n) {
  const std::size_t i = static_cast<std::size_t>(n);
  if (gradx_[i] + grady_[i] > 0.0f) return;  // cached (NavFn's test; other signs recompute)
  if (n < nx_ || n > ns_ - nx_) return;        // would be out of bounds
  const std::size_t w = static_cast<std::size_t>(nx_);
  const float cv = cells_[i].pot;
  float dx = 0.0f;
  float dy = 0.0f;
  if (cv >= kPotHigh) {
    // In an obstacle: point at a reached neighbour.
    if (cells_[i - 1].pot < kPotHigh) dx = -static_cast<float>(kCostObs);
    else if (cells_[i + 1].pot < kPotHigh) dx = static_cast<float>(kCostObs);
    if (cells_[i - w].pot < kPotHigh) dy = -static_cast<float>(kCostObs);
    else if (cells_[i + w].pot < kPotHigh) dy = static_cast<float>(kCostObs);
  } else {
    // Downhill: (left - right, up - down) over the reached neighbours ("up" = row - 1).
    if (cells_[i - 1].pot < kPotHigh) dx += cells_[i - 1].pot - cv;
    if (cells_[i + 1].pot < kPotHigh) dx += cv - cells_[i + 1].pot;
    if (cells_[i - w].pot < kPotHigh) dy += cells_[i - w].pot - cv;
    if (cells_[i + w].pot < kPotHigh) dy += cv - cells_[i + w].pot;
  }
  const float norm = std::hypot(dx, dy);
  if (norm > 0.0f) {
    const float inv = 1.0f / norm;
    gradx_[i] = inv * dx;
    grady_[i] = inv * dy;
    grad_cells_.push_back(n);
  }
}

bool NavFn::extractPath(CellIndex goal, int max_steps, std::vector<Eigen::Vector2f>& points) {
  points.clear();
  if (robot_ < 0 || goal.x < 0 || goal.y < 0 || goal.x >= nx_ || goal.y >= ny_) return false;
  int stc = static_cast<int>(index(goal.x, goal.y));
  const auto pot = [this](int n) { return cells_[static_cast<std::size_t>(n)].pot; };
  float dx = 0.0f;
  float dy = 0.0f;
  for (int step = 0; step < max_steps; ++step) {
    // Near the robot: only the robot cell (0) is below neutral, its neighbours are >= neutral.
    const int nearest = std::clamp(stc + static_cast<int>(std::round(dx)) + nx_ * static_cast<int>(std::round(dy)), 0, ns_ - 1);
    if (pot(nearest) < neutral_) {
      points.emplace_back(static_cast<float>(robot_ % nx_), static_cast<float>(robot_ / nx_));
      return true;
    }
    if (stc < nx_ || stc > ns_ - nx_) return false;  // would be out of bounds
    points.emplace_back(static_cast<float>(stc % nx_) + dx, static_cast<float>(stc / nx_) + dy);
    const std::size_t np = points.size();
    const bool oscillation = np > 2 && points[np - 1].x() == points[np - 3].x() && points[np - 1].y() == points[np - 3].y();
    const int up = stc - nx_;
    const int down = stc + nx_;
    if (pot(stc) >= kPotHigh || pot(stc + 1) >= kPotHigh || pot(stc - 1) >= kPotHigh || pot(down) >= kPotHigh ||
        pot(down + 1) >= kPotHigh || pot(down - 1) >= kPotHigh || pot(up) >= kPotHigh || pot(up + 1) >= kPotHigh ||
        pot(up - 1) >= kPotHigh || oscillation) {
      // Grid mode: jump to the lowest of the 8 neighbours (first found on ties). NavFn keeps
      // the running minimum in an int, so the current cell's potential is truncated.
      int minc = stc;
      int minp = static_cast<int>(pot(stc));  // finite: only reached cells are ever current
      for (const int c : {up - 1, up, up + 1, stc - 1, stc + 1, down - 1, down, down + 1}) {
        if (pot(c) < static_cast<float>(minp)) {
          minp = static_cast<int>(pot(c));
          minc = c;
        }
      }
      stc = minc;
      dx = dy = 0.0f;
      if (pot(stc) >= kPotHigh) return false;
    } else {
      // Gradient mode: blend the normalised gradients of the 4 cells spanning the offset
      // (weights use dx, dy even when negative) and step 0.5 cell along the result.
      gradCell(stc);
      gradCell(stc + 1);
      gradCell(down);
      gradCell(down + 1);
      const auto gx = [this](int c) { return static_cast<double>(gradx_[static_cast<std::size_t>(c)]); };
      const auto gy = [this](int c) { return static_cast<double>(grady_[static_cast<std::size_t>(c)]); };
      const float x1 = static_cast<float>((1.0 - dx) * gx(stc) + dx * gx(stc + 1));
      const float x2 = static_cast<float>((1.0 - dx) * gx(down) + dx * gx(down + 1));
      const float x = static_cast<float>((1.0 - dy) * x1 + dy * x2);
      const float y1 = static_cast<float>((1.0 - dx) * gy(stc) + dx * gy(stc + 1));
      const float y2 = static_cast<float>((1.0 - dx) * gy(down) + dx * gy(down + 1));
      const float y = static_cast<float>((1.0 - dy) * y1 + dy * y2);
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

}  // namespace barn::nav
