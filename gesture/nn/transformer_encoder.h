#pragma once
// torch.nn.TransformerEncoderLayer as the authors instantiate it: post-norm (norm_first = False),
// ReLU feed-forward, LayerNorm eps 1e-5, dropout inactive (eval), no positional encoding
// (NOTES §3.3, §4.4):
//   x ← LayerNorm1(x + SelfAttention(x));   x ← LayerNorm2(x + W2·relu(W1·x + b1) + b2)
// Tokens are rows. Sizes are fixed: Tokens × Dim with Heads heads of Dim/Heads, feed-forward
// width FeedForward.

#include <cmath>
#include <string>

#include "gesture/nn/activations.h"
#include "gesture/nn/linear.h"

namespace deixis::nn {

template <int Dim>
struct LayerNorm {
  VectorParam<Dim> weight;
  VectorParam<Dim> bias;
  static constexpr float kEps = 1e-5f;

  void load(const SafetensorsFile& file, const std::string& prefix) {
    load_vector(file, prefix + ".weight", weight);
    load_vector(file, prefix + ".bias", bias);
  }

  // Normalises one row (biased variance, as PyTorch).
  template <typename Row>
  void apply(Row&& row) const {
    const float mean = row.mean();
    const float variance = (row.array() - mean).square().mean();
    const float inv = 1.0f / std::sqrt(variance + kEps);
    row = ((row.array() - mean) * inv * weight.view().transpose().array() +
           bias.view().transpose().array())
              .matrix();
  }
};

template <int Tokens, int Dim, int Heads, int FeedForward>
struct TransformerEncoderLayer {
  static_assert(Dim % Heads == 0, "heads must divide the model width");
  static constexpr int kHeadDim = Dim / Heads;
  using TokenMatrix = Eigen::Matrix<float, Tokens, Dim, Eigen::RowMajor>;

  MatrixParam<3 * Dim, Dim> in_proj_weight;  // q | k | v stacked, nn.MultiheadAttention layout
  VectorParam<3 * Dim> in_proj_bias;
  Linear<Dim, Dim> out_proj;
  Linear<Dim, FeedForward> linear1;
  Linear<FeedForward, Dim> linear2;
  LayerNorm<Dim> norm1;
  LayerNorm<Dim> norm2;

  // `prefix` is e.g. "transformer.layers.0".
  void load(const SafetensorsFile& file, const std::string& prefix) {
    load_matrix(file, prefix + ".self_attn.in_proj_weight", in_proj_weight);
    load_vector(file, prefix + ".self_attn.in_proj_bias", in_proj_bias);
    out_proj.load(file, prefix + ".self_attn.out_proj");
    linear1.load(file, prefix + ".linear1");
    linear2.load(file, prefix + ".linear2");
    norm1.load(file, prefix + ".norm1");
    norm2.load(file, prefix + ".norm2");
  }

  // All tokens in, all tokens out (in place).
  void run(TokenMatrix& x) const {
    Eigen::Matrix<float, Tokens, 3 * Dim, Eigen::RowMajor> qkv;
    qkv.noalias() = x * in_proj_weight.view().transpose();
    qkv.rowwise() += in_proj_bias.view().transpose();

    TokenMatrix attended;
    for (int h = 0; h < Heads; ++h) {
      const auto q = qkv.template middleCols<kHeadDim>(h * kHeadDim);
      const auto k = qkv.template middleCols<kHeadDim>(Dim + h * kHeadDim);
      const auto v = qkv.template middleCols<kHeadDim>(2 * Dim + h * kHeadDim);
      Eigen::Matrix<float, Tokens, Tokens, Eigen::RowMajor> scores;
      scores.noalias() = (q * k.transpose()) * (1.0f / std::sqrt(static_cast<float>(kHeadDim)));
      for (int t = 0; t < Tokens; ++t) {
        auto row = scores.row(t);
        softmax_inplace(row);
      }
      attended.template middleCols<kHeadDim>(h * kHeadDim).noalias() = scores * v;
    }
    TokenMatrix y;
    y.noalias() = attended * out_proj.weight.view().transpose();
    y.rowwise() += out_proj.bias.view().transpose();
    x += y;
    for (int t = 0; t < Tokens; ++t) {
      norm1.apply(x.row(t));
    }
    feed_forward_rows(x);
  }

  // All tokens in; only the last token's output is computed (the networks read nothing else of
  // the final layer). Keys and values still come from every token.
  Eigen::Matrix<float, 1, Dim> run_last_token(const TokenMatrix& x) const {
    Eigen::Matrix<float, Tokens, 2 * Dim, Eigen::RowMajor> kv;
    kv.noalias() = x * in_proj_weight.view().template bottomRows<2 * Dim>().transpose();
    kv.rowwise() += in_proj_bias.view().template bottomRows<2 * Dim>().transpose();
    Eigen::Matrix<float, 1, Dim> q;
    q.noalias() = x.row(Tokens - 1) * in_proj_weight.view().template topRows<Dim>().transpose();
    q += in_proj_bias.view().template topRows<Dim>().transpose();

    Eigen::Matrix<float, 1, Dim> attended;
    for (int h = 0; h < Heads; ++h) {
      const auto k = kv.template middleCols<kHeadDim>(h * kHeadDim);
      const auto v = kv.template middleCols<kHeadDim>(Dim + h * kHeadDim);
      Eigen::Matrix<float, 1, Tokens> scores;
      scores.noalias() = (q.template middleCols<kHeadDim>(h * kHeadDim) * k.transpose()) *
                         (1.0f / std::sqrt(static_cast<float>(kHeadDim)));
      softmax_inplace(scores);
      attended.template middleCols<kHeadDim>(h * kHeadDim).noalias() = scores * v;
    }
    Eigen::Matrix<float, 1, Dim> y = x.row(Tokens - 1);
    y.noalias() += attended * out_proj.weight.view().transpose();
    y += out_proj.bias.view().transpose();
    norm1.apply(y);
    Eigen::Matrix<float, 1, FeedForward> hidden;
    hidden.noalias() = y * linear1.weight.view().transpose();
    hidden += linear1.bias.view().transpose();
    relu_inplace(hidden);
    y.noalias() += hidden * linear2.weight.view().transpose();
    y += linear2.bias.view().transpose();
    norm2.apply(y);
    return y;
  }

 private:
  void feed_forward_rows(TokenMatrix& x) const {
    Eigen::Matrix<float, Tokens, FeedForward, Eigen::RowMajor> hidden;
    hidden.noalias() = x * linear1.weight.view().transpose();
    hidden.rowwise() += linear1.bias.view().transpose();
    relu_inplace(hidden);
    x.noalias() += hidden * linear2.weight.view().transpose();
    x.rowwise() += linear2.bias.view().transpose();
    for (int t = 0; t < Tokens; ++t) {
      norm2.apply(x.row(t));
    }
  }
};

}  // namespace deixis::nn
