#include "barn/controllers/applr_dwa.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/QR>

#include "barn/controllers/lflh.hpp"
#include "barn/core/text_io.hpp"

namespace barn::controllers {

namespace {

// The least-squares weights that give the polynomial of degree `order` through `window` points
// at abscissae 0 .. window - 1, evaluated at abscissa `at`: value = sum_k w_k y_k.
// (Centred on the window for conditioning.)
Eigen::VectorXd polynomialWeights(int window, int order, double at) {
  const double centre = 0.5 * (window - 1);
  Eigen::MatrixXd a(window, order + 1);
  for (int k = 0; k < window; ++k)
    for (int j = 0; j <= order; ++j) a(k, j) = std::pow(k - centre, j);
  Eigen::VectorXd e(order + 1);
  for (int j = 0; j <= order; ++j) e[j] = std::pow(at - centre, j);
  // w = A (A^T A)^-1 e: the fitted coefficients are (A^T A)^-1 A^T y, and their value at `at` is e . coefficients.
  const Eigen::MatrixXd normal = a.transpose() * a;
  return a * normal.colPivHouseholderQr().solve(e);
}

// What each action of the published actor sets on the DWA.
struct KnownAction {
  const char* name;
  std::vector<std::string> keys;
  bool whole;
};

const std::vector<KnownAction>& knownActions() {
  static const std::vector<KnownAction> kActions = {
      {"max_vel_x", {"max_vel_x"}, false},
      {"max_vel_theta", {"max_vel_theta"}, false},
      {"vx_samples", {"vx_samples"}, true},
      {"vtheta_samples", {"vtheta_samples"}, true},
      {"path_distance_bias", {"pdist_scale"}, false},
      {"goal_distance_bias", {"gdist_scale"}, false},
      // move_base.py reconfigures the inflater_layer of both costmaps.
      {"inflation_radius", {"global_costmap.inflation_radius", "local_costmap.inflation_radius"}, false},
  };
  return kActions;
}

}  // namespace

void validate(const ApplrDwaConfig& c, core::Errors& errors, const std::string& prefix) {
  core::validateFields(c, errors, prefix);
  errors.check(!c.policy.empty(), prefix + ".policy", "must name the converted actor (tools/import_applr_weights.py)");
  errors.check(c.smoothing_window == 0 || (c.smoothing_window >= 3 && c.smoothing_window % 2 == 1 && c.smoothing_window <= 1001),
               prefix + ".smoothing_window", "must be 0 (no smoothing) or odd in [3, 1001]");
  errors.check(c.smoothing_window == 0 || (c.smoothing_order >= 0 && c.smoothing_order < c.smoothing_window),
               prefix + ".smoothing_order", "must be in [0, smoothing_window)");
  validate(c.dwa, errors, prefix + ".dwa");
}

std::vector<double> savitzkyGolay(const std::vector<double>& values, int window, int order) {
  const int n = static_cast<int>(values.size());
  if (window < 3 || n < window) return values;
  const int half = window / 2;
  std::vector<double> out(values.size());
  const Eigen::VectorXd centre = polynomialWeights(window, order, half);
  for (int i = half; i < n - half; ++i) {
    double sum = 0.0;
    for (int k = 0; k < window; ++k) sum += centre[k] * values[static_cast<std::size_t>(i - half + k)];
    out[static_cast<std::size_t>(i)] = sum;
  }
  // The ends: the polynomial through the first (last) window values, evaluated at each end point.
  for (int i = 0; i < half; ++i) {
    const Eigen::VectorXd first = polynomialWeights(window, order, i);
    const Eigen::VectorXd last = polynomialWeights(window, order, window - half + i);
    double head = 0.0, tail = 0.0;
    for (int k = 0; k < window; ++k) {
      head += first[k] * values[static_cast<std::size_t>(k)];
      tail += last[k] * values[static_cast<std::size_t>(n - window + k)];
    }
    out[static_cast<std::size_t>(i)] = head;
    out[static_cast<std::size_t>(n - half + i)] = tail;
  }
  return out;
}

double applrGoalAngle(const nav::Path& path, const core::Pose2& pose, double los, int window, int order) {
  if (path.empty()) return 0.0;  // the local goal stays (0, 0): atan2(0, 0)
  std::vector<double> xs(path.size()), ys(path.size());
  for (std::size_t i = 0; i < path.size(); ++i) {
    xs[i] = path[i].x();
    ys[i] = path[i].y();
  }
  if (window > 0) {
    xs = savitzkyGolay(xs, window, order);
    ys = savitzkyGolay(ys, window, order);
  }
  std::size_t chosen = path.size() - 1;
  for (std::size_t i = 0; i < path.size(); ++i)
    if (std::hypot(xs[i] - pose.x, ys[i] - pose.y) > los) {
      chosen = i;
      break;
    }
  const Eigen::Vector2d local = pose.inverseTransform({xs[chosen], ys[chosen]});
  return std::atan2(local.y(), local.x());
}

std::shared_ptr<const learning::ApplrPolicy> loadApplrPolicy(const std::string& policy, const std::string& config_source) {
  namespace fs = std::filesystem;
  const std::string resolved = resolvePolicyPath(policy, config_source);
  std::error_code ec;
  if (!fs::exists(resolved, ec)) {
    // Name where the config means it: beside the config file for a relative path.
    fs::path meant(policy);
    if (meant.is_relative() && !config_source.empty() && fs::is_regular_file(config_source, ec))
      meant = (fs::path(config_source).parent_path() / meant).lexically_normal();
    throw core::InputError(meant.string() + ": no such file: the APPLR actor is not shipped; convert your copy of the "
                           "published policy_actor (Daffan/the-barn-challenge, branch applr, applr/data/param_policy) with "
                           "`/usr/bin/python3 tools/import_applr_weights.py policy_actor --out " + meant.string() + "`");
  }
  return std::make_shared<const learning::ApplrPolicy>(learning::ApplrPolicy::load(resolved));
}

ApplrDwaController::ApplrDwaController(const ApplrDwaConfig& config, std::shared_ptr<const learning::ApplrPolicy> policy)
    : config_(config), policy_(std::move(policy)), dwa_(config.dwa) {
  const learning::ApplrPolicyInfo& info = policy_->info();
  for (const learning::ApplrAction& action : info.actions) {
    const KnownAction* known = nullptr;
    for (const KnownAction& k : knownActions())
      if (action.name == k.name) known = &k;
    if (!known) {
      std::string names;
      for (const KnownAction& k : knownActions()) names += (names.empty() ? "" : ", ") + std::string(k.name);
      throw core::InputError("APPLR policy '" + info.name + "': action " + action.name + " is not a parameter applr_dwa sets (" +
                             names + ")");
    }
    targets_.push_back({known->keys, known->whole});
    // Both ends of the range must be values the DWA takes (checked here, on the DWA that reset()
    // then restores).
    for (const double end : {action.lo, action.hi}) {
      const double value = known->whole ? std::trunc(end) : end;
      for (const std::string& key : known->keys) {
        try {
          dwa_.setParameter(key, value);
        } catch (const std::invalid_argument& e) {
          throw core::InputError("APPLR policy '" + info.name + "': action " + action.name + " range [" +
                                 core::formatDouble(action.lo) + ", " + core::formatDouble(action.hi) +
                                 "]: the DWA refuses " + core::formatDouble(value) + " (" + e.what() + ")");
        }
      }
    }
  }
}

void ApplrDwaController::reset(const EpisodeInfo& info) {
  dwa_.reset(info);
  next_update_ = 0.0;
  last_.clear();
  changes_.clear();
}

void ApplrDwaController::checkLidar(const core::LidarConfig& lidar) const {
  if (policy_->info().beams != lidar.beams)
    throw core::InputError("APPLR policy '" + policy_->info().name + "' reads " + std::to_string(policy_->info().beams) +
                           " beams but the LiDAR gives " + std::to_string(lidar.beams) + " (lidar.beams in the sim config)");
}

core::Twist ApplrDwaController::act(const Observation& obs) {
  const core::Twist command = dwa_.act(obs);
  changes_.clear();
  constexpr double kSlack = 1e-9;  // the ticks' times are multiples of the control period up to rounding
  if (obs.time >= next_update_ - kSlack) {
    tune(obs);
    while (next_update_ <= obs.time + kSlack) next_update_ += config_.period;
  }
  return command;
}

void ApplrDwaController::tune(const Observation& obs) {
  const double angle = applrGoalAngle(dwa_.navStack().path(), obs.odom_pose, config_.los, config_.smoothing_window,
                                      config_.smoothing_order);
  last_ = policy_->act(*obs.scan, angle);
  for (std::size_t i = 0; i < last_.size(); ++i) {
    // dynamic_reconfigure's client casts to the parameter's type: int() truncates.
    if (targets_[i].whole) last_[i] = std::trunc(last_[i]);
    for (const std::string& key : targets_[i].keys) {
      dwa_.setParameter(key, last_[i]);
      if (!changes_.empty()) changes_ += ';';
      changes_ += key + "=" + core::formatDouble(last_[i]);
    }
  }
}

}  // namespace barn::controllers
