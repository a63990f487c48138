#pragma once
/// A 2D costmap in the odom frame, as ROS costmap_2d builds it from a laser scan: an obstacle
/// layer (marking and ray-trace clearing) and an inflation layer (cost decaying with the
/// distance to the nearest obstacle).
///
/// Costs follow costmap_2d: 0 free, 1..252 inflated, 253 inscribed (the robot's centre here
/// means its inscribed circle touches an obstacle), 254 lethal (an obstacle cell), 255 unknown.
/// Inflated cost at distance d from the nearest obstacle cell (cell centre to cell centre):
///   d <= inscribed_radius                 -> 253
///   inscribed_radius < d <= inflation_radius -> 252 exp(-cost_scaling_factor (d - inscribed_radius))
///   d > inflation_radius                  -> 0
///
/// Changes (scans, cleared polygons, marked obstacles) are recorded as they come; update()
/// folds them into the costs, as costmap_2d's updateMap does, recomputing the inflation only in
/// the window around the cells that became or stopped being obstacles, so an update costs what
/// it changed. The readers are const and read the map as of the last update(); reading a map
/// with changes not yet folded in is a programming error (std::logic_error).

#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "barn/core/beam_directions.hpp"
#include "barn/core/config.hpp"
#include "barn/core/errors.hpp"
#include "barn/core/types.hpp"

namespace barn::nav {

inline constexpr std::uint8_t kFreeCost = 0;
inline constexpr std::uint8_t kInscribedCost = 253;
inline constexpr std::uint8_t kLethalCost = 254;
inline constexpr std::uint8_t kUnknownCost = 255;

struct CostmapConfig {
  double resolution = 0.05;
  double width = 10.0;
  double height = 10.0;
  double origin_x = -5.0;
  double origin_y = -5.0;
  bool rolling = false;
  double obstacle_range = 2.5;
  double raytrace_range = 3.0;
  bool clearing = true;
  bool inf_is_valid = false;
  bool track_unknown = false;
  // The inscribed radius is no setting: nav::NavStack derives it from the footprint (see
  // NavStackConfig::inscribedRadius). ROS sets footprint_padding per costmap; this is the
  // difference of this map's from the stack's, seen by its inflation only (the footprint
  // clearing and the move_base checks use the stack's padding).
  double inscribed_padding_offset = 0.0;
  double inflation_radius = 0.30;
  double cost_scaling_factor = 10.0;

  template <class V> void visit(V& v) {
    v("resolution", resolution, {.unit = "m", .range = core::kPositive, .doc = "cell size"});
    v("width", width, {.unit = "m", .doc = "along x"});
    v("height", height, {.unit = "m", .doc = "along y"});
    v("origin_x", origin_x, {.unit = "m", .doc = "odom frame: lower-left corner of a fixed map (a rolling"});
    v("origin_y", origin_y, {.doc = "window is centred on the robot instead)"});
    v("rolling", rolling, {.doc = "the window follows the robot (local costmap)"});
    v("obstacle_range", obstacle_range,
      {.unit = "m", .range = core::kPositive, .doc = "returns closer than this mark obstacles"});
    v("raytrace_range", raytrace_range,
      {.unit = "m", .range = core::kPositive, .doc = "free space is cleared up to here along each ray"});
    v("clearing", clearing, {.doc = "the scan clears along its rays (costmap_2d observation source `clearing`)"});
    v("inf_is_valid", inf_is_valid, {.doc = "a beam without a return clears (it never does in BARN)"});
    v("track_unknown", track_unknown, {.doc = "unseen cells are unknown (255) rather than free"});
    v("inscribed_padding_offset", inscribed_padding_offset, {.unit = "m", .doc = "our choice: 0, the stack's padding"});
    v("inflation_radius", inflation_radius, {.unit = "m", .range = core::kNonNegative});
    v("cost_scaling_factor", cost_scaling_factor,
      {.unit = "1/m", .range = core::kNonNegative, .doc = "costmap_2d default"});
  }
};

void validate(const CostmapConfig& config, core::Errors& errors, const std::string& prefix);

/// A cell index.
struct CellIndex {
  int x = 0;
  int y = 0;
  friend bool operator==(const CellIndex&, const CellIndex&) = default;
};

class Costmap {
 public:
  /// `inscribed_radius` [m]: the radius of the robot's padded footprint (nav/footprint.hpp),
  /// within which of an obstacle a cell costs 253.
  Costmap(const CostmapConfig& config, double inscribed_radius);

  /// Marks the returns of `scan` taken from `sensor_pose` (odom frame) and clears the cells
  /// its rays cross; then brings the inflation up to date. A rolling map first re-centres on
  /// `robot_position`.
  void integrateScan(const core::LaserScan& scan, const core::Pose2& sensor_pose, const Eigen::Vector2d& robot_position);

