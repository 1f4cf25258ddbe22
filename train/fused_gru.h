#pragma once
// A GRU layer stack for training, with the parameters and equations of torch.nn.GRU
// (batch_first; gate order r|z|n; b_hn inside the reset product) but one autograd node per layer
// instead of ~40 small tensor operations per time step.
//
// Why: the paper's GRUs are tiny (hidden 9 and 24) and the authors step the optimiser once per
// 30-row window, so libtorch's per-operation overhead (dispatch, autograd bookkeeping) dominates:
// torch::nn::GRU forward + backward costs ~5 ms per MPNet step on this machine, this ~0.2 ms.
// The forward and backward passes (backpropagation through time) are written out with Eigen on
// the raw buffers; tests/train/fused_gru_test.cpp checks values and gradients against
// torch::nn::GRU.
//
// Like the authors' networks (docs/conventions.md#grus) every call starts from a zero hidden state.

#include <torch/nn/module.h>
#include <torch/types.h>

namespace deixis::train {

class FusedGruImpl : public torch::nn::Module {
 public:
  FusedGruImpl(int input_size, int hidden_size, int layers);

  // x: [batch, time, input] → the last layer's outputs [batch, time, hidden].
  torch::Tensor forward(const torch::Tensor& x);

  int hidden_size() const { return hidden_; }

 private:
  int hidden_;
  std::vector<torch::Tensor> w_ih_, w_hh_, b_ih_, b_hh_;
};
TORCH_MODULE(FusedGru);

// One GRU layer over a whole sequence as a single differentiable function (exposed for tests).
torch::Tensor gru_layer(const torch::Tensor& x, const torch::Tensor& w_ih,
                        const torch::Tensor& w_hh, const torch::Tensor& b_ih,
                        const torch::Tensor& b_hh);

}  // namespace deixis::train
