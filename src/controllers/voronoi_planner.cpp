#include "barn/controllers/voronoi_planner.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>

#include <boost/polygon/voronoi.hpp>

namespace barn::controllers {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Boost.Polygon's Voronoi takes integer sites: decimetres are snapped to 1/1024 dm (0.01 mm),
// far below anything the planner resolves, and the BARN area (tens of metres) stays well
// inside the 32-bit range the builder's exact predicates are made for.
constexpr double kSiteScale = 1024.0;

double manhattan(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::abs(a.x() - b.x()) + std::abs(a.y() - b.y());
}

}  // namespace

void validate(const VoronoiPlannerConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.ellipse_x >= 0.0 && c.ellipse_y >= 0.0, prefix + ".ellipse_x", "semi-axes must be >= 0");
  errors.check(c.ellipse_points == 0 || c.ellipse_points >= 2, prefix + ".ellipse_points", "must be 0 or >= 2");
  errors.check(c.average_gap_limit > c.end_gap, prefix + ".average_gap_limit",
               "must be > end_gap (the start and goal edges always count)");
}

std::span<const std::string_view> enumNames(EllipseCentre) {
  static constexpr std::array<std::string_view, 2> kNames = {"start", "origin"};
  return kNames;
}

std::span<const std::string_view> enumNames(PathSwitch) {
  static constexpr std::array<std::string_view, 5> kNames = {"First", "Kept", "WiderGap", "Diverged", "Shorter"};
  return kNames;
}

// ---------------------------------------------------------------------------------------------
// The graph

VoronoiGraph buildVoronoiGraph(std::span<const Eigen::Vector2d> sites, int start_site, int goal_site, double end_gap) {
  namespace bp = boost::polygon;
  std::vector<bp::point_data<int>> input;
  input.reserve(sites.size());
  for (const Eigen::Vector2d& s : sites)
    input.emplace_back(static_cast<int>(std::lround(s.x() * kSiteScale)), static_cast<int>(std::lround(s.y() * kSiteScale)));
  bp::voronoi_diagram<double> diagram;
  bp::construct_voronoi(input.begin(), input.end(), &diagram);

  VoronoiGraph graph;
  const auto& vertices = diagram.vertices();
  const int n_vertices = static_cast<int>(vertices.size());
  graph.nodes.reserve(vertices.size() + 2);
  for (const auto& v : vertices) graph.nodes.emplace_back(v.x() / kSiteScale, v.y() / kSiteScale);
  graph.start = n_vertices;
  graph.goal = n_vertices + 1;
  graph.nodes.push_back(sites[static_cast<std::size_t>(start_site)]);
  graph.nodes.push_back(sites[static_cast<std::size_t>(goal_site)]);
  graph.adjacency.resize(graph.nodes.size());
  auto index = [&](const bp::voronoi_vertex<double>* v) { return static_cast<int>(v - vertices.data()); };
  auto site = [&](const bp::voronoi_edge<double>& e) { return sites[e.cell()->source_index()]; };

  // Finite edges, each twin pair once (Boost stores twins next to each other).
  const auto& edges = diagram.edges();
  for (std::size_t i = 0; i + 1 < edges.size(); i += 2) {
    const auto& e = edges[i];
    if (!e.is_finite()) continue;
    const double gap = (site(e) - site(*e.twin())).norm();
    const int a = index(e.vertex0()), b = index(e.vertex1());
    graph.adjacency[static_cast<std::size_t>(a)].push_back({b, gap});
    graph.adjacency[static_cast<std::size_t>(b)].push_back({a, gap});
  }

  // The start reaches every vertex of its cell; every vertex of the goal's cell that lies on a
  // finite edge reaches the goal (the team's graph is a map keyed by vertex: a vertex on
  // infinite edges only is not in it).
  for (const auto& cell : diagram.cells()) {
    const int source = static_cast<int>(cell.source_index());
    if ((source != start_site && source != goal_site) || cell.is_degenerate()) continue;
    const auto* first = cell.incident_edge();
    const auto* e = first;
    do {
      if (e->vertex0() != nullptr) {
        const int v = index(e->vertex0());
        if (source == start_site) {
          graph.adjacency[static_cast<std::size_t>(graph.start)].push_back({v, end_gap});
        } else if (!graph.adjacency[static_cast<std::size_t>(v)].empty()) {
          graph.adjacency[static_cast<std::size_t>(v)].push_back({graph.goal, end_gap});
        }
      }
      e = e->next();
    } while (e != nullptr && e != first);
  }
  return graph;
}

// ---------------------------------------------------------------------------------------------
// The searches

