#pragma once
/// Savitzky-Golay smoothing of a sequence, as scipy.signal.savgol_filter computes it with its
/// default edge mode `interp` (deriv 0, unit spacing):
///  - each point with `window / 2` neighbours on both sides is the value at its own position of
///    the least-squares polynomial of degree `order` through the `window` points centred on it;
///  - the first and last `window / 2` points are the values at their positions of the one
///    least-squares polynomial through the first (last) `window` points.
/// The smoothing is linear and its weights sum to 1, so smoothing a path's x and y apart and then
/// moving the path rigidly gives what moving it first gives.

#include <span>
#include <vector>

#include <Eigen/Core>

namespace barn::nav {

class SavitzkyGolay {
 public:
  /// `window` odd and > `order` >= 0 (window <= 1001); std::invalid_argument otherwise.
  SavitzkyGolay(int window, int order);

  /// The smoothed sequence. Needs x.size() >= window (scipy's `interp` raises ValueError
  /// otherwise); std::invalid_argument if shorter.
  std::vector<double> smooth(std::span<const double> x) const;
  /// Both coordinates of a path, each smoothed apart; the path itself if it is shorter than the
  /// window (what LiCS-KI's node does when savgol_filter raises).
  std::vector<Eigen::Vector2d> smoothPath(const std::vector<Eigen::Vector2d>& path) const;

  int window() const { return window_; }
  int order() const { return order_; }
  /// Row p (0 <= p < window) holds the weights that give the fitted value at window position p
  /// from the window's points: the least-squares projection ("hat") matrix. Row window / 2 is
  /// the interior convolution.
  const Eigen::MatrixXd& weights() const { return hat_; }

 private:
  int window_;
  int order_;
  Eigen::MatrixXd hat_;  // (window x window)
};

}  // namespace barn::nav
