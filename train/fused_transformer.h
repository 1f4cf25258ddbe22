#pragma once
// torch::nn::TransformerEncoder (post-norm layers, ReLU) for training, one autograd node per layer
// with a hand-written backward pass.
//
// Why: the MPNet Transformer is tiny (d_model 16, 4 heads, feed-forward 16, 30 tokens, batch 16:
// ≈ 8 MFLOP per step) and the authors step the optimiser once per 30-row window, so libtorch's
// encoder spent a step (7.9 ms) almost entirely in per-operation dispatch and autograd
// bookkeeping of its hundreds of small operations, and 8 % in the dropout RNG. Here each layer's
// forward and backward run on raw float buffers with Eigen, and dropout masks come from a
// counter-based hash seeded once per layer from the training's generator.
//
// The maths is TransformerEncoderLayer's in training mode:
//   x = norm1(x + dropout(out_proj(attention)))
//   x = norm2(x + dropout(linear2(dropout(relu(linear1(x))))))
// with the attention's queries, keys and values from the packed in_proj ([3d, d]), scores scaled
// by 1/√head_dim, softmax, dropout on the attention weights; LayerNorm eps 1e-5. Without dropout
// (eval, or p = 0) it is the eval-mode encoder. The parameters are the torch modules' own tensors,
// so names, layouts, checkpoints and exports are unchanged. tests/train/fused_transformer_test.cpp
// checks outputs and every gradient against libtorch's encoder.

#include <torch/nn/modules/transformercoder.h>
#include <torch/types.h>

#include <cstdint>

namespace deixis::train {

// The tensors of one torch::nn::TransformerEncoderLayer.
struct EncoderLayerWeights {
  torch::Tensor in_proj_weight, in_proj_bias, out_proj_weight, out_proj_bias;
  torch::Tensor linear1_weight, linear1_bias, linear2_weight, linear2_bias;
  torch::Tensor norm1_weight, norm1_bias, norm2_weight, norm2_bias;
  std::int64_t heads = 1;
};

struct EncoderLayerOptions {
  double dropout = 0.0;    // 0: no masks (eval mode)
  std::uint64_t seed = 0;  // the masks' hash key
  bool last_only = false;  // compute the output of the last token only
};

// One layer: tokens [time, batch, d] → [time, batch, d], or [batch, d] (the last token) when
// options.last_only: the last token's output reads every token's key and value but nothing else
// of the others, so their queries, attention, feed-forward and norms are skipped (the gradient
// stays exact). Differentiable in the tokens and every weight.
torch::Tensor encoder_layer(const torch::Tensor& tokens, const EncoderLayerWeights& weights,
                            const EncoderLayerOptions& options);

// The masks a layer with options.seed = key draws (exposed for tests): count values, each 0 with
// probability p and 1/(1 − p) otherwise. A layer packs them as the attention weights [queries,
// time, heads, batch], then the attention output [queries, batch, d], the feed-forward hidden units
// [queries, batch, ff] and the feed-forward output [queries, batch, d].
torch::Tensor dropout_masks(std::int64_t count, std::uint64_t key, double p);

// encoder->forward(tokens).select(0, -1) for tokens [time, batch, d], with the encoder's own
// parameters, dropout rate and training mode; in training the masks are keyed by numbers drawn
// from generator (one per layer), so a seeded generator gives reproducible runs.
torch::Tensor encoder_last_token(torch::nn::TransformerEncoder& encoder,
                                 const torch::Tensor& tokens, at::Generator generator);

}  // namespace deixis::train
