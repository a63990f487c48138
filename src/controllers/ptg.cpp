#include "barn/controllers/ptg.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace barn::controllers {

namespace {
constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
// MRPT stops simulating a path after this much turning, so a tight circle does not run into
// its own start (CPTG_DiffDrive_CollisionGridBased::simulateTrajectories).
constexpr double kMaxTurn = 1.95 * kPi;  // [rad]

// Wraps to (-pi, pi], as mrpt::math::wrapToPi does (core::wrapAngle's [-pi, pi) would send
// alpha = pi to the first path instead of the last).
double wrapToPi(double a) {
  a = std::fmod(a + kPi, 2.0 * kPi);
  if (a <= 0.0) a += 2.0 * kPi;
  return a - kPi;
}

// Wraps to [0, 2 pi); -0 becomes +0 (a contact right at the start is distance +0).
double wrapTo2Pi(double a) {
  a = std::fmod(a, 2.0 * kPi);
  return a < 0.0 ? a + 2.0 * kPi : a + 0.0;
}
}  // namespace

void validate(const PtgConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(c.resolution > 0.0 && c.resolution <= c.ref_distance, prefix + ".resolution",
               "must be in (0, ref_distance]");
  errors.check(c.v_falloff >= 0.0 && c.v_falloff * kPi < 1.0, prefix + ".v_falloff",
               "must be in [0, 1 / pi) (every path must drive forward)");
  if (errors.check(c.shape_x.size() == c.shape_y.size(), prefix + ".shape_y", "must have as many values as shape_x"))
    errors.check(c.shape_x.size() >= 3, prefix + ".shape_x", "must have at least 3 vertices");
}

double pathAlpha(int k, int n) { return kPi * (-1.0 + (2.0 * k + 1.0) / n); }

int alphaIndex(double alpha, int n) {
  const long k = std::lround(0.5 * (n * (1.0 + wrapToPi(alpha) / kPi) - 1.0));
  return static_cast<int>(std::clamp<long>(k, 0, n - 1));
}

ArcPtg::ArcPtg(const PtgConfig& config) : config_(config), w_max_(config.w_max_deg * kPi / 180.0) {
  for (std::size_t i = 0; i < config_.shape_x.size(); ++i) {
    shape_.emplace_back(config_.shape_x[i], config_.shape_y[i]);
    max_radius_ = std::max(max_radius_, shape_.back().norm());
  }
  path_length_.resize(static_cast<std::size_t>(pathCount()));
  for (int k = 0; k < pathCount(); ++k) {
    const double v = linearSpeed(k), w = angularSpeed(k), r = config_.turning_radius_reference;
    const double loop = w == 0.0 ? kInf : kMaxTurn / std::abs(w) * std::sqrt(v * v + w * w * r * r);
    path_length_[static_cast<std::size_t>(k)] = std::min(config_.ref_distance, loop);
  }
  buildGrid();
}

double ArcPtg::linearSpeed(int k) const { return config_.v_max * (1.0 - config_.v_falloff * std::abs(alpha(k))); }

double ArcPtg::angularSpeed(int k) const { return alpha(k) / kPi * w_max_; }

core::Pose2 ArcPtg::poseAt(int k, double distance) const {
  const double v = linearSpeed(k), w = angularSpeed(k), r = config_.turning_radius_reference;
  const double t = distance / std::sqrt(v * v + w * w * r * r);
  if (w == 0.0) return {v * t, 0.0, 0.0};
  const double radius = v / w, turn = w * t;
  return {radius * std::sin(turn), radius * (1.0 - std::cos(turn)), turn};
}

