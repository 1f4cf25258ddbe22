#pragma once
// torch.nn.Linear with fixed sizes: weight [out, in] row-major, y = W·x + b.

#include <string>

#include "gesture/nn/panel_order.h"
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

  // The same as run(), visiting the weights in fixed blocks of output rows, last block first when
  // `reverse` is set (for layers larger than the L2 cache; see panel_order.h).
  template <typename InputVector>
  Eigen::Matrix<float, Out, 1> run_in_panels(const InputVector& x, bool reverse) const {
    constexpr int kPanel = panel_width(Out);
    constexpr int kPanels = Out / kPanel;
    Eigen::Matrix<float, Out, 1> y;
    for (int k = 0; k < kPanels; ++k) {
      const int p = reverse ? kPanels - 1 - k : k;
      y.template segment<kPanel>(p * kPanel).noalias() =
          weight.view().template middleRows<kPanel>(p * kPanel) * x;
    }
    y += bias.view();
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
