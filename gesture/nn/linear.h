#pragma once
// torch.nn.Linear with fixed sizes: weight [out, in] row-major, y = W·x + b.

#include <string>

#include "gesture/nn/params.h"

namespace deixis::nn {

template <int In, int Out>
struct Linear {
  MatrixParam<Out, In> weight;
  VectorParam<Out> bias;

  // `prefix` is the module name, e.g. "linear1" for "linear1.weight" and "linear1.bias".
  void load(const SafetensorsFile& file, const std::string& prefix) {
    load_matrix(file, prefix + ".weight", weight);
    load_vector(file, prefix + ".bias", bias);
  }

  template <typename InputVector>
  Eigen::Matrix<float, Out, 1> run(const InputVector& x) const {
    Eigen::Matrix<float, Out, 1> y = bias.view();
    y.noalias() += weight.view() * x;
    return y;
  }

  // Rows of `inputs` (Rows × In) mapped to rows of the result (Rows × Out).
  template <int Rows, typename InputMatrix>
  Eigen::Matrix<float, Rows, Out, (Out == 1 ? Eigen::ColMajor : Eigen::RowMajor)> run_rows(
      const InputMatrix& inputs) const {
    Eigen::Matrix<float, Rows, Out, (Out == 1 ? Eigen::ColMajor : Eigen::RowMajor)> y;
    y.noalias() = inputs * weight.view().transpose();
    y.rowwise() += bias.view().transpose();
    return y;
  }
};

}  // namespace deixis::nn
