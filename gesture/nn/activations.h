#pragma once
// Element-wise activations with PyTorch's definitions, on Eigen arrays/vectors.

#include <Eigen/Core>
#include <cmath>

namespace deixis::nn {

// ELU with α = 1: x for x > 0, exp(x) − 1 otherwise (torch.nn.ELU uses expm1).
template <typename Derived>
void elu_inplace(Eigen::MatrixBase<Derived>& x) {
  x = (x.array() > 0.0f).select(x.array(), x.array().expm1()).matrix();
}

template <typename Derived>
void relu_inplace(Eigen::MatrixBase<Derived>& x) {
  x = x.cwiseMax(0.0f);
}

// SiLU (swish): x · σ(x).
template <typename Derived>
void silu_inplace(Eigen::MatrixBase<Derived>& x) {
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const float v = x(i);
    x(i) = v / (1.0f + std::exp(-v));
  }
}

inline float sigmoid(float v) {
  return 1.0f / (1.0f + std::exp(-v));
}

// Numerically stable softmax over a vector, in place.
template <typename Derived>
void softmax_inplace(Eigen::MatrixBase<Derived>& x) {
  const float max = x.maxCoeff();
  float sum = 0.0f;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    x(i) = std::exp(x(i) - max);
    sum += x(i);
  }
  x /= sum;
}

}  // namespace deixis::nn
