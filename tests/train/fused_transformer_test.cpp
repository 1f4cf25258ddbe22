// The fused encoder layers (train/fused_transformer.h) are libtorch's TransformerEncoder:
// same outputs and the same gradients for the tokens and every parameter, without dropout (p = 0
// in training mode, and eval mode), at the MPNet Transformer's sizes and at other ones. With
// dropout they are the libtorch composition of the layer with the same masks, the masks drop
// their rate, the training generator alone decides them, and over many draws the outputs are
// distributed as libtorch's encoder's with its own dropout.

#include "train/fused_transformer.h"

#include <ATen/CPUGeneratorImpl.h>
#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cmath>
#include <map>

#include "gesture/nn/shapes.h"
#include "train/models.h"

namespace deixis::train {
namespace {

// Largest difference relative to the reference's largest magnitude: the two formulations sum in
// different orders, so they differ by float rounding, while a wrong term is wrong by order 1.
double relative_difference(const torch::Tensor& ours, const torch::Tensor& reference) {
  return (ours - reference).abs().max().item<double>() / reference.abs().max().item<double>();
}

struct Sizes {
  int time, batch, d, heads, ff, layers;
};

torch::nn::TransformerEncoder make_encoder(const Sizes& s, double dropout) {
  return torch::nn::TransformerEncoder(
      torch::nn::TransformerEncoderOptions(torch::nn::TransformerEncoderLayerOptions(s.d, s.heads)
                                               .dim_feedforward(s.ff)
                                               .dropout(dropout),
                                           s.layers));
}

// Random values in every parameter (γ away from 1, β and biases away from 0), so that no term of
// the backward pass hides behind a neutral value.
void randomise(torch::nn::Module& module) {
  torch::NoGradGuard no_grad;
  for (auto& p : module.named_parameters()) {
    torch::Tensor t = p.value();
    if (p.key().find("norm") != std::string::npos && p.key().ends_with("weight")) {
      t.copy_(1.0 + 0.3 * torch::randn(t.sizes()));
    } else if (t.dim() == 1) {
      t.copy_(0.3 * torch::randn(t.sizes()));
    } else {
      t.copy_(torch::randn(t.sizes()) / std::sqrt(static_cast<double>(t.size(1))));
    }
  }
}

// A randomised encoder with dropout 0.1 and tokens to run it on, both drawn after seeding torch.
struct DropoutCase {
  torch::nn::TransformerEncoder encoder{nullptr};
  torch::Tensor tokens;
};

DropoutCase dropout_case(const Sizes& s, std::uint64_t seed) {
  torch::manual_seed(seed);
  DropoutCase c{make_encoder(s, 0.1), {}};
  randomise(*c.encoder);
  c.tokens = torch::randn({s.time, s.batch, s.d});
  return c;
}

void copy_parameters(torch::nn::Module& from, torch::nn::Module& to) {
  torch::NoGradGuard no_grad;
  auto source = from.named_parameters();
  for (auto& p : to.named_parameters()) {
    p.value().copy_(source[p.key()]);
  }
}

// Compares the outputs and, for the same upstream gradient, the tokens' and every parameter's
// gradient of two modules with the same parameters.
void expect_same(const torch::Tensor& ours, const torch::Tensor& reference,
                 const torch::Tensor& tokens_ours, const torch::Tensor& tokens_reference,
                 torch::nn::Module& module_ours, torch::nn::Module& module_reference) {
  ASSERT_EQ(ours.sizes(), reference.sizes());
  EXPECT_LT(relative_difference(ours, reference), 1e-5);
  const torch::Tensor upstream = torch::randn(reference.sizes());
  (ours * upstream).sum().backward();
  (reference * upstream).sum().backward();
  EXPECT_LT(relative_difference(tokens_ours.grad(), tokens_reference.grad()), 1e-5);
  auto reference_parameters = module_reference.named_parameters();
  for (auto& p : module_ours.named_parameters()) {
    const torch::Tensor& g = reference_parameters[p.key()].grad();
    ASSERT_TRUE(p.value().grad().defined()) << p.key();
    EXPECT_GT(g.abs().max().item<double>(), 1e-6) << p.key();
    EXPECT_LT(relative_difference(p.value().grad(), g), 1e-5) << p.key();
  }
}

// The whole encoder's last token, in training mode without dropout or in eval mode.
void expect_encoder_matches(const Sizes& s, double dropout, bool training) {
  torch::manual_seed(17);
  torch::nn::TransformerEncoder reference = make_encoder(s, dropout);
  torch::nn::TransformerEncoder ours = make_encoder(s, dropout);
  randomise(*reference);
  copy_parameters(*reference, *ours);
  reference->train(training);
  ours->train(training);
  const torch::Tensor tokens = 2.0 * torch::randn({s.time, s.batch, s.d});
  const torch::Tensor tokens_ours = tokens.clone().requires_grad_(true);
  const torch::Tensor tokens_reference = tokens.clone().requires_grad_(true);
  const torch::Tensor y_ours =
      encoder_last_token(ours, tokens_ours, at::detail::createCPUGenerator(1));
  const torch::Tensor y_reference = reference->forward(tokens_reference).select(0, -1);
  expect_same(y_ours, y_reference, tokens_ours, tokens_reference, *ours, *reference);
}

TEST(FusedTransformer, MpnetEncoderMatchesLibtorchWithoutDropout) {
  expect_encoder_matches({30, 16, 16, 4, 16, 4}, 0.0, true);
}

// The UGNet Transformer's encoder (30 condition tokens and the pose token, d 160, 4 heads,
// feed-forward 160, 4 layers), which trains through the fused layers too; a small batch.
TEST(FusedTransformer, UgnetEncoderMatchesLibtorchWithoutDropout) {
  expect_encoder_matches({31, 3, 160, 4, 160, 4}, 0.0, true);
}

// deixis-train's UGNet Transformer (now through the fused layers) drops out in training only: its
// masks come from the default generator (the trainer seeds it per batch), so one seed gives one
// output and another seed another; in eval mode there is no dropout and the seed is irrelevant.
TEST(FusedTransformer, UgnetTransformerDropsOutInTrainingOnly) {
  torch::manual_seed(5);
  const std::shared_ptr<TrainableNetwork> net = make_network(Network::kUgnetTransformer);
  const torch::Tensor window = torch::randn({4, nn::kWindowRows, nn::kUgnetColumns});
  const auto forward_with_seed = [&](std::uint64_t seed) {
    torch::manual_seed(seed);
    return net->forward(window).detach();
  };
  net->train();
  const torch::Tensor a = forward_with_seed(1);
  EXPECT_TRUE(torch::equal(a, forward_with_seed(1)));
  EXPECT_GT((a - forward_with_seed(2)).abs().max().item<double>(), 1e-3);
  net->eval();
  torch::NoGradGuard no_grad;
  const torch::Tensor e = forward_with_seed(1);
  EXPECT_TRUE(torch::equal(e, forward_with_seed(2)));
  EXPECT_GT((a - e).abs().max().item<double>(), 1e-3);
}

TEST(FusedTransformer, OtherSizesMatchLibtorchWithoutDropout) {
  expect_encoder_matches({7, 3, 12, 3, 20, 2}, 0.0, true);
  expect_encoder_matches({5, 2, 8, 1, 6, 1}, 0.0, true);
}

TEST(FusedTransformer, EvalModeMatchesLibtorch) {
  expect_encoder_matches({30, 16, 16, 4, 16, 4}, 0.1, false);
}

EncoderLayerWeights weights_of(torch::nn::TransformerEncoderLayerImpl& layer) {
  return {layer.self_attn->in_proj_weight,
          layer.self_attn->in_proj_bias,
          layer.self_attn->out_proj->weight,
          layer.self_attn->out_proj->bias,
          layer.linear1->weight,
          layer.linear1->bias,
          layer.linear2->weight,
          layer.linear2->bias,
          layer.norm1->weight,
          layer.norm1->bias,
          layer.norm2->weight,
          layer.norm2->bias,
          layer.options.nhead()};
}

torch::nn::TransformerEncoderLayer make_layer(const Sizes& s) {
  return torch::nn::TransformerEncoderLayer(
      torch::nn::TransformerEncoderLayerOptions(s.d, s.heads).dim_feedforward(s.ff).dropout(0.0));
}

// The post-norm layer written with libtorch operations and explicit dropout masks, applied to
// the query tokens from first_query on (the masks cover only those; the other tokens only
// provide keys and values).
torch::Tensor reference_layer(const torch::Tensor& x, const EncoderLayerWeights& w,
                              const torch::Tensor& masks, std::int64_t first_query) {
  const std::int64_t time = x.size(0), batch = x.size(1), d = x.size(2), heads = w.heads;
  const std::int64_t head_dim = d / heads, ff = w.linear1_weight.size(0);
  const std::int64_t queries = time - first_query;
  const std::int64_t attention = batch * heads * queries * time, rows = queries * batch;
  const torch::Tensor m_attention =
      masks.slice(0, 0, attention).view({queries, time, heads, batch}).permute({3, 2, 0, 1});
  const torch::Tensor m_out =
      masks.slice(0, attention, attention + rows * d).view({queries, batch, d});
  const torch::Tensor m_hidden =
      masks.slice(0, attention + rows * d, attention + rows * (d + ff)).view({queries, batch, ff});
  const torch::Tensor m_ff = masks.slice(0, attention + rows * (d + ff)).view({queries, batch, d});

  const torch::Tensor qkv = torch::nn::functional::linear(x, w.in_proj_weight, w.in_proj_bias);
  auto heads_of = [&](const torch::Tensor& t) {  // [t, batch, d] → [batch, heads, t, head_dim]
    return t.reshape({t.size(0), batch, heads, head_dim}).permute({1, 2, 0, 3});
  };
  const torch::Tensor q = heads_of(qkv.slice(2, 0, d).slice(0, first_query));
  const torch::Tensor k = heads_of(qkv.slice(2, d, 2 * d));
  const torch::Tensor v = heads_of(qkv.slice(2, 2 * d, 3 * d));
  const torch::Tensor p =
      torch::softmax(torch::matmul(q, k.transpose(2, 3)) / std::sqrt(double(head_dim)), -1);
  const torch::Tensor a =
      torch::matmul(p * m_attention, v).permute({2, 0, 1, 3}).reshape({queries, batch, d});
  const torch::Tensor o = torch::nn::functional::linear(a, w.out_proj_weight, w.out_proj_bias);
  const torch::Tensor n1 = torch::layer_norm(x.slice(0, first_query) + o * m_out, {d},
                                             w.norm1_weight, w.norm1_bias, 1e-5);
  const torch::Tensor h =
      torch::relu(torch::nn::functional::linear(n1, w.linear1_weight, w.linear1_bias)) * m_hidden;
  const torch::Tensor f = torch::nn::functional::linear(h, w.linear2_weight, w.linear2_bias);
  return torch::layer_norm(n1 + f * m_ff, {d}, w.norm2_weight, w.norm2_bias, 1e-5);
}

// One layer with dropout against the composition with the same masks, every token's output or
// the last one's.
void expect_layer_with_masks_matches(const Sizes& s, bool last_only) {
  torch::manual_seed(23);
  torch::nn::TransformerEncoderLayer reference = make_layer(s);
  torch::nn::TransformerEncoderLayer ours = make_layer(s);
  randomise(*reference);
  copy_parameters(*reference, *ours);
  const std::int64_t first_query = last_only ? s.time - 1 : 0;
  const std::int64_t queries = s.time - first_query;
  const std::int64_t count =
      s.batch * s.heads * queries * s.time + queries * s.batch * (2 * s.d + s.ff);
  EncoderLayerOptions options;
  options.dropout = 0.25;
  options.seed = 0x5eed;
  options.last_only = last_only;
  const torch::Tensor masks = dropout_masks(count, options.seed, options.dropout);
  ASSERT_GT((masks == 0).sum().item<int>(), 0);  // some elements are dropped

  const torch::Tensor tokens = 2.0 * torch::randn({s.time, s.batch, s.d});
  const torch::Tensor tokens_ours = tokens.clone().requires_grad_(true);
  const torch::Tensor tokens_reference = tokens.clone().requires_grad_(true);
  torch::Tensor y_ours = encoder_layer(tokens_ours, weights_of(*ours), options);
  torch::Tensor y_reference =
      reference_layer(tokens_reference, weights_of(*reference), masks, first_query);
  if (last_only) {
    y_reference = y_reference.select(0, 0);
  }
  expect_same(y_ours, y_reference, tokens_ours, tokens_reference, *ours, *reference);
}

TEST(FusedTransformer, LayerWithDropoutIsTheCompositionWithItsMasks) {
  expect_layer_with_masks_matches({30, 16, 16, 4, 16, 1}, false);
  expect_layer_with_masks_matches({30, 16, 16, 4, 16, 1}, true);
  expect_layer_with_masks_matches({6, 3, 12, 3, 20, 1}, false);
}

// Without dropout the layer is libtorch's TransformerEncoderLayer for every token.
TEST(FusedTransformer, LayerMatchesLibtorchForEveryToken) {
  const Sizes s{9, 4, 16, 4, 24, 1};
  torch::manual_seed(29);
  torch::nn::TransformerEncoderLayer reference = make_layer(s);
  torch::nn::TransformerEncoderLayer ours = make_layer(s);
  randomise(*reference);
  copy_parameters(*reference, *ours);
  const torch::Tensor tokens = 2.0 * torch::randn({s.time, s.batch, s.d});
  const torch::Tensor tokens_ours = tokens.clone().requires_grad_(true);
  const torch::Tensor tokens_reference = tokens.clone().requires_grad_(true);
  expect_same(encoder_layer(tokens_ours, weights_of(*ours), {}),
              reference->forward(tokens_reference), tokens_ours, tokens_reference, *ours,
              *reference);
}

// The masks drop their rate: within 6 standard deviations of the binomial count, at the MPNet
// attention mask's size; two keys give independent masks (both drop ≈ p²).
TEST(FusedTransformer, DropoutMasksDropTheirRate) {
  constexpr double kP = 0.1;
  constexpr std::int64_t kCount = 16 * 4 * 30 * 30;
  const torch::Tensor a = dropout_masks(kCount, 1234, kP);
  const torch::Tensor b = dropout_masks(kCount, 1235, kP);
  auto expect_rate = [&](const torch::Tensor& dropped, double p) {
    const double sd = std::sqrt(p * (1 - p) / kCount);
    EXPECT_NEAR(dropped.to(torch::kDouble).mean().item<double>(), p, 6 * sd);
  };
  expect_rate(a == 0, kP);
  expect_rate(b == 0, kP);
  expect_rate((a == 0).logical_and(b == 0), kP * kP);
  const torch::Tensor kept = a.masked_select(a != 0);
  EXPECT_EQ(kept.min().item<float>(), static_cast<float>(1 / (1 - kP)));
  EXPECT_EQ(kept.max().item<float>(), static_cast<float>(1 / (1 - kP)));
  // Every key draws another mask, and the same key the same one.
  EXPECT_TRUE(torch::equal(a, dropout_masks(kCount, 1234, kP)));
  EXPECT_FALSE(torch::equal(a, b));
}

// In training the generator decides the masks: the same seed gives the same output, another
// seed another, and both differ from eval mode's; in the model, dropped elements are ≈ p.
TEST(FusedTransformer, TrainingDropoutFollowsTheGenerator) {
  const Sizes s{30, 16, 16, 4, 16, 4};
  auto [encoder, tokens] = dropout_case(s, 31);
  torch::NoGradGuard no_grad;
  const torch::Tensor first =
      encoder_last_token(encoder, tokens, at::detail::createCPUGenerator(7));
  const torch::Tensor again =
      encoder_last_token(encoder, tokens, at::detail::createCPUGenerator(7));
  const torch::Tensor other =
      encoder_last_token(encoder, tokens, at::detail::createCPUGenerator(8));
  encoder->eval();
  const torch::Tensor eval = encoder_last_token(encoder, tokens, at::detail::createCPUGenerator(7));
  EXPECT_TRUE(torch::equal(first, again));
  EXPECT_GT((first - other).abs().max().item<double>(), 1e-3);
  EXPECT_GT((first - eval).abs().max().item<double>(), 1e-3);
}

// Dropout as libtorch's in distribution: over many draws the mean output of the fused encoder
// and of libtorch's (its own masks from torch's RNG) agree within 5 standard errors of their
// difference, and so does the spread.
TEST(FusedTransformer, DropoutMatchesLibtorchInDistribution) {
  const Sizes s{6, 3, 8, 2, 12, 2};
  auto [encoder, tokens] = dropout_case(s, 41);
  torch::NoGradGuard no_grad;
  constexpr int kDraws = 4000;
  torch::Tensor sum_ours = torch::zeros({s.batch, s.d}), sum_theirs = torch::zeros_like(sum_ours);
  torch::Tensor square_ours = torch::zeros_like(sum_ours),
                square_theirs = torch::zeros_like(sum_ours);
  at::Generator generator = at::detail::createCPUGenerator(3);
  for (int i = 0; i < kDraws; ++i) {
    const torch::Tensor ours = encoder_last_token(encoder, tokens, generator);
    const torch::Tensor theirs = encoder->forward(tokens).select(0, -1);
    sum_ours += ours;
    square_ours += ours * ours;
    sum_theirs += theirs;
    square_theirs += theirs * theirs;
  }
  const torch::Tensor mean_ours = sum_ours / kDraws, mean_theirs = sum_theirs / kDraws;
  const torch::Tensor var_ours = square_ours / kDraws - mean_ours * mean_ours;
  const torch::Tensor var_theirs = square_theirs / kDraws - mean_theirs * mean_theirs;
  EXPECT_GT(var_theirs.min().item<double>(), 1e-4);  // dropout does change the output
  const torch::Tensor z = (mean_ours - mean_theirs) / ((var_ours + var_theirs) / kDraws).sqrt();
  EXPECT_LT(z.abs().max().item<double>(), 5.0);
  const double spread = (var_ours.sqrt().mean() / var_theirs.sqrt().mean()).item<double>();
  EXPECT_NEAR(spread, 1.0, 0.05);
}

}  // namespace
}  // namespace deixis::train
