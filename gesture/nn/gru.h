#pragma once
// One layer of a PyTorch nn.GRU with fixed sizes, run over a whole window.
//
// Gate order in the stacked weights is PyTorch's r | z | n, and b_hn sits *inside* the reset
// product (torch.nn.GRU, NOTES §3.2):
//   r = σ(W_ir x + b_ir + W_hr h + b_hr)      z = σ(W_iz x + b_iz + W_hz h + b_hz)
//   n = tanh(W_in x + b_in + r ⊙ (W_hn h + b_hn))      h' = (1 − z) ⊙ n + z ⊙ h
// The authors' GRUs are not stateful: every call starts from h = 0 and runs over all rows of the
// window (NOTES §3.2), so a layer has weights and no state.

#include <string>

#include "gesture/nn/activations.h"
#include "gesture/nn/params.h"

namespace deixis::nn {

template <int In, int Hidden>
struct GruLayer {
  static constexpr int kGates = 3 * Hidden;
  MatrixParam<kGates, In> weight_ih;
  MatrixParam<kGates, Hidden> weight_hh;
  VectorParam<kGates> bias_ih;
  VectorParam<kGates> bias_hh;

  // `prefix` is e.g. "gru" and `layer` 0 for "gru.weight_ih_l0".
  void load(const SafetensorsFile& file, const std::string& prefix, int layer) {
    const std::string l = "_l" + std::to_string(layer);
    load_matrix(file, prefix + ".weight_ih" + l, weight_ih);
    load_matrix(file, prefix + ".weight_hh" + l, weight_hh);
    load_vector(file, prefix + ".bias_ih" + l, bias_ih);
    load_vector(file, prefix + ".bias_hh" + l, bias_hh);
  }

  // Runs over `steps` rows of `inputs` (Steps × In, row-major; any Eigen expression) from h = 0.
  // Writes every step's hidden state to `outputs` (Steps × Hidden) and returns nothing else; the
  // last row is the layer's final output.
  template <int Steps, typename InputMatrix, typename OutputMatrix>
  void run(const InputMatrix& inputs, OutputMatrix& outputs) const {
    // Input projections of all steps at once: one matrix product instead of Steps small ones.
    Eigen::Matrix<float, Steps, kGates, Eigen::RowMajor> gi;
    gi.noalias() = inputs * weight_ih.view().transpose();
    gi.rowwise() += bias_ih.view().transpose();

    Eigen::Matrix<float, Hidden, 1> h = Eigen::Matrix<float, Hidden, 1>::Zero();
    Eigen::Matrix<float, kGates, 1> gh;
    for (int t = 0; t < Steps; ++t) {
      gh.noalias() = weight_hh.view() * h;
      gh += bias_hh.view();
      for (int k = 0; k < Hidden; ++k) {
        const float r = sigmoid(gi(t, k) + gh(k));
        const float z = sigmoid(gi(t, Hidden + k) + gh(Hidden + k));
        const float n = std::tanh(gi(t, 2 * Hidden + k) + r * gh(2 * Hidden + k));
        h(k) = (1.0f - z) * n + z * h(k);
      }
      outputs.row(t) = h.transpose();
    }
  }
};

}  // namespace deixis::nn
