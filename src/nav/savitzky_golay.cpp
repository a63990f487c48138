#include "barn/nav/savitzky_golay.hpp"

#include <stdexcept>
#include <string>

#include <Eigen/QR>

namespace barn::nav {

SavitzkyGolay::SavitzkyGolay(int window, int order) : window_(window), order_(order) {
  if (window < 1 || window > 1001 || window % 2 == 0 || order < 0 || order >= window)
    throw std::invalid_argument("Savitzky-Golay: window must be odd, at most 1001 and greater than the order (window " +
                                std::to_string(window) + ", order " + std::to_string(order) + ")");
  // Vandermonde matrix of the positions centred on the window's middle (centring keeps it well
  // conditioned; the fitted values do not depend on where the origin is).
  const int half = window / 2;
  Eigen::MatrixXd a(window, order + 1);
  for (int p = 0; p < window; ++p) {
    double power = 1.0;
    for (int k = 0; k <= order; ++k, power *= static_cast<double>(p - half)) a(p, k) = power;
  }
  // H = A (A^T A)^-1 A^T, by QR: with A = Q R, H = Q Q^T over A's column space.
  const Eigen::HouseholderQR<Eigen::MatrixXd> qr(a);
  const Eigen::MatrixXd q = qr.householderQ() * Eigen::MatrixXd::Identity(window, order + 1);
  hat_ = q * q.transpose();
}

std::vector<double> SavitzkyGolay::smooth(std::span<const double> x) const {
  const auto n = static_cast<std::ptrdiff_t>(x.size());
  if (n < window_)
    throw std::invalid_argument("Savitzky-Golay: " + std::to_string(n) + " points, fewer than the window of " +
                                std::to_string(window_));
  const int half = window_ / 2;
  std::vector<double> out(x.size());
  const auto fitted = [&](std::ptrdiff_t first, int position) {
    double sum = 0.0;
    for (int j = 0; j < window_; ++j) sum += hat_(position, j) * x[static_cast<std::size_t>(first + j)];
    return sum;
  };
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (i < half) out[static_cast<std::size_t>(i)] = fitted(0, static_cast<int>(i));
    else if (i >= n - half) out[static_cast<std::size_t>(i)] = fitted(n - window_, static_cast<int>(i - (n - window_)));
    else out[static_cast<std::size_t>(i)] = fitted(i - half, half);
  }
  return out;
}

std::vector<Eigen::Vector2d> SavitzkyGolay::smoothPath(const std::vector<Eigen::Vector2d>& path) const {
  if (static_cast<int>(path.size()) < window_) return path;
  std::vector<double> xs(path.size()), ys(path.size());
  for (std::size_t i = 0; i < path.size(); ++i) {
    xs[i] = path[i].x();
    ys[i] = path[i].y();
  }
  const std::vector<double> sx = smooth(xs), sy = smooth(ys);
  std::vector<Eigen::Vector2d> out(path.size());
  for (std::size_t i = 0; i < path.size(); ++i) out[i] = {sx[i], sy[i]};
  return out;
}

}  // namespace barn::nav