TpPoint ArcPtg::inverseMap(const Eigen::Vector2d& p) const {
  const int n = pathCount();
  TpPoint tp;
  if (p.y() == 0.0) {
    // On the x axis: straight ahead along the straight path, or unreachable behind.
    if (p.x() > 0.0) {
      tp.k = alphaIndex(0.0, n);
      tp.distance = p.x();
    } else {
      tp.k = n - 1;
      tp.distance = 1e3;
      tp.exact = false;
    }
    return tp;
  }
  // The circle through the origin, tangent to x, through p: centre (0, R).
  const double radius = p.squaredNorm() / (2.0 * p.y());
  const double abs_r = std::abs(radius);
  const double turn = wrapTo2Pi(p.y() > 0.0 ? std::atan2(p.x(), abs_r - p.y()) : std::atan2(p.x(), abs_r + p.y()));
  const double r = config_.turning_radius_reference;
  tp.distance = turn * std::sqrt(radius * radius + r * r);
  // The path of that radius: R(a) = v_max (1 - f a) / (a w_max / pi) solved for a = |alpha|.
  double a = config_.v_max / (abs_r * w_max_ / kPi + config_.v_max * config_.v_falloff);
  if (a > kPi) {
    // Tighter than the tightest path (|R| < v_max (1 - f pi) / w_max).
    a = kPi;
    tp.exact = false;
  }
  tp.k = alphaIndex(radius > 0.0 ? a : -a, n);
  return tp;
}

bool ArcPtg::insideShape(const Eigen::Vector2d& p) const {
  bool inside = false;
  for (std::size_t i = 0, j = shape_.size() - 1; i < shape_.size(); j = i++) {
    const Eigen::Vector2d& a = shape_[i];
    const Eigen::Vector2d& b = shape_[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x())
      inside = !inside;
  }
  return inside;
}

double ArcPtg::collisionDistance(int k, const Eigen::Vector2d& p) const {
  if (insideShape(p)) return 0.0;
  const double v = linearSpeed(k), w = angularSpeed(k), r = config_.turning_radius_reference;
  const double length = pathLength(k);
  double best = kInf;
  if (w == 0.0) {
    // Straight: in the robot's frame the point slides back along -x by the distance driven;
    // it enters the polygon where that horizontal line first crosses an edge.
    for (std::size_t i = 0, j = shape_.size() - 1; i < shape_.size(); j = i++) {
      const Eigen::Vector2d& a = shape_[j];
      const Eigen::Vector2d& b = shape_[i];
      if (a.y() == b.y() || p.y() < std::min(a.y(), b.y()) || p.y() > std::max(a.y(), b.y())) continue;
      const double x_edge = a.x() + (p.y() - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
      if (p.x() >= x_edge) best = std::min(best, p.x() - x_edge);
    }
    return best <= length ? best : kInf;
  }
  // Turning about c = (0, R): in the robot's frame the point turns about c by -w t, on the
  // circle of radius rho; the polygon lies within max_radius_ of the origin, |R| from c.
  const double radius = v / w;
  const Eigen::Vector2d c(0.0, radius);
  const Eigen::Vector2d q = p - c;
  const double rho = q.norm();
  if (rho < std::abs(radius) - max_radius_ || rho > std::abs(radius) + max_radius_) return kInf;
  const double start = std::atan2(q.y(), q.x());
  const double sign = w > 0.0 ? 1.0 : -1.0;
  double best_turn = kInf;
  for (std::size_t i = 0, j = shape_.size() - 1; i < shape_.size(); j = i++) {
    const Eigen::Vector2d f = shape_[j] - c;
    const Eigen::Vector2d e = shape_[i] - shape_[j];
    const double qa = e.squaredNorm(), qb = 2.0 * f.dot(e), qc = f.squaredNorm() - rho * rho;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc < 0.0) continue;
    const double root = std::sqrt(disc);
    for (const double s : {(-qb - root) / (2.0 * qa), (-qb + root) / (2.0 * qa)}) {
      if (s < 0.0 || s > 1.0) continue;
      const Eigen::Vector2d hit = f + s * e;
      best_turn = std::min(best_turn, wrapTo2Pi(sign * (start - std::atan2(hit.y(), hit.x()))));
    }
  }
  if (best_turn == kInf) return kInf;
  best = best_turn / std::abs(w) * std::sqrt(v * v + w * w * r * r);
  return best <= length ? best : kInf;
}

