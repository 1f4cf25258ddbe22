#pragma once
// One layer of the authors' mixture of experts (model.py: w_l1 [experts, in, out], b_l1
// [experts, out]): y = x·(Σ_e ω_e W_e) + Σ_e ω_e b_e. The weights are stored [e, in, out] and
// multiply from the right (x·W), unlike nn.Linear.
//
// We blend the experts' *outputs* instead of their weights: Σ_e ω_e (x·W_e + b_e) is the same
// value (Σ ω = 1 is not even needed: both are linear in ω), costs one pass over the weights
// instead of two, and needs no per-call weight buffer. To make that one pass a single long
// matrix-vector product, load() re-lays the weights out as [in, e·out].

#include <string>

#include "gesture/nn/params.h"

namespace deixis::nn {

template <int Experts, int In, int Out>
struct ExpertLayer {
  MatrixParam<In, Experts * Out> weight;  // row i: input i's weights for every expert's outputs
  MatrixParam<Out, Experts> bias;         // column e: expert e's bias (stored col-major below)

  void load(const SafetensorsFile& file, const std::string& weight_name,
            const std::string& bias_name) {
    AlignedFloats stacked(static_cast<std::size_t>(Experts) * In * Out);
    const std::int64_t weight_shape[] = {Experts, In, Out};
    file.copy_f32(weight_name, weight_shape, stacked);
    auto dst = weight.storage();
    for (int e = 0; e < Experts; ++e) {
      for (int i = 0; i < In; ++i) {
        for (int o = 0; o < Out; ++o) {
          dst[static_cast<std::size_t>(i) * Experts * Out + e * Out + o] =
              stacked[(static_cast<std::size_t>(e) * In + i) * Out + o];
        }
      }
    }
    // b [e, out] row-major is exactly an Out × Experts column-major matrix; MatrixParam stores
    // row-major, so transpose while copying.
    AlignedFloats b(static_cast<std::size_t>(Experts) * Out);
    const std::int64_t bias_shape[] = {Experts, Out};
    file.copy_f32(bias_name, bias_shape, b);
    auto bias_dst = bias.storage();
    for (int e = 0; e < Experts; ++e) {
      for (int o = 0; o < Out; ++o) {
        bias_dst[static_cast<std::size_t>(o) * Experts + e] = b[static_cast<std::size_t>(e) * Out + o];
      }
    }
  }

  template <typename InputVector, typename OmegaVector>
  Eigen::Matrix<float, Out, 1> run(const InputVector& x, const OmegaVector& omega) const {
    Eigen::Matrix<float, Experts * Out, 1> all;
    all.noalias() = weight.view().transpose() * x;
    const Eigen::Map<const Eigen::Matrix<float, Out, Experts>> per_expert(all.data());
    Eigen::Matrix<float, Out, 1> y;
    y.noalias() = per_expert * omega;
    y.noalias() += bias.view() * omega;
    return y;
  }
};

}  // namespace deixis::nn