namespace {

/// The team's A* (both variants): `step(a, b)` is the g increment along an edge, `extra(edge)`
/// what f adds beyond g + h. Python's heap pops the least (f, (x, y)) tuple, so equal f falls to
/// the node's coordinates; the node index breaks what is left. A node is closed when popped and
/// never reopened; popping it again later is skipped, which is what the team's re-expansion
/// amounts to (a closed node's neighbours cannot improve through it twice).
template <class Step, class Extra>
std::optional<GraphPath> search(const VoronoiGraph& graph, const VoronoiPlannerConfig& config, Step step, Extra extra) {
  struct Entry {
    double f;
    double x, y;
    int node;
    bool operator>(const Entry& o) const {
      if (f != o.f) return f > o.f;
      if (x != o.x) return x > o.x;
      if (y != o.y) return y > o.y;
      return node > o.node;
    }
  };
  const std::size_t n = graph.nodes.size();
  std::vector<double> g(n, kInf);
  std::vector<char> closed(n, 0);
  std::vector<int> parent(n, -1);
  std::vector<double> parent_gap(n, 0.0);
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  const Eigen::Vector2d& goal = graph.nodes[static_cast<std::size_t>(graph.goal)];
  g[static_cast<std::size_t>(graph.start)] = 0.0;
  open.push({0.0, graph.nodes[static_cast<std::size_t>(graph.start)].x(),
             graph.nodes[static_cast<std::size_t>(graph.start)].y(), graph.start});
  while (!open.empty()) {
    const Entry top = open.top();
    open.pop();
    const auto current = static_cast<std::size_t>(top.node);
    if (top.node == graph.goal) {
      GraphPath path;
      double gap_sum = 0.0;
      int gap_count = 0;
      for (int v = graph.goal; v != graph.start; v = parent[static_cast<std::size_t>(v)]) {
        path.points.push_back(graph.nodes[static_cast<std::size_t>(v)]);
        const double gap = parent_gap[static_cast<std::size_t>(v)];
        if (gap < config.average_gap_limit) {
          gap_sum += gap;
          ++gap_count;
        }
      }
      path.points.push_back(graph.nodes[static_cast<std::size_t>(graph.start)]);
      std::reverse(path.points.begin(), path.points.end());
      path.average_gap = gap_count > 0 ? gap_sum / gap_count : 0.0;
      return path;
    }
    if (closed[current]) continue;
    closed[current] = 1;
    for (const GraphEdge& edge : graph.adjacency[current]) {
      const auto next = static_cast<std::size_t>(edge.to);
      if (closed[next] || edge.gap < config.min_gap) continue;
      const double tentative = g[current] + step(graph.nodes[current], graph.nodes[next]);
      if (tentative < g[next]) {
        g[next] = tentative;
        parent[next] = top.node;
        parent_gap[next] = edge.gap;
        const double f = tentative + manhattan(graph.nodes[next], goal) + extra(edge);
        open.push({f, graph.nodes[next].x(), graph.nodes[next].y(), edge.to});
      }
    }
  }
  return std::nullopt;
}

}  // namespace

std::optional<GraphPath> searchWidest(const VoronoiGraph& graph, const VoronoiPlannerConfig& config) {
  return search(
      graph, config, [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return (a - b).norm(); },
      [&](const GraphEdge& e) { return config.gap_weight / e.gap; });
}

std::optional<GraphPath> searchNearOldPath(const VoronoiGraph& graph, std::span<const Eigen::Vector2d> old_path,
                                           const VoronoiPlannerConfig& config) {
  return search(graph, config, manhattan, [&](const GraphEdge& e) {
    const Eigen::Vector2d& p = graph.nodes[static_cast<std::size_t>(e.to)];
    double nearest = kInf;
    for (const Eigen::Vector2d& q : old_path) nearest = std::min(nearest, manhattan(p, q));
    return config.old_path_weight * nearest;
  });
}

double pathLength(std::span<const Eigen::Vector2d> path) {
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) length += (path[i] - path[i - 1]).norm();
  return length;
}

namespace {

/// Each segment as `samples` evenly spaced points, ends included (joints appear twice).
std::vector<Eigen::Vector2d> densify(std::span<const Eigen::Vector2d> path, int samples) {
  std::vector<Eigen::Vector2d> points;
  if (path.size() == 1) points.push_back(path[0]);
  for (std::size_t i = 1; i < path.size(); ++i)
    for (int k = 0; k < samples; ++k) {
      const double t = static_cast<double>(k) / (samples - 1);
      points.push_back(path[i - 1] + t * (path[i] - path[i - 1]));
    }
  return points;
}

/// max over a of the distance to the nearest point of b.
double directedHausdorff(const std::vector<Eigen::Vector2d>& a, const std::vector<Eigen::Vector2d>& b) {
  double worst_sq = 0.0;
  for (const Eigen::Vector2d& p : a) {
    double nearest_sq = kInf;
    for (const Eigen::Vector2d& q : b) {
      nearest_sq = std::min(nearest_sq, (p - q).squaredNorm());
      if (nearest_sq <= worst_sq) break;  // p cannot raise the maximum
    }
    worst_sq = std::max(worst_sq, nearest_sq);
  }
  return std::sqrt(worst_sq);
}

}  // namespace

