// The fused expert layers (train/fused_experts.h) are the libtorch composition they
// replace: same outputs and the same gradients for the input, the gating weights and every
// weight and bias, at MPNet's and UGNet's sizes, with inputs on both sides of the ELU's kink.

#include "train/fused_experts.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

namespace deixis::train {
namespace {

double max_abs(const torch::Tensor& a, const torch::Tensor& b) {
  return (a - b).abs().max().item<double>();
}

// The authors' definition written with libtorch operations: per layer x·(Σ_e ω_e W_e) +
// Σ_e ω_e b_e with the blended weight formed per sample, ELU between layers.
torch::Tensor reference_layers(torch::Tensor x, const torch::Tensor& omega,
                               const std::array<torch::Tensor, 3>& w,
                               const std::array<torch::Tensor, 3>& b) {
  for (int l = 0; l < 3; ++l) {
    const torch::Tensor blended_w = torch::einsum("be,eio->bio", {omega, w[l]});
    x = torch::bmm(x.unsqueeze(1), blended_w).squeeze(1) + torch::matmul(omega, b[l]);
    if (l < 2) {
      x = torch::elu(x);
    }
  }
  return x;
}

void expect_same_as_composition(int batch, int in, int hidden, int out) {
  constexpr int kExperts = 9;
  torch::manual_seed(11);
  const std::array<std::int64_t, 4> sizes = {in, hidden, hidden, out};
  std::array<torch::Tensor, 3> w, b, w_ref, b_ref;
  for (std::size_t l = 0; l < 3; ++l) {
    const double scale = 1.5 / std::sqrt(static_cast<double>(sizes[l]));
    w[l] = (torch::randn({kExperts, sizes[l], sizes[l + 1]}) * scale).requires_grad_(true);
    b[l] = (torch::randn({kExperts, sizes[l + 1]}) * 0.3).requires_grad_(true);
    w_ref[l] = w[l].detach().clone().requires_grad_(true);
    b_ref[l] = b[l].detach().clone().requires_grad_(true);
  }
  const torch::Tensor x = torch::randn({batch, in});
  const torch::Tensor logits = torch::randn({batch, kExperts});
  const torch::Tensor x_fused = x.clone().requires_grad_(true);
  const torch::Tensor x_ref = x.clone().requires_grad_(true);
  const torch::Tensor omega_fused = logits.clone().requires_grad_(true);
  const torch::Tensor omega_ref = logits.clone().requires_grad_(true);

  const torch::Tensor y_fused = expert_layers(x_fused, torch::softmax(omega_fused, 1), w, b);
  const torch::Tensor y_ref = reference_layers(x_ref, torch::softmax(omega_ref, 1), w_ref, b_ref);
  ASSERT_EQ(y_fused.sizes(), y_ref.sizes());
  EXPECT_LT(max_abs(y_fused, y_ref), 1e-5);
  // The hidden pre-activations straddle 0, so both branches of the ELU are exercised.
  EXPECT_GT(y_ref.abs().max().item<double>(), 0.1);

  const torch::Tensor weights = torch::rand({batch, out});
  (y_fused * weights).sum().backward();
  (y_ref * weights).sum().backward();
  EXPECT_LT(max_abs(x_fused.grad(), x_ref.grad()), 1e-5);
  EXPECT_LT(max_abs(omega_fused.grad(), omega_ref.grad()), 1e-5);
  EXPECT_GT(omega_ref.grad().abs().max().item<double>(), 1e-4);
  for (std::size_t l = 0; l < 3; ++l) {
    EXPECT_LT(max_abs(w[l].grad(), w_ref[l].grad()), 1e-4) << "layer " << l + 1;
    EXPECT_LT(max_abs(b[l].grad(), b_ref[l].grad()), 1e-4) << "layer " << l + 1;
    EXPECT_GT(w_ref[l].grad().abs().max().item<double>(), 1e-3) << "layer " << l + 1;
  }
}

TEST(FusedExperts, MpnetSizesMatchTheComposition) {
  expect_same_as_composition(16, 24, 12, 3);
}

TEST(FusedExperts, UgnetSizesMatchTheComposition) {
  expect_same_as_composition(32, 264, 144, 24);
}

// Training feeds data that needs no gradient: the input gradient is then not computed, and the
// rest is unchanged.
TEST(FusedExperts, NoInputGradientWhenTheInputNeedsNone) {
  torch::manual_seed(5);
  std::array<torch::Tensor, 3> w = {torch::randn({9, 6, 4}).requires_grad_(true),
                                    torch::randn({9, 4, 4}).requires_grad_(true),
                                    torch::randn({9, 4, 2}).requires_grad_(true)};
  std::array<torch::Tensor, 3> b = {torch::zeros({9, 4}).requires_grad_(true),
                                    torch::zeros({9, 4}).requires_grad_(true),
                                    torch::zeros({9, 2}).requires_grad_(true)};
  const torch::Tensor omega = torch::softmax(torch::randn({3, 9}), 1);
  expert_layers(torch::randn({3, 6}), omega, w, b).sum().backward();
  for (const torch::Tensor& t : w) {
    EXPECT_TRUE(t.grad().defined());
  }
}

}  // namespace
}  // namespace deixis::train
