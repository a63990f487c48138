#include "barn/nav/goal_field.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>

#include <Eigen/Core>

namespace barn::nav {

namespace {
constexpr std::int64_t kInfinite = std::numeric_limits<std::int64_t>::max();
constexpr std::size_t kMaxRepairedCells = 32;
// The fixed direction order: straight +x, -x, +y, -y, then the diagonals.
constexpr int kSteps[8][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {1, -1}, {-1, 1}, {-1, -1}};

/// The flat index steps of the four straight directions.
struct StraightSteps {
  int east, west, north, south;
};

/// Calls offer(p, step cost) for every neighbour p that reaches cell i in one move, by
/// entering it: the four straight ones at `straight`, and diagonally at `diagonal` only past two
/// open corners, which are i's straight neighbours.
template <class Passable, class Offer>
inline __attribute__((always_inline)) void offerToEnterers(int i, StraightSteps d, int straight, int diagonal,
                                                           Passable passable, Offer offer) {
  offer(i + d.east, straight);
  offer(i + d.west, straight);
  offer(i + d.north, straight);
  offer(i + d.south, straight);
  const bool e = passable(i + d.east), w = passable(i + d.west), n = passable(i + d.north), s = passable(i + d.south);
  if (e && n) offer(i + d.east + d.north, diagonal);
  if (e && s) offer(i + d.east + d.south, diagonal);
  if (w && n) offer(i + d.west + d.north, diagonal);
  if (w && s) offer(i + d.west + d.south, diagonal);
}
}  // namespace

GoalField::GoalField(double neutral_cost, double cost_factor, bool allow_unknown) {
  straight_cost_.resize(256);
  diagonal_cost_.resize(256);
  for (int c = 0; c < 256; ++c) {
    double enter = neutral_cost + cost_factor * c;
    bool open = c < kInscribedCost;
    if (c == kUnknownCost) {
      open = allow_unknown;
      enter = neutral_cost;
    }
    straight_cost_[static_cast<std::size_t>(c)] = open ? static_cast<int>(std::lround(10.0 * enter)) : -1;
    diagonal_cost_[static_cast<std::size_t>(c)] = open ? static_cast<int>(std::lround(10.0 * enter * std::sqrt(2.0))) : -1;
  }
}

bool GoalField::canMove(int i, int dir) const {
  if (!passable(i + offset_[dir])) return false;
  return dir < 4 || (passable(i + kSteps[dir][0]) && passable(i + kSteps[dir][1] * width_));
}

int GoalField::heuristic(int cell) const {
  const int dx = std::abs(cell % width_ - start_ % width_);
  const int dy = std::abs(cell / width_ - start_ / width_);
  return straight_cost_[0] * std::abs(dx - dy) + diagonal_cost_[0] * std::min(dx, dy);
}

bool GoalField::update(const Costmap& costmap, CellIndex start, CellIndex goal) {
  path_.clear();
  if (straight_cost_[costmap.cost(goal.x, goal.y)] < 0) return false;
  const int w = costmap.widthCells() + 2;
  const int h = costmap.heightCells() + 2;
  const int goal_index = (goal.y + 1) * w + goal.x + 1;
  const int start_index = (start.y + 1) * w + start.x + 1;
  if (map_ != &costmap || w != width_ || h != height_ || goal_index != goal_ ||
      (costmap.version() != map_version_ && !applyCostChanges(costmap))) {
    startOver(costmap, start, goal);
  } else {
    last_expanded_ = 0;
    if (start_index != start_) {
      // D* Lite: keys already queued stay valid lower bounds once k_m grows by the
      // heuristic distance the start moved.
      const int old_start = start_;
      start_ = start_index;
      k_m_ += heuristic(old_start);
    }
    repair();
  }
  map_version_ = costmap.version();
  if (g_[static_cast<std::size_t>(start_)] == kInfinite) return false;
  path_cost_ = g_[static_cast<std::size_t>(start_)];
  return descend();
}

void GoalField::startOver(const Costmap& costmap, CellIndex start, CellIndex goal) {
  map_ = &costmap;
  width_ = costmap.widthCells() + 2;
  height_ = costmap.heightCells() + 2;
  goal_ = (goal.y + 1) * width_ + goal.x + 1;
  start_ = (start.y + 1) * width_ + start.x + 1;
  for (int k = 0; k < 8; ++k) offset_[k] = kSteps[k][1] * width_ + kSteps[k][0];
  const std::size_t n = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  cost_.assign(n, kLethalCost);
  const std::uint8_t* costs = costmap.costs();
  for (int y = 0; y < costmap.heightCells(); ++y)
    std::copy_n(costs + static_cast<std::ptrdiff_t>(y) * costmap.widthCells(), costmap.widthCells(),
                cost_.begin() + static_cast<std::ptrdiff_t>(y + 1) * width_ + 1);
  g_.resize(n);  // seedSearch() sets every cell
  rhs_.resize(n);
  queued_.assign(n, 0);
  queued_k1_.resize(n);  // read only where queued_ is set
  queue_.clear();
  if (touched_round_.size() != n) {
    touched_round_.assign(n, 0);
    round_ = 0;
  }
  k_m_ = 0;
  search();
  // The cells the search reached but did not settle are D* Lite's open list (a start that
  // cannot be entered among them: it is never expanded); heaped at once.
  for (auto i = static_cast<std::size_t>(searched_from_); i < static_cast<std::size_t>(searched_to_); ++i)
    if (rhs_[i] != g_[i]) {
      const std::int64_t k1 = rhs_[i] + h_[i];  // the search's start: h_ is current
      queued_[i] = 1;
      queued_k1_[i] = k1;
      queue_.push_back({k1, rhs_[i], static_cast<int>(i)});
    }
  std::make_heap(queue_.begin(), queue_.end(), std::greater<>());
  repair();
}

void GoalField::seedSearch() {
  // The cells whose cost differs from the snapshot's, and their neighbours, are the cells a
  // change can reach: the least g any of them can have had bounds the cells still exact.
  // A cell the snapshot's search did not settle had f = g + h > settled_to, so its g was at
  // least settled_to - h + 1 (h toward the snapshot's start; a neighbour's h is at most one
  // diagonal step more than the cell's).
  seeds_.clear();
  const Snapshot& snap = snapshot_;
  const bool reusable = snap.map == map_ && snap.width == width_ && snap.height == height_ && snap.goal == goal_ &&
                        snap.g.size() == cost_.size();
  const std::int64_t* old_g = snap.g.data();
  std::int64_t bound = kInfinite;
  if (reusable) {
    const int sx = snap.start % width_, sy = snap.start / width_;
    const std::ptrdiff_t w = width_;
    for (int y = 1; y < height_ - 1 && bound > 0; ++y) {
      const std::size_t row = static_cast<std::size_t>(y) * static_cast<std::size_t>(width_);
      if (std::memcmp(cost_.data() + row, snap.cost.data() + row, static_cast<std::size_t>(width_)) == 0) continue;
      for (int x = 1; x < width_ - 1; ++x) {
        if (cost_[row + static_cast<std::size_t>(x)] == snap.cost[row + static_cast<std::size_t>(x)]) continue;
        const std::int64_t* around = old_g + row + static_cast<std::size_t>(x);
        const std::int64_t least = std::min({around[-w - 1], around[-w], around[-w + 1], around[-1], around[0], around[1],
                                             around[w - 1], around[w], around[w + 1]});
        bound = std::min(bound, least);
        const bool all_settled = std::max({around[-w - 1], around[-w], around[-w + 1], around[-1], around[0], around[1],
                                           around[w - 1], around[w], around[w + 1]}) != kInfinite;
        if (!all_settled && snap.settled_to != kInfinite) {
          const int dx = std::abs(x - sx), dy = std::abs(y - sy);
          const std::int64_t h = straight_cost_[0] * std::abs(dx - dy) + diagonal_cost_[0] * std::min(dx, dy);
          bound = std::min(bound, std::max<std::int64_t>(0, snap.settled_to - h - diagonal_cost_[0] + 1));
        }
      }
    }
  }
  if (!reusable || bound <= old_g[goal_]) {
    std::fill(g_.begin(), g_.end(), kInfinite);
    std::fill(rhs_.begin(), rhs_.end(), kInfinite);
    rhs_[static_cast<std::size_t>(goal_)] = 0;
    seeds_.push_back({h_[static_cast<std::size_t>(goal_)], goal_});
    return;
  }
  // Cells below the bound are settled at their old g; the ones with a neighbour above it are
  // where the search goes on from (the closed border ring among those neighbours only adds
  // seeds whose offers it refuses).
  const std::size_t n = cost_.size();
  kept_.resize(n);
  std::uint8_t* kept = kept_.data();
  std::int64_t* g = g_.data();
  std::int64_t* rhs = rhs_.data();
  for (std::size_t c = 0; c < n; ++c) {
    const bool keep = old_g[c] < bound;
    kept[c] = keep;
    g[c] = rhs[c] = keep ? old_g[c] : kInfinite;
  }
  // A seed is a kept cell with a neighbour that is not. Kept flags are 0 or 1 per byte, so
  // eight cells at a time: a byte of `edge` is 1 where the cell is kept and some neighbour is
  // not. Most words have none (inside the kept region or outside it).
  const std::ptrdiff_t w = width_;
  const auto load = [](const std::uint8_t* p) {
    std::uint64_t v;
    std::memcpy(&v, p, sizeof v);
    return v;
  };
  const auto isSeed = [&](std::ptrdiff_t i) {  // the same test for one cell
    const std::uint8_t* a = kept + i;
    return a[0] && (a[-w - 1] & a[-w] & a[-w + 1] & a[-1] & a[1] & a[w - 1] & a[w] & a[w + 1]) == 0;
  };
  const int* h = h_.data();
  for (int y = 1; y < height_ - 1; ++y) {
    const std::ptrdiff_t row = y * w;
    for (int x = 1; x < width_ - 1; x += 8) {
      const std::ptrdiff_t c = row + x;
      const int cells = std::min(8, width_ - 1 - x);
      std::uint64_t edge = 0;
      if (cells == 8) {
        const std::uint8_t* a = kept + c;
        edge = load(a) & ~(load(a - w - 1) & load(a - w) & load(a - w + 1) & load(a - 1) & load(a + 1) &
                           load(a + w - 1) & load(a + w) & load(a + w + 1));
      } else {  // the row's last few cells
        for (int k = 0; k < cells; ++k) edge |= static_cast<std::uint64_t>(isSeed(c + k)) << (8 * k);
      }
      for (; edge != 0; edge &= edge - 1) {
        const std::ptrdiff_t i = c + __builtin_ctzll(edge) / 8;
        g[i] = kInfinite;
        seeds_.push_back({old_g[i] + h[i], static_cast<int>(i)});
      }
    }
  }
  std::sort(seeds_.begin(), seeds_.end(), [](const Seed& a, const Seed& b) { return a.key < b.key || (a.key == b.key && a.cell < b.cell); });
}

void GoalField::takeSnapshot(std::int64_t settled_to) {
  snapshot_.map = map_;
  snapshot_.width = width_;
  snapshot_.height = height_;
  snapshot_.goal = goal_;
  snapshot_.start = start_;
  snapshot_.g = g_;
  snapshot_.cost = cost_;
  snapshot_.settled_to = settled_to;
}

void GoalField::search() {
  // A* from the goal: settles cells in order of f = g + h. A settled cell has g = rhs; a
  // reached one holds its best candidate in rhs. It starts from the seeds: the goal, or the
  // edge of the cells kept from the last search (seedSearch), each joining the queue
  // when the scan reaches its key.
  const int w = width_;
  fillHeuristic();
  seedSearch();
  const int* h = h_.data();
  const int* straight_cost = straight_cost_.data();
  const int* diagonal_cost = diagonal_cost_.data();
  const std::uint8_t* cost = cost_.data();
  std::int64_t* g = g_.data();
  std::int64_t* rhs = rhs_.data();
  const auto passable = [&](int c) { return straight_cost[cost[c]] >= 0; };
  // Dial's algorithm on f: a ring of buckets, one per integer f modulo (largest f increase
  // + 1), and a bitmap of the non-empty ones so the scan jumps over the (many) empty values.
  const unsigned ring = static_cast<unsigned>(diagonal_cost_[kInscribedCost - 1] + diagonal_cost_[0] + 1);
  bucket_head_.assign(static_cast<std::size_t>(ring), -1);
  bucket_entries_.clear();
  occupied_buckets_.assign(static_cast<std::size_t>(ring + 63) / 64, 0);
  std::uint64_t* occupied = occupied_buckets_.data();
  const std::size_t words = occupied_buckets_.size();
  int* head = bucket_head_.data();
  const auto push = [&](unsigned to_slot, int cell) __attribute__((always_inline)) {
    bucket_entries_.push_back({cell, head[to_slot]});
    head[to_slot] = static_cast<int>(bucket_entries_.size()) - 1;
  };
  const auto nextOccupied = [&](int slot) {  // first non-empty slot at or after `slot`, cyclically
    std::size_t word = static_cast<std::size_t>(slot) / 64;
    std::uint64_t bits = occupied[word] & (~std::uint64_t{0} << (slot % 64));
    while (bits == 0) {
      word = word + 1 == words ? 0 : word + 1;
      bits = occupied[word];
    }
    return static_cast<int>(word * 64 + static_cast<std::size_t>(__builtin_ctzll(bits)));
  };
  const auto start = static_cast<std::size_t>(start_);
  std::size_t pending = 0;
  std::size_t expanded = 0;
  int settled_lo = std::numeric_limits<int>::max(), settled_hi = -1;
  std::size_t next_seed = 0;
  std::int64_t key = seeds_.front().key;  // the key of the bucket being scanned
  int slot = 0;
  std::int64_t settled_to = kInfinite;     // stays so if the search runs out of cells
  const StraightSteps steps{offset_[0], offset_[1], offset_[2], offset_[3]};
  const int interior_x1 = w - 1, interior_y1 = height_ - 1;
  // Stop once every cell with f up to the start's g is settled (h is 0 at the start): then
  // the start's g is final, and so is every cell the descent compares.
  for (;;) {
    int next = -1;
    std::int64_t next_key = kInfinite;
    if (pending > 0) {
      next = nextOccupied(slot);
      next_key = key + (next >= slot ? next - slot : next - slot + static_cast<int>(ring));
    }
    if (next_seed < seeds_.size() && seeds_[next_seed].key <= next_key) {
      // The seeds of this key join the queue (the ring is empty beyond `ring` keys ahead).
      next_key = seeds_[next_seed].key;
      next = static_cast<int>((static_cast<std::int64_t>(slot) + (next_key - key)) % ring);
      for (; next_seed < seeds_.size() && seeds_[next_seed].key == next_key; ++next_seed) {
        push(static_cast<unsigned>(next), seeds_[next_seed].cell);
        ++pending;
      }
      occupied[next / 64] |= std::uint64_t{1} << (next % 64);
    }
    if (next_key == kInfinite) break;
    if (next_key > rhs[start]) {
      settled_to = rhs[start];
      break;
    }
    key = next_key;
    slot = next;
    // Entries join this bucket while it is taken when a step leaves f unchanged (a free step
    // straight toward the start); the loop takes them too. The order within a bucket does
    // not change the field: every cell of this key is settled before the next key.
    while (head[slot] >= 0) {
      const BucketEntry entry = bucket_entries_[static_cast<std::size_t>(head[slot])];
      head[slot] = entry.next;
      const int i = entry.cell;
      --pending;
      if (g[i] != kInfinite) continue;  // settled already: a stale entry
      const int h_here = h[i];
      const std::int64_t g_here = rhs[i];
      if (g_here + h_here != key) continue;  // a stale entry
      g[i] = g_here;
      ++expanded;
      settled_lo = std::min(settled_lo, i);
      settled_hi = std::max(settled_hi, i);
      // Backward: a neighbour p reaches this cell by entering it.
      const std::uint8_t c = cost[i];
      // Inlined at each of the eight uses: most offers fail the first test, so the call
      // would cost more than the work.
      const auto offer = [&](int p, int step) __attribute__((always_inline)) {
        const std::int64_t candidate = g_here + step;
        if (candidate >= rhs[p]) return;
        if (!passable(p)) {
          // It gets the candidate (a start may sit there) but is never queued: nothing
          // passes through it. The closed border ring gets none.
          const int px = p % w, py = p / w;
          if (px > 0 && py > 0 && px < interior_x1 && py < interior_y1) rhs[p] = candidate;
          return;
        }
        rhs[p] = candidate;
        unsigned target = static_cast<unsigned>(slot + step + h[p] - h_here);  // ahead of the slot by less than the ring
        if (target >= ring) target -= ring;
        push(target, p);
        occupied[target / 64] |= std::uint64_t{1} << (target % 64);
        ++pending;
      };
      offerToEnterers(i, steps, straight_cost[c], diagonal_cost[c], passable, offer);
    }
    occupied[slot / 64] &= ~(std::uint64_t{1} << (slot % 64));
  }
  // Seeds the search stopped before are exact all the same: settled, and their offers made
  // (not queued), so every cell's rhs is its best way through a settled neighbour, as D* Lite
  // requires of the open list that startOver builds.
  for (std::size_t k = 0; k < seeds_.size(); ++k) {
    const int i = seeds_[k].cell;
    if (g[i] != kInfinite) continue;
    g[i] = rhs[i];
    settled_lo = std::min(settled_lo, i);
    settled_hi = std::max(settled_hi, i);
    const std::uint8_t c = cost[i];
    offerToEnterers(i, steps, straight_cost[c], diagonal_cost[c], passable, [&](int p, int step) {
      const int px = p % w, py = p / w;
      if (px > 0 && py > 0 && px < interior_x1 && py < interior_y1) rhs[p] = std::min(rhs[p], g[i] + step);
    });
  }
  last_expanded_ = expanded;
  // Only a settled cell's neighbours can have got an rhs without a g: the open list lies within
  // a row and a cell of the settled range.
  const int n = static_cast<int>(cost_.size());
  searched_from_ = settled_hi < 0 ? 0 : std::max(0, settled_lo - w - 1);
  searched_to_ = settled_hi < 0 ? 0 : std::min(n, settled_hi + w + 2);
  takeSnapshot(settled_to);
}

void GoalField::fillHeuristic() {
  // The octile distance of every cell to the start (a search reads it for every cell it
  // reaches, several times). It depends on |dx| and |dy| only: each row is a row of the
  // start-independent table octile_, copied out from the start's column both ways.
  const std::size_t n = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  if (octile_width_ != width_ || octile_.size() != n) {
    octile_width_ = width_;
    const int hs = straight_cost_[0], hd = diagonal_cost_[0];
    octile_.resize(n);
    for (int dy = 0; dy < height_; ++dy)
      for (int dx = 0; dx < width_; ++dx)
        octile_[static_cast<std::size_t>(dy * width_ + dx)] = hs * std::abs(dx - dy) + hd * std::min(dx, dy);
  }
  h_.resize(n);
  const int sx = start_ % width_, sy = start_ / width_;
  for (int y = 0; y < height_; ++y) {
    const int* table = octile_.data() + static_cast<std::ptrdiff_t>(std::abs(y - sy)) * width_;
    int* row = h_.data() + static_cast<std::ptrdiff_t>(y) * width_;
    std::copy(table, table + (width_ - sx), row + sx);        // x >= sx: dx = x - sx
    std::reverse_copy(table + 1, table + sx + 1, row);        // x < sx: dx = sx - x
  }
}

bool GoalField::applyCostChanges(const Costmap& costmap) {
  const int cw = costmap.widthCells();
  const std::uint8_t* costs = costmap.costs();
  changed_.clear();
  for (int y = 0; y < costmap.heightCells(); ++y) {
    std::uint8_t* row = cost_.data() + static_cast<std::ptrdiff_t>(y + 1) * width_ + 1;
    const std::uint8_t* now = costs + static_cast<std::ptrdiff_t>(y) * cw;
    if (std::memcmp(row, now, static_cast<std::size_t>(cw)) == 0) continue;
    for (int x = 0; x < cw; ++x)
      if (row[x] != now[x]) {
        row[x] = now[x];
        changed_.push_back((y + 1) * width_ + x + 1);
      }
  }
  // A repair costs about as much as the cells whose g it changes, and a cost rise near the
  // start spreads to everything behind it; past a few dozen changed cells that the search had
  // reached, a new search is cheaper.
  std::size_t reached = 0;
  for (const int u : changed_)
    if (rhs_[static_cast<std::size_t>(u)] != kInfinite) ++reached;
  if (reached > kMaxRepairedCells) return false;
  // A cell's cost enters the moves into it and the diagonal moves around its corner: all
  // from its eight neighbours, whose best way on must be looked at again.
  if (++round_ == 0) {
    std::fill(touched_round_.begin(), touched_round_.end(), 0);
    round_ = 1;
  }
  for (const int u : changed_)
    for (int dir = 0; dir < 8; ++dir) {
      const int p = u + offset_[dir];
      const int px = p % width_, py = p / width_;
      if (px <= 0 || py <= 0 || px >= width_ - 1 || py >= height_ - 1) continue;  // the closed border
      if (touched_round_[static_cast<std::size_t>(p)] == round_) continue;
      touched_round_[static_cast<std::size_t>(p)] = round_;
      updateCell(p);
    }
  return true;
}

std::int64_t GoalField::bestThroughNeighbours(int cell) const {
  std::int64_t best = kInfinite;
  for (int dir = 0; dir < 8; ++dir) {
    if (!canMove(cell, dir)) continue;
    const int nb = cell + offset_[dir];
    const std::int64_t g = g_[static_cast<std::size_t>(nb)];
    if (g != kInfinite) best = std::min(best, g + stepCost(cost_[static_cast<std::size_t>(nb)], dir >= 4));
  }
  return best;
}

void GoalField::enqueue(int cell) {
  const auto i = static_cast<std::size_t>(cell);
  const std::int64_t k2 = std::min(g_[i], rhs_[i]);
  const std::int64_t k1 = k2 == kInfinite ? kInfinite : k2 + heuristic(cell) + k_m_;
  queued_[i] = 1;
  queued_k1_[i] = k1;
  queue_.push_back({k1, k2, cell});
  std::push_heap(queue_.begin(), queue_.end(), std::greater<>());
}

void GoalField::updateCell(int cell) {
  const auto i = static_cast<std::size_t>(cell);
  if (cell != goal_) rhs_[i] = bestThroughNeighbours(cell);
  if (g_[i] != rhs_[i]) enqueue(cell);
  else queued_[i] = 0;
}

void GoalField::repair() {
  const auto start = static_cast<std::size_t>(start_);
  const auto live = [&](const QueueEntry& e) {
    const auto i = static_cast<std::size_t>(e.cell);
    return queued_[i] && queued_k1_[i] == e.k1 && std::min(g_[i], rhs_[i]) == e.k2;
  };
  while (!queue_.empty()) {
    const QueueEntry top = queue_.front();
    std::pop_heap(queue_.begin(), queue_.end(), std::greater<>());
    queue_.pop_back();
    if (!live(top)) continue;
    // Stop once the start is consistent and every key left is above its own: unlike D* Lite,
    // cells whose key equals the start's are expanded too, so the descent's ties are exact.
    const std::int64_t start_k2 = std::min(g_[start], rhs_[start]);
    const QueueEntry start_key{start_k2 == kInfinite ? kInfinite : start_k2 + k_m_, start_k2, start_};
    if (top > start_key && g_[start] == rhs_[start]) {
      queue_.push_back(top);
      std::push_heap(queue_.begin(), queue_.end(), std::greater<>());
      break;
    }
    const int u = top.cell;
    const auto ui = static_cast<std::size_t>(u);
    queued_[ui] = 0;
    const std::int64_t k2 = std::min(g_[ui], rhs_[ui]);
    const QueueEntry now{k2 == kInfinite ? kInfinite : k2 + heuristic(u) + k_m_, k2, u};
    if (now > top) {  // its key grew since it was queued (the start moved): queue it again
      enqueue(u);
      continue;
    }
    ++last_expanded_;
    if (g_[ui] > rhs_[ui]) {
      g_[ui] = rhs_[ui];
    } else {
      g_[ui] = kInfinite;
      updateCell(u);
    }
    // The cells that may enter u: nothing enters a cell that cannot be entered.
    if (!passable(u)) continue;
    for (int dir = 0; dir < 8; ++dir) {
      const int p = u - offset_[dir];
      const int px = p % width_, py = p / width_;
      if (px <= 0 || py <= 0 || px >= width_ - 1 || py >= height_ - 1) continue;  // the closed border
      if (dir >= 4 && (!passable(p + kSteps[dir][0]) || !passable(p + kSteps[dir][1] * width_))) continue;
      updateCell(p);
    }
  }
}

bool GoalField::descend() {
  const int w = width_;
  const Eigen::Vector2d goal_xy(goal_ % w, goal_ / w);
  for (int i = start_;;) {
    path_.push_back({i % w - 1, i / w - 1});
    if (i == goal_) return true;
    const Eigen::Vector2d to_goal_dir = (goal_xy - Eigen::Vector2d(i % w, i / w)).normalized();
    int best = -1;
    std::int64_t best_cost = kInfinite;
    std::int64_t best_g = kInfinite;
    double best_alignment = -2.0;
    for (int dir = 0; dir < 8; ++dir) {
      if (!canMove(i, dir)) continue;
      const int nb = i + offset_[dir];
      const std::int64_t g = g_[static_cast<std::size_t>(nb)];
      if (g == kInfinite || g != rhs_[static_cast<std::size_t>(nb)]) continue;  // not final
      const std::int64_t through = g + stepCost(cost_[static_cast<std::size_t>(nb)], dir >= 4);
      const double alignment = Eigen::Vector2d(kSteps[dir][0], kSteps[dir][1]).normalized().dot(to_goal_dir);
      if (through < best_cost ||
          (through == best_cost && (g < best_g || (g == best_g && alignment > best_alignment)))) {
        best_cost = through;
        best_g = g;
        best_alignment = alignment;
        best = nb;
      }
    }
    if (best < 0) {  // cannot happen for a reached start; no path rather than a loop
      path_.clear();
      return false;
    }
    i = best;
  }
}

}  // namespace barn::nav
