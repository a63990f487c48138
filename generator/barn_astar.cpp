#include "generator/barn_astar.hpp"

#include <algorithm>
#include <cmath>

#include "generator/cspace.hpp"

namespace barn::generator {

namespace {

// The move list in BARN's cyclic order; neighbours in this list differ by 45 degrees.
constexpr int kMoves[8][2] = {{0, 1}, {1, 1}, {1, 0}, {1, -1}, {0, -1}, {-1, -1}, {-1, 0}, {-1, 1}};
constexpr double kInflationRadiusCells = 2.0;  // round(0.3 m / 0.15 m)
constexpr double kWallPenalty = 5.0;

struct Node {
  core::Cell cell;
  int parent = -1;   // index into the node store, -1 for the start
  double g = 0.0;    // path cost from the start [cells]
  double f = 0.0;    // priority (see the header for BARN's formula)
};

int moveIndex(int dr, int dc) {
  for (int k = 0; k < 8; ++k)
    if (kMoves[k][0] == dr && kMoves[k][1] == dc) return k;
  return -1;
}

}  // namespace

std::optional<std::vector<core::Cell>> barnAStar(const core::Grid& cspace, core::Cell start, core::Cell goal) {
  const int cols = cspace.cols();
  const auto flat = [cols](core::Cell c) { return static_cast<std::size_t>(c.row * cols + c.col); };
  const std::vector<double> wall_distance = distanceToBlocked(cspace);

  std::vector<Node> nodes;                 // every node ever inserted
  std::vector<int> open;                   // indices into `nodes`, in insertion order
  std::vector<int> open_node_at(static_cast<std::size_t>(cspace.rows() * cols), -1);  // by position
  std::vector<char> closed(static_cast<std::size_t>(cspace.rows() * cols), 0);        // by position

  nodes.push_back({start, -1, 0.0, 0.0});
  open.push_back(0);
  open_node_at[flat(start)] = 0;

  while (!open.empty()) {
    // First node with the strictly smallest priority.
    std::size_t best = 0;
    for (std::size_t i = 1; i < open.size(); ++i)
      if (nodes[static_cast<std::size_t>(open[i])].f < nodes[static_cast<std::size_t>(open[best])].f) best = i;
    const int current = open[best];
    open.erase(open.begin() + static_cast<std::ptrdiff_t>(best));
    const Node node = nodes[static_cast<std::size_t>(current)];
    open_node_at[flat(node.cell)] = -1;
    closed[flat(node.cell)] = 1;

    if (node.cell == goal) {
      std::vector<core::Cell> path;
      for (int i = current; i >= 0; i = nodes[static_cast<std::size_t>(i)].parent)
        path.push_back(nodes[static_cast<std::size_t>(i)].cell);
      path.push_back(start);  // BARN's get_path prepends the start once more
      std::reverse(path.begin(), path.end());
      return path;
    }

    // Allowed moves: all 8 from the start, else the current direction and its +-45 degrees.
    int candidates[8];
    int candidate_count = 0;
    if (node.parent < 0) {
      for (int k = 0; k < 8; ++k) candidates[candidate_count++] = k;
    } else {
      const core::Cell from = nodes[static_cast<std::size_t>(node.parent)].cell;
      const int k = moveIndex(node.cell.row - from.row, node.cell.col - from.col);
      candidates[candidate_count++] = (k + 7) % 8;
      candidates[candidate_count++] = k;
      candidates[candidate_count++] = (k + 1) % 8;
    }

    for (int i = 0; i < candidate_count; ++i) {
      const int dr = kMoves[candidates[i]][0];
      const int dc = kMoves[candidates[i]][1];
      const core::Cell child{node.cell.row + dr, node.cell.col + dc};
      if (!cspace.inBounds(child) || cspace.at(child)) continue;
      if (dr != 0 && dc != 0 && cspace.at(node.cell.row + dr, node.cell.col) &&
          cspace.at(node.cell.row, node.cell.col + dc))
        continue;  // squeezing between two blocked side cells
      if (closed[flat(child)]) continue;

      const double g = node.g + ((dr != 0 && dc != 0) ? std::sqrt(2.0) : 1.0);
      const double d = wall_distance[flat(child)];
      const double penalty = d <= kInflationRadiusCells ? kWallPenalty / d : 0.0;
      const int existing = open_node_at[flat(child)];
      if (existing >= 0) {
        Node& other = nodes[static_cast<std::size_t>(existing)];
        if (g < other.g) {
          const int gr = goal.row - child.row;
          const int gc = goal.col - child.col;
          const double h = std::sqrt(static_cast<double>(gr * gr + gc * gc));
          other.parent = current;
          other.g = g;
          other.f = g + h + penalty;
        }
      } else {
        nodes.push_back({child, current, g, g + penalty});
        open.push_back(static_cast<int>(nodes.size() - 1));
        open_node_at[flat(child)] = open.back();
      }
    }
  }
  return std::nullopt;
}

}  // namespace barn::generator