double pathHausdorff(std::span<const Eigen::Vector2d> a, std::span<const Eigen::Vector2d> b, int samples) {
  const std::vector<Eigen::Vector2d> pa = densify(a, samples), pb = densify(b, samples);
  if (pa.empty() || pb.empty()) return kInf;
  return std::max(directedHausdorff(pa, pb), directedHausdorff(pb, pa));
}

PathSwitch choosePath(const GraphPath& fresh, const GraphPath& replanned, std::span<const Eigen::Vector2d> old_path,
                      const VoronoiPlannerConfig& c) {
  if (fresh.average_gap > c.switch_gap_ratio * replanned.average_gap &&
      old_path.size() > static_cast<std::size_t>(c.switch_min_old_points))
    return PathSwitch::WiderGap;
  if (pathHausdorff(old_path, replanned.points, c.hausdorff_samples) > c.switch_hausdorff) return PathSwitch::Diverged;
  if (pathLength(fresh.points) < c.switch_length_ratio * pathLength(old_path) &&
      fresh.average_gap >= c.switch_length_gap_ratio * replanned.average_gap)
    return PathSwitch::Shorter;
  return PathSwitch::Kept;
}

std::vector<Eigen::Vector2d> ellipseArc(const Eigen::Vector2d& centre, double heading, double semi_x, double semi_y,
                                        int count) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < count; ++i) {
    const double a = heading + std::numbers::pi / 2.0 + i * std::numbers::pi / (count - 1);
    points.push_back(centre + Eigen::Vector2d(semi_x * std::cos(a), semi_y * std::sin(a)));
  }
  return points;
}

// ---------------------------------------------------------------------------------------------
// The clearing polygon

