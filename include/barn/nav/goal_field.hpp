#pragma once
/// The cost-to-goal field of the `dijkstra` global planner, kept up to date incrementally, and
/// the path down it.
///
/// Each cell costs neutral_cost + cost_factor * (its costmap cost) to enter (NavFn's
/// COST_NEUTRAL and COST_FACTOR), times the step length (1 or sqrt 2 cells), rounded to an
/// integer (tenths of the NavFn unit). Inscribed and lethal cells cannot be entered, unknown
/// ones neither unless allow_unknown; moves are 8-connected without cutting the corner of a
/// cell that cannot be entered. The start may sit in such a cell (a robot brushing an obstacle
/// must still be able to leave); the goal may not.
///
/// g(c), the least cost from cell c to the goal, is exact on every cell the path depends on:
///  - The first field for a goal is an A* search from the goal toward the start (Dial's
///    bucket queue on f = g + h, h the octile distance at the cheapest step costs, which is
///    consistent), run until every cell with f up to the start's g is settled: the band
///    between goal and start, not the disc around the goal.
///  - After that the field is repaired when few cells changed (D* Lite, Koenig and Likhachev
///    2002): the cells whose cost changed since the last call put their neighbours' g in
///    doubt, and only the cells whose g actually changes are expanded again, with the keys
///    corrected for the start's movement (k_m). Costmap updates change cells around the
///    robot, at the end of the search, so a repair touches a small part of the field. A wide
///    inflation changes hundreds of cells per new obstacle, and a cost rise near the start
///    spreads to everything behind it: past a few dozen changed cells inside the searched
///    region, a new search is cheaper and runs instead (same field, same path).
///  - A new search after costmap changes reuses the last search's field: a cell it settled
///    whose g is below every g the changed cells (and their neighbours, whose diagonal moves
///    a change may open or close) can have had is exact still, since neither its path to the
///    goal nor any cheaper one can pass a changed cell. Those cells are taken as settled and
///    the search starts from the ones on their edge, each in the order of its key, so it
///    expands only the part of the band the changes can have touched: the changes come from
///    the scans around the robot, the far end of a search that starts at the goal.
///  - The path is the steepest descent from the start: each step to the neighbour n with the
///    least step cost + g(n); among equals the one with the least g (the dearer step, a
///    diagonal before a straight one, so a sideways shift comes early), then the one pointing
///    most nearly at the goal, then the first in a fixed direction order. It is a function of
///    the costs, start and goal alone, so the first search and every repair give the same
///    path. Every neighbour compared is exact: one that ties has f <= the start's g.

#include <cstdint>
#include <vector>

#include "barn/nav/costmap.hpp"

namespace barn::nav {

class GoalField {
 public:
  GoalField(double neutral_cost, double cost_factor, bool allow_unknown);

  /// Integer cost of stepping into a cell of costmap cost `c` (straight or diagonal step);
  /// negative if the cell cannot be entered. round(10 (neutral + factor c) length).
  int stepCost(std::uint8_t c, bool diagonal) const { return diagonal ? diagonal_cost_[c] : straight_cost_[c]; }

  /// Brings the field up to date for `costmap` (the same object between calls, or it starts
  /// over), `goal` and `start`, and descends from the start. False if the goal cannot be
  /// entered or the start cannot reach it.
  bool update(const Costmap& costmap, CellIndex start, CellIndex goal);
  /// The last update's path, start cell ... goal cell, and its cost.
  const std::vector<CellIndex>& path() const { return path_; }
  std::int64_t pathCost() const { return path_cost_; }
  /// Cells expanded by the last update (for reports and benchmarks).
  std::size_t lastExpanded() const { return last_expanded_; }

 private:
  struct QueueEntry {
    std::int64_t k1, k2;
    int cell;
    bool operator>(const QueueEntry& o) const { return k1 != o.k1 ? k1 > o.k1 : k2 > o.k2; }
  };

  bool passable(int i) const { return straight_cost_[cost_[static_cast<std::size_t>(i)]] >= 0; }
  /// The move from cell i in direction dir (an index of the fixed direction order) is allowed:
  /// the target can be entered and, diagonally, neither corner cell is closed.
  bool canMove(int i, int dir) const;
  int heuristic(int cell) const;  // octile distance to the start at the cheapest step costs
  void startOver(const Costmap& costmap, CellIndex start, CellIndex goal);
  void search();                  // the first field: A* from the goal, or from the reused cells
  void seedSearch();              // g and rhs before the search, and where it starts (seeds_)
  void takeSnapshot(std::int64_t settled_to);
  void fillHeuristic();           // h_ for the current start
  bool applyCostChanges(const Costmap& costmap);  // false: too many, start over instead
  void repair();                  // D* Lite's ComputeShortestPath, ties included
  void updateCell(int cell);      // D* Lite's UpdateVertex
  std::int64_t bestThroughNeighbours(int cell) const;
  void enqueue(int cell);
  bool descend();

  std::vector<int> straight_cost_;  // by costmap cost (256 entries), -1: cannot be entered
  std::vector<int> diagonal_cost_;
  int offset_[8] = {};              // flat index step of each direction

  // The field, on the map padded by one closed cell on every side (neighbours need no
  // bounds checks; a cell is one flat index).
  const Costmap* map_ = nullptr;
  std::uint64_t map_version_ = 0;
  int width_ = 0, height_ = 0;      // padded
  int goal_ = -1, start_ = -1;      // flat indices
  std::vector<std::uint8_t> cost_;  // the costs the field is for
  std::vector<std::int64_t> g_, rhs_;
  std::vector<int> h_;              // scratch of search(): heuristic() of every cell
  std::vector<int> octile_;         // octile distance by (|dy|, |dx|), the padded map's shape
  int octile_width_ = 0;
  std::int64_t k_m_ = 0;            // D* Lite's key modifier: h summed over the start's moves
  std::vector<QueueEntry> queue_;   // min-heap; an entry is live if it matches queued_key_
  std::vector<std::int64_t> queued_k1_;
  std::vector<char> queued_;
  std::vector<int> changed_;        // scratch: cells whose cost changed
  std::vector<std::uint32_t> touched_round_;
  std::uint32_t round_ = 0;
  // Scratch of search(): Dial's bucket ring, each bucket a list threaded through one array of
  // entries (first entry by slot, -1 = empty), and a bit per non-empty bucket.
  struct BucketEntry {
    int cell;
    int next;  // the bucket's next entry, -1 = last
  };
  std::vector<int> bucket_head_;
  std::vector<BucketEntry> bucket_entries_;
  std::vector<std::uint64_t> occupied_buckets_;

  // The field as the last search left it, for the next search to reuse (seedSearch):
  // g of every cell it settled (exact for the costs it saw), kUnsettled elsewhere.
  struct Snapshot {
    const Costmap* map = nullptr;
    int width = 0, height = 0, goal = -1, start = -1;
    std::vector<std::int64_t> g;
    std::vector<std::uint8_t> cost;
    std::int64_t settled_to = 0;  // every cell with g + h(start) <= settled_to was settled
  };
  Snapshot snapshot_;
  struct Seed {
    std::int64_t key;
    int cell;
  };
  std::vector<Seed> seeds_;       // scratch of search(): where it starts, by key
  std::vector<std::uint8_t> kept_;  // scratch of seedSearch(): 1 where the snapshot's g is kept

  int searched_from_ = 0, searched_to_ = 0;  // flat range holding every cell search() left open

  std::vector<CellIndex> path_;
  std::int64_t path_cost_ = 0;
  std::size_t last_expanded_ = 0;
};

}  // namespace barn::nav
