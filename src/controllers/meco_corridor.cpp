#include "barn/controllers/meco_corridor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace barn::controllers {

std::span<const std::string_view> enumNames(MecoEdge) {
  static constexpr std::string_view kNames[] = {"Front", "Right", "Back", "Left"};
  return kNames;
}

Eigen::Vector2d MecoCorridor::axis() const { return {std::cos(heading), std::sin(heading)}; }

Eigen::Vector2d MecoCorridor::left() const { return {-std::sin(heading), std::cos(heading)}; }

Eigen::Vector2d MecoCorridor::normal(MecoEdge edge) const {
  switch (edge) {
    case MecoEdge::Front: return axis();
    case MecoEdge::Right: return -left();
    case MecoEdge::Back: return -axis();
    case MecoEdge::Left: return left();
  }
  return axis();
}

double MecoCorridor::halfExtent(MecoEdge edge) const {
  return edge == MecoEdge::Front || edge == MecoEdge::Back ? 0.5 * length : 0.5 * width;
}

bool MecoCorridor::contains(const Eigen::Vector2d& p, double tolerance) const {
  const Eigen::Vector2d d = p - center;
  return std::abs(d.dot(axis())) <= 0.5 * length + tolerance && std::abs(d.dot(left())) <= 0.5 * width + tolerance;
}

std::array<Eigen::Vector2d, 4> MecoCorridor::corners() const {
  const Eigen::Vector2d f = 0.5 * length * axis();
  const Eigen::Vector2d l = 0.5 * width * left();
  return {center + f - l, center - f - l, center - f + l, center + f + l};
}

double MecoCorridor::maxCornerY() const {
  double y = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& c : corners()) y = std::max(y, c.y());
  return y;
}

Eigen::Vector2d MecoCorridor::frontPoint(double margin) const { return center + (0.5 * length - margin) * axis(); }

Eigen::Vector2d MecoCorridor::backPoint(double margin) const { return center - (0.5 * length - margin) * axis(); }

void MecoCorridor::moveEdge(MecoEdge edge, double distance) {
  center += 0.5 * distance * normal(edge);
  if (edge == MecoEdge::Front || edge == MecoEdge::Back)
    length += distance;
  else
    width += distance;
}

void MecoCorridor::turnQuarter(bool clockwise) {
  heading += clockwise ? -std::numbers::pi / 2 : std::numbers::pi / 2;
  std::swap(length, width);
}

MecoCorridor MecoCorridor::reversed() const {
  MecoCorridor r = *this;
  r.heading = core::wrapAngle(heading + std::numbers::pi);
  return r;
}

MecoCorridor MecoCorridor::toParent(const core::Pose2& pose) const {
  const core::PoseFrame frame(pose);
  MecoCorridor r = *this;
  r.center = frame.toParent(center);
  r.growth_center = frame.toParent(growth_center);
  r.heading = core::wrapAngle(heading + pose.yaw);
  return r;
}

bool intersectLines(const Eigen::Vector2d& a, const Eigen::Vector2d& da, const Eigen::Vector2d& b,
                    const Eigen::Vector2d& db, Eigen::Vector2d& point) {
  const double cross = da.x() * db.y() - da.y() * db.x();
  if (std::abs(cross) < 1e-12) return false;
  const Eigen::Vector2d ab = b - a;
  const double s = (ab.x() * db.y() - ab.y() * db.x()) / cross;
  point = a + s * da;
  return true;
}

void edgeLine(const MecoCorridor& corridor, MecoEdge edge, Eigen::Vector2d& point, Eigen::Vector2d& direction) {
  const Eigen::Vector2d n = corridor.normal(edge);
  point = corridor.center + corridor.halfExtent(edge) * n;
  direction = {-n.y(), n.x()};
}

}  // namespace barn::controllers