void ArcPtg::buildGrid() {
  const double ref = config_.ref_distance, res = config_.resolution;
  cells_ = static_cast<int>(std::ceil(2.0 * ref / res - 1e-9));
  const int corners = cells_ + 1;
  const auto cell_count = static_cast<std::size_t>(cells_) * static_cast<std::size_t>(cells_);
  std::vector<std::vector<CellEntry>> lists(cell_count);
  std::vector<float> cell_min(cell_count);
  std::vector<std::size_t> touched;
  for (int k = 0; k < pathCount(); ++k) {
    std::fill(cell_min.begin(), cell_min.end(), std::numeric_limits<float>::infinity());
    touched.clear();
    for (int iy = 0; iy < corners; ++iy)
      for (int ix = 0; ix < corners; ++ix) {
        const double d = collisionDistance(k, {-ref + ix * res, -ref + iy * res});
        if (d == kInf) continue;
        // The corner is shared by the cells (ix - 1 .. ix, iy - 1 .. iy).
        for (int cy = iy - 1; cy <= iy; ++cy)
          for (int cx = ix - 1; cx <= ix; ++cx) {
            if (cx < 0 || cy < 0 || cx >= cells_ || cy >= cells_) continue;
            const std::size_t cell = static_cast<std::size_t>(cy) * static_cast<std::size_t>(cells_) +
                                     static_cast<std::size_t>(cx);
            if (cell_min[cell] == std::numeric_limits<float>::infinity()) touched.push_back(cell);
            cell_min[cell] = std::min(cell_min[cell], static_cast<float>(d));
          }
      }
    for (const std::size_t cell : touched) lists[cell].push_back({static_cast<std::uint16_t>(k), cell_min[cell]});
  }
  cell_begin_.assign(cell_count + 1, 0);
  std::size_t total = 0;
  for (std::size_t cell = 0; cell < cell_count; ++cell) {
    cell_begin_[cell] = static_cast<std::uint32_t>(total);
    total += lists[cell].size();
  }
  cell_begin_[cell_count] = static_cast<std::uint32_t>(total);
  entries_.reserve(total);
  for (const auto& list : lists) entries_.insert(entries_.end(), list.begin(), list.end());
}

std::span<const ArcPtg::CellEntry> ArcPtg::cellEntries(const Eigen::Vector2d& p) const {
  const double ref = config_.ref_distance, res = config_.resolution;
  const double fx = std::floor((p.x() + ref) / res), fy = std::floor((p.y() + ref) / res);
  if (!(fx >= 0.0 && fy >= 0.0 && fx < cells_ && fy < cells_)) return {};
  const std::size_t cell = static_cast<std::size_t>(fy) * static_cast<std::size_t>(cells_) + static_cast<std::size_t>(fx);
  return {entries_.data() + cell_begin_[cell], entries_.data() + cell_begin_[cell + 1]};
}

void ArcPtg::tpObstacles(std::span<const Eigen::Vector2d> points, std::vector<double>& out) const {
  out.assign(path_length_.begin(), path_length_.end());
  for (const Eigen::Vector2d& p : points) {
    const std::span<const CellEntry> entries = cellEntries(p);
    if (entries.empty()) continue;
    const bool inside = insideShape(p);
    for (const CellEntry& e : entries) {
      double& free = out[e.k];
      if (!inside) {
        free = std::min(free, static_cast<double>(e.distance));
      } else if (e.distance >= max_radius_) {
        // COLL_BEH_BACK_AWAY: already touching and the path goes further in.
        free = 0.0;
      }  // else: moving away from a point already inside the robot; ignore it.
    }
  }
  for (double& free : out) free /= config_.ref_distance;
}

}  // namespace barn::controllers