ScanPolygon::ScanPolygon(std::span<const Eigen::Vector2d> vertices) : vertices_(vertices.begin(), vertices.end()) {
  if (vertices_.size() < 3) return;
  x_min_ = x_max_ = vertices_[0].x();
  y_min_ = y_max_ = vertices_[0].y();
  for (const Eigen::Vector2d& v : vertices_) {
    x_min_ = std::min(x_min_, v.x());
    x_max_ = std::max(x_max_, v.x());
    y_min_ = std::min(y_min_, v.y());
    y_max_ = std::max(y_max_, v.y());
  }
  // About as many bins as edges: most scan edges are short, so each bin holds a few.
  const std::size_t n = vertices_.size();
  const int bins = static_cast<int>(std::clamp<std::size_t>(n, 1, 4096));
  bin_height_ = std::max((y_max_ - y_min_) / bins, 1e-9);
  auto bin = [&](double y) { return std::clamp(static_cast<int>((y - y_min_) / bin_height_), 0, bins - 1); };
  std::vector<int> count(static_cast<std::size_t>(bins) + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const double a = vertices_[i].y(), b = vertices_[(i + 1) % n].y();
    for (int k = bin(std::min(a, b)); k <= bin(std::max(a, b)); ++k) ++count[static_cast<std::size_t>(k) + 1];
  }
  for (std::size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
  bin_start_ = count;
  bin_edges_.resize(static_cast<std::size_t>(count.back()));
  for (std::size_t i = 0; i < n; ++i) {
    const double a = vertices_[i].y(), b = vertices_[(i + 1) % n].y();
    for (int k = bin(std::min(a, b)); k <= bin(std::max(a, b)); ++k)
      bin_edges_[static_cast<std::size_t>(count[static_cast<std::size_t>(k)]++)] = static_cast<int>(i);
  }
}

bool ScanPolygon::contains(const Eigen::Vector2d& p) const {
  if (vertices_.size() < 3 || p.x() < x_min_ || p.x() > x_max_ || p.y() < y_min_ || p.y() > y_max_) return false;
  const int bins = static_cast<int>(bin_start_.size()) - 1;
  const int k = std::clamp(static_cast<int>((p.y() - y_min_) / bin_height_), 0, bins - 1);
  const std::size_t n = vertices_.size();
  bool inside = false;
  for (int j = bin_start_[static_cast<std::size_t>(k)]; j < bin_start_[static_cast<std::size_t>(k) + 1]; ++j) {
    const auto i = static_cast<std::size_t>(bin_edges_[static_cast<std::size_t>(j)]);
    const Eigen::Vector2d& a = vertices_[i];
    const Eigen::Vector2d& b = vertices_[(i + 1) % n];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
      inside = !inside;
  }
  return inside;
}

// ---------------------------------------------------------------------------------------------
// The planner

void VoronoiPlanner::reset() {
  started_ = false;
  goal_.setZero();
  origin_.setZero();
  heading_ = 0.0;
  memory_.clear();
  path_.clear();
  last_switch_ = PathSwitch::First;
  last_graph_nodes_ = 0;
}

std::vector<Eigen::Vector2d> VoronoiPlanner::pathMetres() const {
  std::vector<Eigen::Vector2d> metres;
  metres.reserve(path_.size());
  for (const Eigen::Vector2d& p : path_) metres.push_back(p / config_.scale);
  return metres;
}

void VoronoiPlanner::updateMemory(const core::LaserScan& scan, const core::Pose2& robot, const core::Pose2& sensor) {
  const core::PoseFrame frame(sensor);
  const double s = config_.scale;
  // The clearing polygon: the robot, then every beam's end a little beyond its return.
  std::vector<Eigen::Vector2d> polygon;
  polygon.reserve(scan.ranges.size() + 1);
  polygon.push_back(s * robot.position());
  std::vector<GridPoint> seen;
  seen.reserve(scan.ranges.size());
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    const double a = scan.angle(i);
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    const double reach = (std::isfinite(r) ? r : config_.clear_inf_range) + config_.clear_margin;
    polygon.push_back(s * frame.toParent(reach * dir));
    if (!std::isfinite(r)) continue;
    // Python's round() rounds halves to even, as nearbyint does in the default rounding mode.
    const Eigen::Vector2d p = s * frame.toParent(r * dir) / config_.grid;
    seen.push_back({static_cast<int>(std::nearbyint(p.x())) * config_.grid,
                    static_cast<int>(std::nearbyint(p.y())) * config_.grid});
  }
  const ScanPolygon clearing(polygon);
  std::erase_if(memory_, [&](const GridPoint& q) { return clearing.contains(Eigen::Vector2d(q.x, q.y)); });
  memory_.insert(memory_.end(), seen.begin(), seen.end());
  std::sort(memory_.begin(), memory_.end());
  memory_.erase(std::unique(memory_.begin(), memory_.end()), memory_.end());
}

bool VoronoiPlanner::plan(const core::LaserScan& scan, const core::Pose2& robot, const core::Pose2& sensor) {
  const double s = config_.scale;
  if (!started_) {
    // Fixed at the first cycle: the goal ahead, the heading the arc is laid out from.
    started_ = true;
    origin_ = robot.position();
    heading_ = robot.yaw;
    goal_ = s * (robot.position() + config_.goal_distance * Eigen::Vector2d(std::cos(robot.yaw), std::sin(robot.yaw)));
  }
  updateMemory(scan, robot, sensor);

  std::vector<Eigen::Vector2d> sites;
  sites.reserve(memory_.size() + static_cast<std::size_t>(config_.ellipse_points) + 2);
  sites.push_back(goal_);
  sites.push_back(s * robot.position());
  for (const GridPoint& q : memory_) sites.emplace_back(q.x, q.y);
  const Eigen::Vector2d centre = config_.ellipse_centre == EllipseCentre::Start ? robot.position() : origin_;
  for (const Eigen::Vector2d& p : ellipseArc(centre, heading_, config_.ellipse_x, config_.ellipse_y, config_.ellipse_points))
    sites.push_back(s * p);
  const VoronoiGraph graph = buildVoronoiGraph(sites, 1, 0, config_.end_gap);
  last_graph_nodes_ = graph.nodes.size();

  const std::optional<GraphPath> fresh = searchWidest(graph, config_);
  if (!fresh) {
    memory_.clear();
    path_.clear();
    return false;
  }
  if (path_.empty()) {
    last_switch_ = PathSwitch::First;
    path_ = fresh->points;
    return true;
  }
  const std::optional<GraphPath> replanned = searchNearOldPath(graph, path_, config_);
  // Both searches see the same graph and gap limit, so the second finds a path when the first
  // does; the check keeps a broken invariant from reading an empty optional.
  last_switch_ = replanned ? choosePath(*fresh, *replanned, path_, config_) : PathSwitch::WiderGap;
  path_ = last_switch_ == PathSwitch::Kept ? replanned->points : fresh->points;
  return true;
}

}  // namespace barn::controllers
