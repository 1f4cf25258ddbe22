#pragma once
// Element-wise activations with PyTorch's definitions, on Eigen arrays/vectors.

#include <Eigen/Core>
#include <cmath>
#include <cstddef>

#include "gesture/nn/batch.h"
#include "gesture/nn/lanewise_math.h"

namespace deixis::nn {

// ELU with α = 1: x for x > 0, e^x − 1 otherwise (torch.nn.ELU uses expm1). The lane-wise expm1
// (lanewise_math.h) is a few multiply-adds the compiler vectorises, where the C library's ran one
// value at a time (8 % of a 64-person tick), and gives a value the same bits wherever it sits.
inline float elu(float v) noexcept {
  const float negative = lanewise::expm1(v);
  return v > 0.0f ? v : negative;
}

// Over `count` contiguous values, in a loop compiled to vector code (activations.cpp; the
// compile flag that allows it is explained in gesture/CMakeLists.txt): 16-float vectors where the
// CPU has AVX-512, the build's otherwise, the same bits either way. With a kernel: the products'
// choice (batch.h); it must be available.
void elu_inplace(float* x, std::size_t count) noexcept;
void elu_inplace(ProductKernel kernel, float* x, std::size_t count) noexcept;

template <typename Derived>
void elu_inplace(Eigen::MatrixBase<Derived>& x) {
  if constexpr ((Derived::Flags & Eigen::DirectAccessBit) != 0) {
    if (x.innerStride() == 1 && (x.outerSize() == 1 || x.outerStride() == x.innerSize())) {
      elu_inplace(x.derived().data(), static_cast<std::size_t>(x.size()));
      return;
    }
  }
  x = x.unaryExpr([](float v) { return elu(v); });
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
