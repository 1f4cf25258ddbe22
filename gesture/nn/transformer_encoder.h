#pragma once
// torch.nn.TransformerEncoderLayer as the authors instantiate it: post-norm (norm_first = False),
// ReLU feed-forward, LayerNorm eps 1e-5, dropout inactive (eval), no positional encoding
// (docs/conventions.md#mpnet, #ugnet):
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

  // The queries, keys and values of every token: x·W_inᵀ + b_in.
  using QkvMatrix = Eigen::Matrix<float, Tokens, 3 * Dim, Eigen::RowMajor>;
  // Window j's tokens as rows j·Tokens … j·Tokens + Tokens − 1 of one matrix, for run_batch().
  using TokenRows = Eigen::Matrix<float, Eigen::Dynamic, Dim, Eigen::RowMajor>;
  using QkvRows = Eigen::Matrix<float, Eigen::Dynamic, 3 * Dim, Eigen::RowMajor>;

  // All tokens in, all tokens out (in place).
  void run(TokenMatrix& x) const {
    QkvMatrix qkv;
    qkv.noalias() = x * in_proj_weight.view().transpose();
    qkv.rowwise() += in_proj_bias.view().transpose();
    run_projected(qkv, x);
  }

  // run() given x's projections qkv, for a caller that computes them more cheaply
  // (UgnetTransformer folds its token embedding into the first layer's).
  void run_projected(const QkvMatrix& qkv, TokenMatrix& x) const {
    TokenMatrix attended;
    self_attention(qkv, attended);
    finish_rows(attended, x);
  }

  // run() on many windows at once (x: TokenRows). The projections and the feed-forward run as
  // products over every window's rows, so each weight matrix is read once per batch instead of
  // once per window; the attention stays per window.
  void run_batch(TokenRows& x) const {
    QkvRows qkv(x.rows(), 3 * Dim);
    qkv.noalias() = x * in_proj_weight.view().transpose();
    qkv.rowwise() += in_proj_bias.view().transpose();
    run_batch_projected(qkv, x);
  }

  // run_batch() given x's projections.
  void run_batch_projected(const QkvRows& qkv, TokenRows& x) const {
    TokenRows attended(x.rows(), Dim);
    for (Eigen::Index w = 0; w < x.rows() / Tokens; ++w) {
      self_attention(qkv.middleRows(w * Tokens, Tokens), attended.middleRows(w * Tokens, Tokens));
    }
    finish_rows(attended, x);
  }

  // All tokens in; only the last token's output is computed (the networks read nothing else of
  // the final layer). Keys and values still come from every token.
  Eigen::Matrix<float, 1, Dim> run_last_token(const TokenMatrix& x) const {
    Eigen::Matrix<float, Tokens, 2 * Dim, Eigen::RowMajor> kv;
    kv.noalias() = x * in_proj_weight.view().template bottomRows<2 * Dim>().transpose();
    kv.rowwise() += in_proj_bias.view().template bottomRows<2 * Dim>().transpose();
    Eigen::Matrix<float, 1, Dim> y = x.row(Tokens - 1);
    Eigen::Matrix<float, 1, Dim> q;
    q.noalias() = y * in_proj_weight.view().template topRows<Dim>().transpose();
    q += in_proj_bias.view().template topRows<Dim>().transpose();
    Eigen::Matrix<float, 1, Dim> attended;
    last_token_attention(q, kv, attended);
    finish_rows(attended, y);
    return y;
  }

  // run_last_token() on many windows (x: TokenRows); row j of the result is window j's.
  TokenRows run_last_token_batch(const TokenRows& x) const {
    const Eigen::Index windows = x.rows() / Tokens;
    Eigen::Matrix<float, Eigen::Dynamic, 2 * Dim, Eigen::RowMajor> kv(x.rows(), 2 * Dim);
    kv.noalias() = x * in_proj_weight.view().template bottomRows<2 * Dim>().transpose();
    kv.rowwise() += in_proj_bias.view().template bottomRows<2 * Dim>().transpose();
    TokenRows y(windows, Dim);
    for (Eigen::Index w = 0; w < windows; ++w) {
      y.row(w) = x.row(w * Tokens + Tokens - 1);
    }
    TokenRows q(windows, Dim);
    q.noalias() = y * in_proj_weight.view().template topRows<Dim>().transpose();
    q.rowwise() += in_proj_bias.view().template topRows<Dim>().transpose();
    TokenRows attended(windows, Dim);
    for (Eigen::Index w = 0; w < windows; ++w) {
      last_token_attention(q.row(w), kv.middleRows(w * Tokens, Tokens), attended.row(w));
    }
    finish_rows(attended, y);
    return y;
  }

 private:
  // softmax(q·kᵀ/√head_dim)·v per head, for Queries query rows against the window's Tokens keys.
  template <int Queries, typename Q, typename K, typename V, typename Out>
  static void attend(const Q& q, const K& k, const V& v, Out&& out) {
    Eigen::Matrix<float, Queries, Tokens, Eigen::RowMajor> scores;
    scores.noalias() = (q * k.transpose()) * (1.0f / std::sqrt(static_cast<float>(kHeadDim)));
    for (int t = 0; t < Queries; ++t) {
      auto row = scores.row(t);
      softmax_inplace(row);
    }
    out.noalias() = scores * v;
  }

  // Every token attends to every token: qkv [Tokens, 3·Dim] → attended [Tokens, Dim].
  template <typename Qkv, typename Out>
  static void self_attention(const Qkv& qkv, Out&& attended) {
    for (int h = 0; h < Heads; ++h) {
      attend<Tokens>(qkv.template middleCols<kHeadDim>(h * kHeadDim),
                     qkv.template middleCols<kHeadDim>(Dim + h * kHeadDim),
                     qkv.template middleCols<kHeadDim>(2 * Dim + h * kHeadDim),
                     attended.template middleCols<kHeadDim>(h * kHeadDim));
    }
  }

  // The last token attends to every token: q [1, Dim], kv [Tokens, 2·Dim] → attended [1, Dim].
  template <typename Q, typename Kv, typename Out>
  static void last_token_attention(const Q& q, const Kv& kv, Out&& attended) {
    for (int h = 0; h < Heads; ++h) {
      attend<1>(q.template middleCols<kHeadDim>(h * kHeadDim),
                kv.template middleCols<kHeadDim>(h * kHeadDim),
                kv.template middleCols<kHeadDim>(Dim + h * kHeadDim),
                attended.template middleCols<kHeadDim>(h * kHeadDim));
    }
  }

  // The rest of the layer on the rows of x given their attention output:
  //   x ← norm1(x + out_proj(attended));  x ← norm2(x + linear2(relu(linear1(x))))
  template <typename Rows>
  void finish_rows(const Rows& attended, Rows& x) const {
    x.noalias() += attended * out_proj.weight.view().transpose();
    x.rowwise() += out_proj.bias.view().transpose();
    for (Eigen::Index t = 0; t < x.rows(); ++t) {
      norm1.apply(x.row(t));
    }
    Eigen::Matrix<float, Rows::RowsAtCompileTime, FeedForward, Eigen::RowMajor> hidden(x.rows(),
                                                                                       FeedForward);
    hidden.noalias() = x * linear1.weight.view().transpose();
    hidden.rowwise() += linear1.bias.view().transpose();
    relu_inplace(hidden);
    x.noalias() += hidden * linear2.weight.view().transpose();
    x.rowwise() += linear2.bias.view().transpose();
    for (Eigen::Index t = 0; t < x.rows(); ++t) {
      norm2.apply(x.row(t));
    }
  }
};

}  // namespace deixis::nn
