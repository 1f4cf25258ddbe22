// The fused GRU (train/fused_gru.h) is torch.nn.GRU: same outputs and the same gradients
// for the input and every parameter, on random data, one and two layers.

#include "train/fused_gru.h"

#include <gtest/gtest.h>
#include <torch/nn/modules/rnn.h>
#include <torch/torch.h>

namespace deixis::train {
namespace {

double max_abs(const torch::Tensor& a, const torch::Tensor& b) {
  return (a - b).abs().max().item<double>();
}

void expect_same_as_torch_gru(int input, int hidden, int layers) {
  torch::manual_seed(3);
  FusedGru fused(input, hidden, layers);
  torch::nn::GRU reference(
      torch::nn::GRUOptions(input, hidden).num_layers(layers).batch_first(true));
  {
    torch::NoGradGuard no_grad;
    for (const auto& p : reference->named_parameters()) {
      p.value().copy_(fused->named_parameters()[p.key()]);
    }
  }
  const torch::Tensor x = torch::randn({5, 30, input});
  const torch::Tensor x_fused = x.clone().requires_grad_(true);
  const torch::Tensor x_reference = x.clone().requires_grad_(true);
  const torch::Tensor out_fused = fused->forward(x_fused);
  const torch::Tensor out_reference = std::get<0>(reference->forward(x_reference));
  EXPECT_LT(max_abs(out_fused, out_reference), 1e-6);

  // A loss that reads every time step (layer stacking) and weighs the last one more (how the
  // networks use it).
  const torch::Tensor weights = torch::rand({5, 30, hidden});
  (out_fused * weights).sum().backward();
  (out_reference * weights).sum().backward();
  EXPECT_LT(max_abs(x_fused.grad(), x_reference.grad()), 1e-5);
  for (const auto& p : reference->named_parameters()) {
    const torch::Tensor& fused_grad = fused->named_parameters()[p.key()].grad();
    ASSERT_TRUE(fused_grad.defined()) << p.key();
    EXPECT_LT(max_abs(fused_grad, p.value().grad()), 1e-4) << p.key();
    EXPECT_GT(p.value().grad().abs().max().item<double>(), 1e-3) << p.key();
  }
}

TEST(FusedGru, OneLayerMatchesTorchGru) {
  expect_same_as_torch_gru(11, 24, 1);
}

TEST(FusedGru, TwoLayersMatchTorchGru) {
  expect_same_as_torch_gru(5, 9, 2);
}

// The parameters are registered under torch.nn.GRU's names, so checkpoints are interchangeable.
TEST(FusedGru, HasTorchGruParameterNames) {
  FusedGru fused(8, 9, 2);
  torch::nn::GRU reference(torch::nn::GRUOptions(8, 9).num_layers(2));
  std::vector<std::string> a, b;
  for (const auto& p : fused->named_parameters()) {
    a.push_back(p.key() + " " + c10::str(p.value().sizes()));
  }
  for (const auto& p : reference->named_parameters()) {
    b.push_back(p.key() + " " + c10::str(p.value().sizes()));
  }
  EXPECT_EQ(a, b);
}

}  // namespace
}  // namespace deixis::train
