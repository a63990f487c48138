#include "barn/learning/mlp.hpp"

#include <cmath>

namespace barn::learning {

std::span<const std::string_view> enumNames(Activation) {
  static constexpr std::string_view kNames[] = {"relu", "leaky_relu"};
  return kNames;
}

template <class Scalar>
MlpParameters<Scalar> MlpParameters<Scalar>::zeros(int inputs, int hidden, int outputs) {
  MlpParameters p;
  p.w1 = Matrix::Zero(hidden, inputs);
  p.b1 = Vector::Zero(hidden);
  p.w2 = Matrix::Zero(hidden, hidden);
  p.b2 = Vector::Zero(hidden);
  p.w3 = Matrix::Zero(outputs, hidden);
  p.b3 = Vector::Zero(outputs);
  return p;
}

template <class Scalar>
std::size_t MlpParameters<Scalar>::count() const {
  return static_cast<std::size_t>(w1.size() + b1.size() + w2.size() + b2.size() + w3.size() + b3.size());
}

template <class Scalar>
Mlp<Scalar>::Mlp(int inputs, int hidden, int outputs, Activation activation, double slope)
    : p_(Parameters::zeros(inputs, hidden, outputs)), activation_(activation), slope_(static_cast<Scalar>(slope)) {}

template <class Scalar>
Mlp<Scalar>::Mlp(Parameters parameters, Activation activation, double slope)
    : p_(std::move(parameters)), activation_(activation), slope_(static_cast<Scalar>(slope)) {}

namespace {

// The activation in place. relu keeps its original form (cwiseMax) so that relu networks give
// the same bits as before leaky_relu existed.
template <class Matrix, class Scalar>
void activate(Matrix& h, Activation activation, Scalar slope) {
  if (activation == Activation::Relu) h = h.cwiseMax(Scalar(0));
  else h = (h.array() > Scalar(0)).select(h, slope * h);
}

// delta through the activation, from its output h: relu passes where h > 0; leaky_relu passes
// there and scales by the slope elsewhere (h > 0 exactly where its input is > 0).
template <class Matrix, class Scalar>
void activateBackward(Matrix& delta, const Matrix& h, Activation activation, Scalar slope) {
  if (activation == Activation::Relu) delta = (h.array() > Scalar(0)).select(delta, Scalar(0));
  else delta = (h.array() > Scalar(0)).select(delta, slope * delta);
}

}  // namespace

template <class Scalar>
void Mlp<Scalar>::initialise(core::Rng& rng) {
  const auto fill = [&](Scalar* data, Eigen::Index size, int fan_in) {
    const double k = 1.0 / std::sqrt(static_cast<double>(fan_in));
    for (Eigen::Index i = 0; i < size; ++i) data[i] = static_cast<Scalar>(k * (2.0 * rng.uniform01() - 1.0));
  };
  fill(p_.w1.data(), p_.w1.size(), p_.inputs());
  fill(p_.b1.data(), p_.b1.size(), p_.inputs());
  fill(p_.w2.data(), p_.w2.size(), p_.hidden());
  fill(p_.b2.data(), p_.b2.size(), p_.hidden());
  fill(p_.w3.data(), p_.w3.size(), p_.hidden());
  fill(p_.b3.data(), p_.b3.size(), p_.hidden());
}

template <class Scalar>
const typename Mlp<Scalar>::Matrix& Mlp<Scalar>::forward(const Matrix& x) {
  h1_.noalias() = p_.w1 * x;
  h1_.colwise() += p_.b1;
  activate(h1_, activation_, slope_);
  h2_.noalias() = p_.w2 * h1_;
  h2_.colwise() += p_.b2;
  activate(h2_, activation_, slope_);
  y_.noalias() = p_.w3 * h2_;
  y_.colwise() += p_.b3;
  return y_;
}

template <class Scalar>
double Mlp<Scalar>::backward(const Matrix& x, const Matrix& target, Parameters& grad) {
  const Scalar batch = static_cast<Scalar>(x.cols());
  const Matrix error = y_ - target;
  double loss = 0.0;
  for (Eigen::Index i = 0; i < error.size(); ++i) loss += static_cast<double>(error.data()[i]) * error.data()[i];
  loss /= static_cast<double>(x.cols());

  // dL/dy = 2 (y - t) / B; through each layer: dW = delta a^T, db = row sums of delta,
  // delta_below = (W^T delta) through the activation's derivative (relu: 1 where h > 0, else
  // 0; leaky_relu: 1 where h > 0, else the slope).
  const Matrix dy = (Scalar(2) / batch) * error;
  grad.w3.noalias() = dy * h2_.transpose();
  grad.b3 = dy.rowwise().sum();
  Matrix d2 = p_.w3.transpose() * dy;
  activateBackward(d2, h2_, activation_, slope_);
  grad.w2.noalias() = d2 * h1_.transpose();
  grad.b2 = d2.rowwise().sum();
  Matrix d1 = p_.w2.transpose() * d2;
  activateBackward(d1, h1_, activation_, slope_);
  grad.w1.noalias() = d1 * x.transpose();
  grad.b1 = d1.rowwise().sum();
  return loss;
}

template <class Scalar>
double Mlp<Scalar>::lossAndGradient(const Matrix& x, const Matrix& target, Parameters& grad) {
  forward(x);
  return backward(x, target, grad);
}

template <class Scalar>
double Mlp<Scalar>::loss(const Matrix& x, const Matrix& target) {
  const Matrix& y = forward(x);
  double sum = 0.0;
  for (Eigen::Index i = 0; i < y.size(); ++i) {
    const double e = static_cast<double>(y.data()[i]) - static_cast<double>(target.data()[i]);
    sum += e * e;
  }
  return sum / static_cast<double>(x.cols());
}

template <class Scalar>
Adam<Scalar>::Adam(const MlpParameters<Scalar>& shape, double learning_rate)
    : m_(MlpParameters<Scalar>::zeros(shape.inputs(), shape.hidden(), shape.outputs())),
      v_(MlpParameters<Scalar>::zeros(shape.inputs(), shape.hidden(), shape.outputs())),
      learning_rate_(learning_rate) {}

template <class Scalar>
void Adam<Scalar>::step(MlpParameters<Scalar>& params, MlpParameters<Scalar>& grad) {
  constexpr double kBeta1 = 0.9, kBeta2 = 0.999, kEpsilon = 1e-8;
  ++t_;
  const double t = static_cast<double>(t_);
  // Bias corrections folded into the step size and epsilon (as PyTorch does):
  // p -= lr / (1 - b1^t) * m / (sqrt(v) / sqrt(1 - b2^t) + eps).
  const Scalar step_size = static_cast<Scalar>(learning_rate_ / (1.0 - std::pow(kBeta1, t)));
  const Scalar root_correction = static_cast<Scalar>(1.0 / std::sqrt(1.0 - std::pow(kBeta2, t)));
  const Scalar b1 = static_cast<Scalar>(kBeta1), b2 = static_cast<Scalar>(kBeta2);
  const Scalar eps = static_cast<Scalar>(kEpsilon);
  // Walk the six blocks of params, grad, m and v together.
  Scalar* p_blocks[6];
  Scalar* g_blocks[6];
  Scalar* m_blocks[6];
  Scalar* v_blocks[6];
  Eigen::Index sizes[6];
  int n = 0;
  params.forEachBlock([&](const char*, Scalar* data, Eigen::Index size) { p_blocks[n] = data; sizes[n++] = size; });
  n = 0;
  grad.forEachBlock([&](const char*, Scalar* data, Eigen::Index) { g_blocks[n++] = data; });
  n = 0;
  m_.forEachBlock([&](const char*, Scalar* data, Eigen::Index) { m_blocks[n++] = data; });
  n = 0;
  v_.forEachBlock([&](const char*, Scalar* data, Eigen::Index) { v_blocks[n++] = data; });
  for (int b = 0; b < 6; ++b) {
    using Array = Eigen::Array<Scalar, Eigen::Dynamic, 1>;
    Eigen::Map<Array> p(p_blocks[b], sizes[b]), g(g_blocks[b], sizes[b]), m(m_blocks[b], sizes[b]), v(v_blocks[b], sizes[b]);
    m = b1 * m + (Scalar(1) - b1) * g;
    v = b2 * v + (Scalar(1) - b2) * g.square();
    p -= step_size * m / (v.sqrt() * root_correction + eps);
  }
}

template struct MlpParameters<float>;
template struct MlpParameters<double>;
template class Mlp<float>;
template class Mlp<double>;
template class Adam<float>;
template class Adam<double>;

}  // namespace barn::learning
