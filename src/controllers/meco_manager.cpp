#include "barn/controllers/meco_manager.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "barn/core/types.hpp"

namespace barn::controllers {

namespace {
constexpr double kDeg = std::numbers::pi / 180.0;
}  // namespace

void validate(const MecoManagerConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(std::isfinite(c.quality_margin), prefix + ".quality_margin", "must be finite");
}

double corridorImprovement(const MecoCorridor& parent, const MecoCorridor& child) {
  const double h1 = 0.5 * parent.length;
  const double w1 = 0.5 * parent.width;
  // From the growth centre to the child's front edge, along the child's heading.
  const double h2 = 0.5 * child.length - (child.growth_center - child.center).dot(child.axis());
  // The growth centre in the parent's frame: ahead of its centre (y1) and to its left (x1).
  const Eigen::Vector2d g = child.growth_center - parent.center;
  const double y1 = g.dot(parent.axis());
  const double x1 = g.dot(parent.left());
  const double gamma = core::wrapAngle(child.heading - parent.heading);
  double beyond = 0.0;
  if (gamma >= 0.0) {
    // Turning left: out through the front unless the heading passes the front-left corner.
    if (gamma >= std::atan2(w1 - x1, h1 - y1))
      beyond = h2 - (w1 - x1) / std::cos(std::numbers::pi / 2 - gamma);
    else
      beyond = h2 - (h1 - y1) / std::cos(gamma);
  } else {
    if (gamma >= std::atan2(-(w1 + x1), h1 - y1))
      beyond = h2 - (h1 - y1) / std::cos(gamma);
    else
      beyond = h2 - (w1 + x1) / std::cos(gamma + std::numbers::pi / 2);
  }
  return std::max(0.0, beyond);
}

bool significantlyDifferent(const MecoCorridor& a, const MecoCorridor& b, double distance, double angle) {
  const auto ca = a.corners();
  const auto cb = b.corners();
  // The team's corners 0 and 3: front right and front left.
  const double apart = (ca[0] - cb[0]).norm() + (ca[3] - cb[3]).norm();
  return apart > distance && std::abs(core::wrapAngle(a.heading - b.heading)) > angle;
}

std::span<const std::string_view> enumNames(MecoMessageKind) {
  static constexpr std::string_view kNames[] = {"Next", "Final", "Backtrack"};
  return kNames;
}

std::span<const std::string_view> enumNames(MecoPhase) {
  static constexpr std::string_view kNames[] = {"Starting",           "Exploring",    "WaitingAtEnd",
                                                "WaitingToBacktrack", "Backtracking", "GoalInSight"};
  return kNames;
}

void MecoManager::reset() {
  nodes_.clear();
  orphans_.clear();
  pending_.clear();
  root_ = current_ = -1;
  goal_in_sight_ = backtracking_ = waiting_at_end_ = waiting_to_backtrack_ = false;
  end_since_ = backtrack_since_ = 0.0;
}

void MecoManager::receive(std::span<const MecoCorridor> corridors) {
  pending_.insert(pending_.end(), corridors.begin(), corridors.end());
}

MecoPhase MecoManager::phase() const {
  if (goal_in_sight_) return MecoPhase::GoalInSight;
  if (backtracking_) return MecoPhase::Backtracking;
  if (current_ < 0) return MecoPhase::Starting;
  if (waiting_to_backtrack_) return MecoPhase::WaitingToBacktrack;
  if (waiting_at_end_) return MecoPhase::WaitingAtEnd;
  return MecoPhase::Exploring;
}

int MecoManager::addChild(int parent, const MecoCorridor& corridor, bool force, double margin) {
  const int grandparent = nodes_[static_cast<std::size_t>(parent)].parent;
  if (!force && grandparent >= 0 &&
      !significantlyDifferent(nodes_[static_cast<std::size_t>(grandparent)].corridor, corridor, config_.parent_distance, 0.0))
    return -1;
  Node node;
  node.corridor = corridor;
  node.parent = parent;
  node.quality = corridor.maxCornerY() > nodes_[static_cast<std::size_t>(parent)].corridor.maxCornerY() + margin ? 1.0 : 0.1;
  nodes_.push_back(std::move(node));
  const int index = static_cast<int>(nodes_.size()) - 1;
  nodes_[static_cast<std::size_t>(parent)].children.push_back(index);
  return index;
}

void MecoManager::sortChildren(int node) {
  std::vector<int>& children = nodes_[static_cast<std::size_t>(node)].children;
  std::stable_sort(children.begin(), children.end(), [&](int a, int b) {
    return nodes_[static_cast<std::size_t>(a)].corridor.maxCornerY() > nodes_[static_cast<std::size_t>(b)].corridor.maxCornerY();
  });
}

void MecoManager::detach(int node) {
  Node& n = nodes_[static_cast<std::size_t>(node)];
  if (n.parent >= 0) {
    std::vector<int>& siblings = nodes_[static_cast<std::size_t>(n.parent)].children;
    siblings.erase(std::remove(siblings.begin(), siblings.end(), node), siblings.end());
  }
  n.parent = -1;
}

void MecoManager::removeSimilarChildren(int node) {
  const double angle = config_.similar_angle_deg * kDeg;
  // Copied: detach() edits the list.
  const std::vector<int> children = nodes_[static_cast<std::size_t>(node)].children;
  std::vector<bool> removed(children.size(), false);
  for (std::size_t i = children.size(); i-- > 1;) {
    for (std::size_t j = 0; j < i; ++j) {
      if (removed[j]) continue;
      if (!significantlyDifferent(nodes_[static_cast<std::size_t>(children[i])].corridor,
                                  nodes_[static_cast<std::size_t>(children[j])].corridor, config_.similar_distance, angle)) {
        detach(children[i]);
        removed[i] = true;
        break;
      }
    }
  }
}

bool MecoManager::hasQualityChild(int node) const {
  for (const int child : nodes_[static_cast<std::size_t>(node)].children)
    if (nodes_[static_cast<std::size_t>(child)].quality >= config_.quality_threshold) return true;
  return false;
}

int MecoManager::selectChild(int node) const {
  const std::vector<int>& children = nodes_[static_cast<std::size_t>(node)].children;
  if (children.empty()) return -1;
  for (const int child : children)
    if (nodes_[static_cast<std::size_t>(child)].quality >= config_.quality_threshold) return child;
  return children.front();
}

bool MecoManager::similarToOrphan(const MecoCorridor& corridor, double angle) const {
  return std::any_of(orphans_.begin(), orphans_.end(), [&](const MecoCorridor& orphan) {
    return !significantlyDifferent(orphan, corridor, config_.orphan_distance, angle);
  });
}

void MecoManager::clearOrphanLike(int node) {
  // Angle -1: any heading differs, so only the corners' distance counts (the team's -0.1).
  const std::vector<int> children = nodes_[static_cast<std::size_t>(node)].children;
  for (std::size_t i = children.size(); i-- > 0;)
    if (similarToOrphan(nodes_[static_cast<std::size_t>(children[i])].corridor, -1.0)) detach(children[i]);
  for (const int child : std::vector<int>(nodes_[static_cast<std::size_t>(node)].children)) clearOrphanLike(child);
}

std::vector<MecoCorridor> MecoManager::backtrack() {
  const int dead_end = current_;
  int parent = nodes_[static_cast<std::size_t>(dead_end)].parent;
  if (parent < 0) return {};
  std::vector<MecoCorridor> route = {nodes_[static_cast<std::size_t>(dead_end)].corridor,
                                     nodes_[static_cast<std::size_t>(parent)].corridor};
  // The team removes the parent's first child, which is the dead end (the child taken is the
  // first of its parent's, and later corridors go to the dead end, not its parent).
  detach(dead_end);
  orphans_.push_back(nodes_[static_cast<std::size_t>(dead_end)].corridor);
  const Eigen::Vector2d dead_centre = nodes_[static_cast<std::size_t>(dead_end)].corridor.center;
  // Go back far enough, and past explored corridors with a single way on.
  while (true) {
    const Node& p = nodes_[static_cast<std::size_t>(parent)];
    if (p.parent < 0) break;
    const bool near = (dead_centre - p.corridor.center).norm() <= config_.min_backtrack_distance;
    if (!near && !(p.fully_explored && p.children.size() == 1)) break;
    const int left_behind = parent;
    parent = p.parent;
    route.push_back(nodes_[static_cast<std::size_t>(parent)].corridor);
    detach(left_behind);
    orphans_.push_back(nodes_[static_cast<std::size_t>(left_behind)].corridor);
  }
  current_ = parent;
  return route;
}

void MecoManager::processNew(const MecoCorridor& corridor, const Eigen::Vector2d& goal, std::vector<MecoMessage>& out) {
  if (root_ < 0) {
    Node node;
    node.corridor = corridor;
    nodes_.push_back(std::move(node));
    root_ = current_ = static_cast<int>(nodes_.size()) - 1;
    out.push_back({MecoMessageKind::Next, {corridor}});
    return;
  }
  const Node& current = nodes_[static_cast<std::size_t>(current_)];
  // Fitted while the robot was outside the current corridor: not for this corridor.
  if (current.parent >= 0 && !current.corridor.contains(corridor.growth_center)) return;
  if (corridor.contains(goal, config_.inside_tolerance)) {
    if (addChild(current_, corridor, false, 0.0) >= 0) {
      removeSimilarChildren(current_);
      sortChildren(current_);
    }
    goal_in_sight_ = true;
    out.push_back({MecoMessageKind::Final, {corridor}});
    return;
  }
  const bool stuck = corridorImprovement(current.corridor, corridor) < config_.stuck_threshold;
  const bool backed_out = similarToOrphan(corridor, 0.0);
  if (stuck || backed_out) return;
  if (addChild(current_, corridor, false, config_.quality_margin) >= 0) {
    sortChildren(current_);
    removeSimilarChildren(current_);
  }
}

std::vector<MecoMessage> MecoManager::tick(double time, const Eigen::Vector2d& robot, const Eigen::Vector2d& goal) {
  std::vector<MecoMessage> out;
  if (goal_in_sight_) return out;
  if (backtracking_) {
    // Wait until the robot is back in the corridor it returns to; what was fitted meanwhile is dropped.
    if (!nodes_[static_cast<std::size_t>(current_)].corridor.contains(robot, config_.inside_tolerance)) return out;
    backtracking_ = false;
    pending_.clear();
  }
  for (const MecoCorridor& corridor : pending_) {
    processNew(corridor, goal, out);
    if (goal_in_sight_) break;
  }
  pending_.clear();
  if (goal_in_sight_ || current_ < 0) return out;

  Node& current = nodes_[static_cast<std::size_t>(current_)];
  const bool end_reached = (current.corridor.frontPoint(0.0) - robot).norm() < config_.end_distance;
  current.fully_explored = end_reached;
  if (!end_reached && !hasQualityChild(current_)) return out;

  int chosen = -1;
  if (end_reached && !waiting_at_end_) {
    waiting_at_end_ = true;
    end_since_ = time;
  } else if (end_reached) {
    if (time - end_since_ > config_.end_wait) {
      waiting_at_end_ = false;
      chosen = selectChild(current_);
    }
  } else {
    waiting_at_end_ = false;
    chosen = selectChild(current_);
  }
  if (chosen >= 0) {
    waiting_to_backtrack_ = false;
    current_ = chosen;
    out.push_back({MecoMessageKind::Next, {nodes_[static_cast<std::size_t>(chosen)].corridor}});
    return out;
  }
  // No child taken (or still waiting at the end): the backtracking clock runs.
  if (!waiting_to_backtrack_) {
    waiting_to_backtrack_ = true;
    backtrack_since_ = time;
  } else if (time - backtrack_since_ > config_.backtrack_wait) {
    waiting_to_backtrack_ = false;
    std::vector<MecoCorridor> route = backtrack();
    if (!route.empty()) {
      clearOrphanLike(root_);
      backtracking_ = true;
      out.push_back({MecoMessageKind::Backtrack, std::move(route)});
    }
  }
  return out;
}

}  // namespace barn::controllers
