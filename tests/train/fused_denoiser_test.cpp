// The fused denoiser (train/fused_denoiser.h) is the libtorch composition of the UGNet
// Diffusion's NoiseDecoder: the same output and the same gradients for its three inputs and every
// parameter, at the UGNet's sizes and at odd ones, with and without gradients for the data.

#include "train/fused_denoiser.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cmath>

namespace deixis::train {
namespace {

namespace F = torch::nn::functional;

struct Sizes {
  std::int64_t batch, condition, pose, time, hidden, groups, blocks;
};

// Random weights, γ away from 1 and β and biases away from 0, so that no term of the backward
// pass hides behind a neutral value; all of them require gradients.
DenoiserWeights random_weights(const Sizes& s) {
  auto weight = [](std::int64_t out, std::int64_t in) {
    return (torch::randn({out, in}) / std::sqrt(static_cast<double>(in))).requires_grad_();
  };
  auto vector = [](std::int64_t n, double mean) {
    return (mean + 0.3 * torch::randn({n})).requires_grad_();
  };
  const std::int64_t fin_width = s.condition + s.pose + s.time;
  DenoiserWeights w;
  w.groups = s.groups;
  w.fin_weight = weight(s.hidden, fin_width);
  w.fin_bias = vector(s.hidden, 0.0);
  for (std::int64_t b = 0; b < s.blocks; ++b) {
    w.blocks.push_back({vector(s.hidden, 1.0), vector(s.hidden, 0.0),
                        weight(s.hidden, s.hidden + fin_width), vector(s.hidden, 0.0)});
  }
  w.fco_weight = weight(s.pose, s.hidden + fin_width);
  w.fco_bias = vector(s.pose, 0.0);
  return w;
}

// model.py NoiseDecoder.forward in libtorch's own operations.
torch::Tensor reference_denoise(const torch::Tensor& condition, const torch::Tensor& noisy,
                                const torch::Tensor& time, const DenoiserWeights& w) {
  torch::Tensor h = F::linear(torch::cat({condition, noisy, time}, -1), w.fin_weight, w.fin_bias);
  for (const DenoiserBlockWeights& block : w.blocks) {
    h = F::silu(F::group_norm(
        h, F::GroupNormFuncOptions(w.groups).weight(block.norm_weight).bias(block.norm_bias)));
    h = F::linear(torch::cat({h, noisy, condition, time}, -1), block.weight, block.bias);
  }
  return F::linear(torch::cat({h, noisy, condition, time}, -1), w.fco_weight, w.fco_bias);
}

std::vector<torch::Tensor> parameters(const DenoiserWeights& w) {
  std::vector<torch::Tensor> p{w.fin_weight, w.fin_bias};
  for (const DenoiserBlockWeights& b : w.blocks) {
    p.insert(p.end(), {b.norm_weight, b.norm_bias, b.weight, b.bias});
  }
  p.insert(p.end(), {w.fco_weight, w.fco_bias});
  return p;
}

// Largest difference relative to the reference's largest magnitude: the two formulations sum in
// different orders, so they differ by float rounding, while a wrong term is wrong by order 1.
double relative_difference(const torch::Tensor& ours, const torch::Tensor& reference) {
  return (ours - reference).abs().max().item<double>() / reference.abs().max().item<double>();
}

// The gradients of Σ weight ⊙ output with respect to the inputs (undefined where not required)
// and every parameter.
std::vector<torch::Tensor> gradients(const torch::Tensor& out, const torch::Tensor& weighting,
                                     const std::vector<torch::Tensor>& inputs,
                                     const DenoiserWeights& w) {
  std::vector<torch::Tensor> wrt;
  for (const torch::Tensor& t : inputs) {
    if (t.requires_grad()) {
      wrt.push_back(t);
    }
  }
  const std::vector<torch::Tensor> p = parameters(w);
  wrt.insert(wrt.end(), p.begin(), p.end());
  return torch::autograd::grad({(out * weighting).sum()}, wrt);
}

// Which of the three inputs require gradients (every parameter does).
struct Requires {
  bool condition, noisy, time;
};

void expect_matches_libtorch(const Sizes& s, Requires requires_grad) {
  torch::manual_seed(17);
  const DenoiserWeights w = random_weights(s);
  const torch::Tensor condition =
      torch::randn({s.batch, s.condition}).requires_grad_(requires_grad.condition);
  const torch::Tensor noisy = torch::randn({s.batch, s.pose}).requires_grad_(requires_grad.noisy);
  const torch::Tensor time = torch::randn({s.batch, s.time}).requires_grad_(requires_grad.time);
  const torch::Tensor weighting = torch::randn({s.batch, s.pose});

  const torch::Tensor ours = denoise(condition, noisy, time, w);
  const torch::Tensor reference = reference_denoise(condition, noisy, time, w);
  EXPECT_LT(relative_difference(ours, reference), 1e-5);

  const std::vector<torch::Tensor> inputs{condition, noisy, time};
  const std::vector<torch::Tensor> got = gradients(ours, weighting, inputs, w);
  const std::vector<torch::Tensor> expected = gradients(reference, weighting, inputs, w);
  ASSERT_EQ(got.size(), expected.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    ASSERT_TRUE(got[i].defined()) << "gradient " << i;
    EXPECT_LT(relative_difference(got[i], expected[i]), 1e-5) << "gradient " << i;
  }
}

// The UGNet Diffusion's denoiser: batch 32, condition 264, pose 24, step embedding 64, hidden 128,
// GroupNorm(16), 10 blocks.
constexpr Sizes kUgnetSizes{32, 264, 24, 64, 128, 16, 10};
// A batch of 5, groups of 4 channels, 2 blocks.
constexpr Sizes kOddSizes{5, 7, 3, 4, 12, 3, 2};

// In training the data need no gradient (only the step embedding has parameters before it); the
// node then computes the time columns' alone.
TEST(FusedDenoiser, MatchesLibtorchAtTheUgnetsSizes) {
  expect_matches_libtorch(kUgnetSizes, {false, false, true});
}

TEST(FusedDenoiser, MatchesLibtorchWithGradientsForTheData) {
  expect_matches_libtorch(kUgnetSizes, {true, true, true});
}

// Each input's gradient alone, and none: the node computes only the columns asked for.
TEST(FusedDenoiser, MatchesLibtorchForEverySubsetOfInputGradients) {
  for (const Requires r : {Requires{true, false, false}, Requires{false, true, false},
                           Requires{false, false, true}, Requires{false, false, false}}) {
    SCOPED_TRACE(::testing::Message()
                 << "condition " << r.condition << ", noisy " << r.noisy << ", time " << r.time);
    expect_matches_libtorch(kOddSizes, r);
  }
}

TEST(FusedDenoiser, NoBlocksIsFinThenFco) {
  expect_matches_libtorch({3, 5, 2, 4, 8, 2, 0}, {true, true, true});
}

TEST(FusedDenoiser, ShapesThatDoNotFitAreAnError) {
  DenoiserWeights w = random_weights({2, 3, 2, 2, 8, 2, 1});
  EXPECT_NO_THROW(denoise(torch::randn({2, 3}), torch::randn({2, 2}), torch::randn({2, 2}), w));
  EXPECT_THROW(denoise(torch::randn({2, 3}), torch::randn({3, 2}), torch::randn({2, 2}), w),
               c10::Error);  // batches differ
  EXPECT_THROW(denoise(torch::randn({2, 4}), torch::randn({2, 2}), torch::randn({2, 2}), w),
               c10::Error);  // fin is not that wide
  DenoiserWeights narrow_fco = w;
  narrow_fco.fco_weight = torch::randn({2, 10});
  EXPECT_THROW(
      denoise(torch::randn({2, 3}), torch::randn({2, 2}), torch::randn({2, 2}), narrow_fco),
      c10::Error);  // fco reads 8 + 7 columns
  w.groups = 3;     // does not divide the hidden width 8
  EXPECT_THROW(denoise(torch::randn({2, 3}), torch::randn({2, 2}), torch::randn({2, 2}), w),
               c10::Error);
}

}  // namespace
}  // namespace deixis::train