  /// Re-centres a rolling window on `position` (no-op for a fixed map), as costmap_2d does:
  /// the window moves by whole cells, and only once the robot is a full cell from the centre.
  void recentre(const Eigen::Vector2d& position);
  /// Where recentre(position) would put the lower-left corner of a window now at `origin`
  /// (`origin` itself for a fixed map, or while the robot is within a cell of the centre).
  Eigen::Vector2d windowOriginFor(const Eigen::Vector2d& origin, const Eigen::Vector2d& position) const;

  /// Frees the obstacle cells under the convex polygon (odom frame, corners in order), the
  /// cells of polygonCells(): costmap_2d's footprint clearing, so the robot never sees itself
  /// as stuck in an obstacle it only now sees beside it.
  void clearPolygon(const std::vector<Eigen::Vector2d>& polygon);

  /// The cells costmap_2d takes as under a convex polygon (convexFillCells): the rasterised
  /// outline plus, per column, every cell between its lowest and highest outline cell; empty
  /// if a corner is off the map. Cells may repeat.
  std::vector<CellIndex> polygonCells(const std::vector<Eigen::Vector2d>& polygon) const;

  /// Marks the cell containing `p` as an obstacle and updates the inflation (a static obstacle;
  /// also how tests draw maps).
  void markObstacle(const Eigen::Vector2d& p);

  /// New inflation settings, as costmap_2d's InflationLayer takes them from dynamic_reconfigure:
  /// every cost is recomputed at the next read. A radius below the inscribed radius is allowed
  /// (costmap_2d's too: cells beyond it stay free).
  void setInflation(double inflation_radius, double cost_scaling_factor);
  /// New obstacle and raytrace ranges [m], used from the next scan on.
  void setRanges(double obstacle_range, double raytrace_range);

  /// Forgets everything: every cell back to unseen (free, or unknown when unknown space is
  /// tracked), as costmap_2d's resetLayers leaves the map until its next update.
  void reset();

  /// Forgets the obstacles farther than `radius` from `centre` (move_base's clearing
  /// recovery resets them to unknown, or free when unknown space is not tracked).
  void clearOutside(const Eigen::Vector2d& centre, double radius);

  int widthCells() const { return width_; }
  int heightCells() const { return height_; }
  double resolution() const { return config_.resolution; }
  const CostmapConfig& config() const { return config_; }
  double inscribedRadius() const { return inscribed_radius_; }  // [m]
  Eigen::Vector2d origin() const { return origin_; }  // [m] odom frame, lower-left corner

  bool inBounds(int x, int y) const { return x >= 0 && y >= 0 && x < width_ && y < height_; }
  bool toCell(const Eigen::Vector2d& p, CellIndex& cell) const { return toCell(p.x(), p.y(), cell); }
  /// The cell containing (px, py) [m, odom frame]; false if it is off the map.
  bool toCell(double px, double py, CellIndex& cell) const {
    const double fx = (px - origin_.x()) / config_.resolution;
    const double fy = (py - origin_.y()) / config_.resolution;
    if (fx < 0.0 || fy < 0.0) return false;
    cell = {static_cast<int>(fx), static_cast<int>(fy)};
    return inBounds(cell.x, cell.y);
  }
  Eigen::Vector2d cellCentre(CellIndex cell) const;

  /// Folds every change since the last update into the costs (the inflation around them).
  void update();

  /// Final (inflated) cost of a cell; cells outside the map are unknown.
  std::uint8_t cost(int x, int y) const {
    if (!inBounds(x, y)) return kUnknownCost;
    requireUpdated();
    return cost_[index(x, y)];
  }
  /// All final costs, row-major (x fastest), widthCells() x heightCells().
  const std::uint8_t* costs() const {
    requireUpdated();
    return cost_.data();
  }
  std::uint8_t costAt(const Eigen::Vector2d& p) const;
  /// True if the cell holds an obstacle (marked and not cleared since).
  bool isObstacle(int x, int y) const { return inBounds(x, y) && obstacle_[index(x, y)] == kLethalCost; }
  /// True if the cell is unknown space (tracked, never seen, or forgotten); off the map too.
  bool isUnknown(int x, int y) const { return !inBounds(x, y) || obstacle_[index(x, y)] == kUnknownCost; }

  /// Changes whenever a cost changed (planners cache on it); a scan that only confirms what
  /// the map held leaves it.
  std::uint64_t version() const {
    requireUpdated();
    return version_;
  }

