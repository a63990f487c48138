#include "generator/difficulty_metrics.hpp"

#include <cmath>

#include "generator/cspace.hpp"

namespace barn::generator {

namespace {

constexpr int kDirections8[8][2] = {{0, 1}, {1, 1}, {1, 0}, {1, -1}, {0, -1}, {-1, -1}, {-1, 0}, {-1, 1}};
// The dispersion rays in difficulty_quant.py's cyclic order.
constexpr int kDispersionRays[16][2] = {{0, 1},  {1, 2},   {1, 1},   {2, 1},   {1, 0},   {2, -1},
                                        {1, -1}, {1, -2},  {0, -1},  {-2, -1}, {-1, -1}, {-1, -2},
                                        {-1, 0}, {-2, 1},  {-1, 1},  {-1, 2}};
constexpr int kDispersionRadius = 3;
constexpr int kAxes[4][2] = {{0, 1}, {1, 1}, {1, 0}, {1, -1}};

// True if a ray from `cell` along `move` meets a blocked cell within the dispersion radius.
bool dispersionRayHitsWall(const core::Grid& cspace, core::Cell cell, const int move[2]) {
  // The original adds 2 per step only when a component is literally +2; steps with a -2
  // component add 1, so those rays reach three steps (~6.7 cells) instead of two.
  const int step_count = (move[0] == 2 || move[1] == 2) ? 2 : 1;
  int count = 0;
  int r = cell.row;
  int c = cell.col;
  while (count < kDispersionRadius) {
    r += move[0];
    c += move[1];
    if (!cspace.inBounds(r, c)) return false;
    if (cspace.at(r, c)) return true;
    count += step_count;
  }
  return false;
}

// Free length from `cell` (excluded) along (dr, dc) until a blocked cell or the map edge.
double freeLength(const core::Grid& cspace, core::Cell cell, int dr, int dc) {
  const double step = (dr != 0 && dc != 0) ? std::sqrt(2.0) : 1.0;
  double length = 0.0;
  int r = cell.row + dr;
  int c = cell.col + dc;
  while (cspace.inBounds(r, c) && !cspace.at(r, c)) {
    length += step;
    r += dr;
    c += dc;
  }
  return length;
}

}  // namespace

int cellVisibility(const core::Grid& cspace, core::Cell cell) {
  int sum = 0;
  int kept = 0;
  for (const auto& d : kDirections8) {
    int run = 0;
    int r = cell.row;
    int c = cell.col;
    bool hit_wall = false;
    while (cspace.inBounds(r, c)) {
      if (cspace.at(r, c)) {
        hit_wall = true;
        break;
      }
      ++run;
      r += d[0];
      c += d[1];
    }
    if (!hit_wall) continue;  // left the map before a wall: the direction is dropped
    sum += run;
    ++kept;
  }
  return kept == 0 ? 0 : sum / kept;  // non-negative operands: C++ division floors like Python 2
}

int cellDispersion(const core::Grid& cspace, core::Cell cell) {
  if (cspace.at(cell)) return -1;
  int changes = 0;
  bool previous = dispersionRayHitsWall(cspace, cell, kDispersionRays[15]);
  for (const auto& ray : kDispersionRays) {
    const bool wall = dispersionRayHitsWall(cspace, cell, ray);
    changes += wall != previous;
    previous = wall;
  }
  return changes;
}

double cellCharacteristicDimension(const core::Grid& cspace, core::Cell cell) {
  if (cspace.at(cell)) return -1.0;
  double narrowest = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double width = freeLength(cspace, cell, kAxes[i][0], kAxes[i][1]) +
                         freeLength(cspace, cell, -kAxes[i][0], -kAxes[i][1]);
    if (i == 0 || width < narrowest) narrowest = width;
  }
  return narrowest;
}

double tortuosity(const std::vector<core::Cell>& path) {
  double arc = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const int dr = path[i].row - path[i - 1].row;
    const int dc = path[i].col - path[i - 1].col;
    arc += std::sqrt(static_cast<double>(dr * dr + dc * dc));
  }
  const int dr = path.back().row - path.front().row;
  const int dc = path.back().col - path.front().col;
  return arc / std::sqrt(static_cast<double>(dr * dr + dc * dc));
}

core::DifficultyMetrics computeMetrics(const core::Grid& cspace, const std::vector<core::Cell>& path) {
  const std::vector<double> wall_distance = distanceToBlocked(cspace);
  double closest = 0.0;
  double visibility = 0.0;
  double dispersion = 0.0;
  double dimension = 0.0;
  for (const core::Cell& cell : path) {
    closest += wall_distance[static_cast<std::size_t>(cell.row * cspace.cols() + cell.col)];
    visibility += cellVisibility(cspace, cell);
    dispersion += cellDispersion(cspace, cell);
    dimension += cellCharacteristicDimension(cspace, cell);
  }
  const double n = static_cast<double>(path.size());
  return {closest / n, visibility / n, dispersion / n, dimension / n, tortuosity(path)};
}

MetricsNormalisation metricsNormalisation(const std::vector<core::DifficultyMetrics>& set) {
  std::array<double, 5> mean{};
  std::array<double, 5> var{};
  const double n = static_cast<double>(set.size());
  for (const auto& m : set) {
    const auto a = m.toArray();
    for (std::size_t k = 0; k < 5; ++k) mean[k] += a[k];
  }
  for (auto& v : mean) v /= n;
  for (const auto& m : set) {
    const auto a = m.toArray();
    for (std::size_t k = 0; k < 5; ++k) var[k] += (a[k] - mean[k]) * (a[k] - mean[k]);
  }
  std::array<double, 5> std_dev{};
  for (std::size_t k = 0; k < 5; ++k) std_dev[k] = std::sqrt(var[k] / n);
  return {core::DifficultyMetrics::fromArray(mean), core::DifficultyMetrics::fromArray(std_dev)};
}

core::DifficultyMetrics normaliseMetrics(const core::DifficultyMetrics& raw, const MetricsNormalisation& norm) {
  const auto a = raw.toArray();
  const auto mean = norm.mean.toArray();
  const auto sd = norm.std_dev.toArray();
  std::array<double, 5> z{};
  for (std::size_t k = 0; k < 5; ++k) z[k] = sd[k] > 0.0 ? (a[k] - mean[k]) / sd[k] : 0.0;
  return core::DifficultyMetrics::fromArray(z);
}

}  // namespace barn::generator
