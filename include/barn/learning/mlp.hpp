#pragma once
/// The LfLH policy network and its training arithmetic, on Eigen:
///
///     h1 = f(W1 x + b1),  h2 = f(W2 h1 + b2),  y = W3 h2 + b3      (no output squashing)
///
/// f is the hidden layers' activation: relu(z) = max(z, 0), or leaky_relu(z) = z for z > 0 and
/// slope * z otherwise (the published LfLH network: slope 0.01, PyTorch's default), with x = 720 clipped ranges + the unit goal (722), 256 hidden units, y = (v, w). Loss of a
/// batch of B columns: L = (1/B) sum_b ||y_b - t_b||^2, the mean over the batch of the summed
/// squared error of v and w (the original's loss). Instantiated for float (training and
/// inference) and double (the finite-difference gradient test).
///
/// Eigen runs single-threaded here (barn_learning is built with EIGEN_DONT_PARALLELIZE), so a
/// run is bit-reproducible on one machine.

#include <cstddef>
#include <span>
#include <string_view>

#include <Eigen/Core>

#include "barn/core/rng.hpp"

namespace barn::learning {

/// The hidden layers' activation (see the header comment); the slope is leaky_relu's.
enum class Activation { Relu, LeakyRelu };
/// The config names, in enum order: "relu", "leaky_relu" (makes Activation a core::NamedEnum).
std::span<const std::string_view> enumNames(Activation);

template <class Scalar>
struct MlpParameters {
  using Matrix = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;

  Matrix w1;  // (hidden x inputs)
  Vector b1;  // (hidden)
  Matrix w2;  // (hidden x hidden)
  Vector b2;  // (hidden)
  Matrix w3;  // (outputs x hidden)
  Vector b3;  // (outputs)

  /// Zero parameters of the given shape.
  static MlpParameters zeros(int inputs, int hidden, int outputs);
  int inputs() const { return static_cast<int>(w1.cols()); }
  int hidden() const { return static_cast<int>(w1.rows()); }
  int outputs() const { return static_cast<int>(w3.rows()); }
  std::size_t count() const;  // number of scalars

  /// Calls f(name, data, size) for each block in file order: w1 b1 w2 b2 w3 b3. Matrices are
  /// column-major in memory.
  template <class F> void forEachBlock(F&& f) {
    f("w1", w1.data(), w1.size()); f("b1", b1.data(), b1.size());
    f("w2", w2.data(), w2.size()); f("b2", b2.data(), b2.size());
    f("w3", w3.data(), w3.size()); f("b3", b3.data(), b3.size());
  }
};

template <class Scalar>
class Mlp {
 public:
  using Matrix = typename MlpParameters<Scalar>::Matrix;
  using Parameters = MlpParameters<Scalar>;

  Mlp(int inputs, int hidden, int outputs, Activation activation = Activation::Relu, double slope = 0.01);
  explicit Mlp(Parameters parameters, Activation activation = Activation::Relu, double slope = 0.01);

  /// PyTorch's nn.Linear initialisation: every weight and bias U(-k, k), k = 1 / sqrt(fan_in).
  void initialise(core::Rng& rng);

  /// y for a batch (inputs x B) -> (outputs x B). Keeps the activations for backward().
  const Matrix& forward(const Matrix& x);
  /// Loss of the last forward() against `target` (outputs x B), and its gradient into `grad`.
  double backward(const Matrix& x, const Matrix& target, Parameters& grad);
  /// forward() + backward().
  double lossAndGradient(const Matrix& x, const Matrix& target, Parameters& grad);
  /// The loss alone (no activations kept beyond the call's own).
  double loss(const Matrix& x, const Matrix& target);

  Parameters& parameters() { return p_; }
  const Parameters& parameters() const { return p_; }
  Activation activation() const { return activation_; }
  double slope() const { return static_cast<double>(slope_); }

 private:
  Parameters p_;
  Activation activation_;
  Scalar slope_;  // leaky_relu's negative slope
  Matrix h1_, h2_, y_;  // activations of the last forward()
};

/// Adam (Kingma & Ba) with bias correction: beta1 0.9, beta2 0.999, eps 1e-8.
template <class Scalar>
class Adam {
 public:
  Adam(const MlpParameters<Scalar>& shape, double learning_rate);
  /// One update of `params` by `grad`.
  void step(MlpParameters<Scalar>& params, MlpParameters<Scalar>& grad);
  long steps() const { return t_; }

 private:
  MlpParameters<Scalar> m_, v_;  // first and second moment estimates
  double learning_rate_;
  long t_ = 0;
};

extern template struct MlpParameters<float>;
extern template struct MlpParameters<double>;
extern template class Mlp<float>;
extern template class Mlp<double>;
extern template class Adam<float>;
extern template class Adam<double>;

}  // namespace barn::learning
