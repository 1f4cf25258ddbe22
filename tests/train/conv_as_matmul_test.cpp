// The autoencoder's convolutions as matrix products (train/conv_as_matmul.h) are libtorch's
// conv1d and conv_transpose1d: same outputs and the same gradients for the input, the weight and
// the bias, at the FMD autoencoder's four layer shapes and at shapes with other sizes.

#include "train/conv_as_matmul.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

namespace deixis::train {
namespace {

// Largest difference relative to the reference's largest magnitude: the two formulations sum up
// to 4096 float products in different orders, so they differ by rounding (≈ 1e-7 relative per
// operation), while a misplaced index or transposed weight is wrong by order 1.
double relative_difference(const torch::Tensor& ours, const torch::Tensor& reference) {
  return (ours - reference).abs().max().item<double>() / reference.abs().max().item<double>();
}

struct Leaf {  // one tensor twice, so each formulation has its own gradient
  torch::Tensor ours, reference;
  explicit Leaf(const torch::Tensor& value)
      : ours(value.clone().requires_grad_(true)), reference(value.clone().requires_grad_(true)) {}
};

// y_ours is time-major [B, T, O]; y_reference is libtorch's channel-major [B, O, T].
void expect_same(const torch::Tensor& y_ours, const torch::Tensor& y_reference, Leaf& x,
                 Leaf& weight, Leaf& bias) {
  const torch::Tensor reference = y_reference.permute({0, 2, 1});
  ASSERT_EQ(y_ours.sizes(), reference.sizes());
  EXPECT_GT(reference.abs().max().item<double>(), 0.1);  // not a comparison of zeros
  EXPECT_LT(relative_difference(y_ours, reference), 1e-6);
  // A different weight per output element, so a misplaced gradient cannot cancel out.
  const torch::Tensor upstream = torch::randn(reference.sizes());
  (y_ours * upstream).sum().backward();
  (reference * upstream).sum().backward();
  EXPECT_LT(relative_difference(x.ours.grad(), x.reference.grad()), 1e-6);
  EXPECT_LT(relative_difference(weight.ours.grad(), weight.reference.grad()), 1e-6);
  EXPECT_LT(relative_difference(bias.ours.grad(), bias.reference.grad()), 1e-6);
}

void expect_conv1d_matches(int batch, int frames, int channels, int outputs, int kernel) {
  torch::manual_seed(3);
  Leaf x(torch::randn({batch, frames, channels}));
  Leaf weight(torch::randn({outputs, channels, kernel}) * 0.2);
  Leaf bias(torch::randn({outputs}));
  expect_same(conv1d_as_matmul(x.ours, weight.ours, bias.ours),
              torch::conv1d(x.reference.permute({0, 2, 1}), weight.reference, bias.reference), x,
              weight, bias);
}

void expect_conv_transpose1d_matches(int batch, int frames, int inputs, int outputs, int kernel) {
  torch::manual_seed(5);
  Leaf x(torch::randn({batch, frames, inputs}));
  Leaf weight(torch::randn({inputs, outputs, kernel}) * 0.2);
  Leaf bias(torch::randn({outputs}));
  expect_same(
      conv_transpose1d_as_matmul(x.ours, weight.ours, bias.ours),
      torch::conv_transpose1d(x.reference.permute({0, 2, 1}), weight.reference, bias.reference), x,
      weight, bias);
}

TEST(ConvAsMatmul, TheAutoencodersEncoderLayersAreConv1d) {
  expect_conv1d_matches(8, 30, 18, 256, 15);   // 30 → 16 frames
  expect_conv1d_matches(8, 16, 256, 128, 16);  // 16 → 1: the 128-d code
}

TEST(ConvAsMatmul, TheAutoencodersDecoderLayersAreConvTranspose1d) {
  expect_conv_transpose1d_matches(8, 1, 128, 256, 16);  // 1 → 16 frames, nothing overlaps
  expect_conv_transpose1d_matches(8, 16, 256, 18, 15);  // 16 → 30, overlap-add
}

TEST(ConvAsMatmul, OtherSizesToo) {
  expect_conv1d_matches(3, 11, 4, 5, 3);
  expect_conv1d_matches(1, 7, 2, 3, 7);
  expect_conv_transpose1d_matches(3, 5, 4, 6, 3);
  expect_conv_transpose1d_matches(2, 9, 3, 2, 1);
}

}  // namespace
}  // namespace deixis::train