  /// The inflation cost for a distance d [m] to the nearest obstacle (see the header comment).
  std::uint8_t inflationCost(double distance) const;
  /// The same for a distance counted in cells, without the radius cut-off (costmap_2d
  /// computes costs in cell units and cuts at ceil(inflation_radius / resolution) cells).
  std::uint8_t inflationCostAtCells(double cells) const;

 private:
  /// How many cells an obstacle's inflation reaches: ceil(inflation_radius / resolution), or
  /// less where the cost has fallen to 0 before.
  int inflationReach() const;
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) + static_cast<std::size_t>(x); }
  /// Cells [x0, x1) x [y0, y1).
  struct CellBox {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool empty() const { return x1 <= x0 || y1 <= y0; }
  };

  void setObstacle(int x, int y, std::uint8_t value) {
    if (obstacle_[index(x, y)] != value) changeObstacle(x, y, value);  // most ray cells are free already
  }
  void changeObstacle(int x, int y, std::uint8_t value);
  void queueReinflation(CellBox box);
  void foldCellChangesIntoBox();
  /// Throws std::logic_error if there are changes update() has not folded in yet.
  void requireUpdated() const;
  void buildKernel();
  /// Recomputes the costs of the cells of `changed` grown by `grow` cells on every side.
  void reinflate(CellBox changed, int grow);
  /// Sets one cell's cost from the obstacles within the reach.
  void recomputeCell(int x, int y);
  /// Raises the free cells of `target` around obstacle (ox, oy) to its kernel.
  void stampObstacle(int ox, int oy, CellBox target);
  /// The cell where costmap_2d's ray trace from cell `from` toward `to` ends: `to` pulled
  /// back onto the map along the ray.
  CellIndex rayStopCell(CellIndex from, const Eigen::Vector2d& to) const;
  /// Frees every cell of the traced line from `from` to `stop`, at most `max_cells` steps
  /// (see integrateScan).
  void clearLine(CellIndex from, CellIndex stop, double max_cells);

  CostmapConfig config_;
  double inscribed_radius_ = 0.0;  // [m]
  int width_ = 0;
  int height_ = 0;
  Eigen::Vector2d origin_;
  std::vector<std::uint8_t> obstacle_;  // kLethalCost, kFreeCost or kUnknownCost per cell
  // Final cost per cell: obstacle_ and the inflation, as of the last update().
  std::vector<std::uint8_t> cost_;
  // Changes whose inflation is not yet folded in: cells whose state may differ from the one
  // their costs were computed for (inflated_state_), and regions (a few boxes, merged when
  // many; re-inflated with a margin of the reach plus one cell).
  std::vector<std::uint8_t> inflated_state_;
  std::vector<CellIndex> changed_;
  std::vector<CellBox> pending_;
  bool stale_ = false;
  int inflation_cells_ = 0;             // cells an obstacle's cost reaches (inflationReach)
  // The inflation cost of an obstacle cell at each offset (dx, dy) in [-r, r]^2, r the
  // inflation reach in cells, row-major: a cell's cost is the largest any obstacle stamps on it
  // (cost falls with distance, so that is the cost at the nearest obstacle). Built by the first
  // inflation (buildKernel): a map whose costs are never read never pays for it (a 5 m kernel
  // has 31 000 offsets to sort).
  std::vector<std::uint8_t> kernel_;
  // The same offsets' squared distance in cells where they cost more than 0, else
  // the largest value (no obstacle).
  std::vector<std::uint32_t> kernel_distance_;
  // The kernel's non-zero offsets (the centre excluded), nearest first.
  struct KernelOffset {
    int dx = 0, dy = 0;
    std::ptrdiff_t flat = 0;    // dy * width + dx
    std::uint32_t squared = 0;  // dx^2 + dy^2
    std::uint8_t cost = 0;
  };
  std::vector<KernelOffset> offsets_by_distance_;
  std::vector<std::size_t> first_offset_from_;  // [d]: first offset with squared >= d
  // Per cell, the squared distance in cells to the obstacle its cost comes from (the largest
  // value if none is within the reach; 0 for a cell that is not free): the obstacle a cleared cell was
  // is known exactly, where equal costs would also name every other obstacle whose cost ties.
  std::vector<std::uint32_t> nearest_;
  // Scratch of inflatePending(): the round in which each cell was last recomputed.
  std::vector<std::uint32_t> recomputed_in_round_;
  std::uint32_t recompute_round_ = 0;
  std::uint64_t version_ = 0;
  core::BeamDirections beams_;  // in the sensor frame
  struct Return {
    Eigen::Vector2d end;  // [m] odom frame
    bool marks;           // within obstacle_range
  };
  std::vector<Return> returns_;  // scratch of integrateScan: the scan's usable returns
};

}  // namespace barn::nav
