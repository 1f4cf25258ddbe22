#pragma once
// Element-wise activations with PyTorch's definitions, on Eigen arrays/vectors.

#include <Eigen/Core>
#include <cmath>

namespace deixis::nn {

// ELU with α = 1: x for x > 0, exp(x) − 1 otherwise (torch.nn.ELU uses expm1). Element by
// element, so that expm1 (the C library's, one value at a time) runs only where it is used:
// an array select evaluates both sides everywhere, which made expm1 7 % of a 64-person tick.
template <typename Derived>
void elu_inplace(Eigen::MatrixBase<Derived>& x) {
  x = x.unaryExpr([](float v) { return v > 0.0f ? v : std::expm1(v); });
}

template <typename Derived>
void relu_inplace(Eigen::MatrixBase<Derived>& x) {
  x = x.cwiseMax(0.0f);
}

// SiLU (swish): x · σ(x) = x / (1 + e^−x). As an array expression Eigen evaluates the
// exponential eight lanes at a time; the diffusion UGNet takes 38,400 of them per call, which a
// scalar std::exp loop made a third of its time.
template <typename Derived>
void silu_inplace(Eigen::MatrixBase<Derived>& x) {
  x = (x.array() / (1.0f + (-x.array()).exp())).matrix();
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
