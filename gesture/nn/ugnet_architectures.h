#pragma once
// The four UGNet architectures of paper Table IV (docs/conventions.md#ugnet), with the authors'
// tensor names (model.py). Each has load() and a const run(); Ugnet (ugnet.h) dispatches to them.

#include "gesture/nn/expert_layer.h"
#include "gesture/nn/gru.h"
#include "gesture/nn/linear.h"
#include "gesture/nn/transformer_encoder.h"
#include "gesture/nn/ugnet.h"

namespace deixis::nn {

using UgnetWindowMatrix = Eigen::Matrix<float, kWindowRows, kUgnetColumns, Eigen::RowMajor>;
using ConditionVector = Eigen::Matrix<float, kConditionSize, 1>;

// Newest x (24) ++ the 8 conditioning columns of every row, oldest first
// (docs/conventions.md#ugnet).
ConditionVector condition_vector(UgnetWindow window);

// MoE, the paper's UGNet (docs/conventions.md#ugnet). Gating: 2-layer GRU (hidden 9) over the 8
// conditioning columns, softmax of its last output → 9 expert weights. Experts 264 → 144 → 144 → 24
// with ELU (144 = 24 + 240/2, model.py's operator precedence).
struct UgnetMoe {
  static constexpr int kExperts = 9;
  static constexpr int kHidden = kPoseSize + (kConditionColumns * kWindowRows) / 2;

  GruLayer<kConditionColumns, kExperts> gating_l0;
  GruLayer<kExperts, kExperts> gating_l1;
  ExpertLayer<kExperts, kConditionSize, kHidden> expert_l1;
  ExpertLayer<kExperts, kHidden, kHidden> expert_l2;
  ExpertLayer<kExperts, kHidden, kPoseSize> expert_l3;
  PanelOrder panel_order;  // alternates the weight traversal per call (panel_order.h)

  static bool recognises(const SafetensorsFile& file);
  void load(const SafetensorsFile& file);
  PoseVector run(UgnetWindow window, UgnetTrace* trace) const;
  // run() on `count` windows stored one after another, predictions into out (count × 24)
  // (Ugnet::run_batch): the gating GRUs stepped for everyone at once, every expert's products
  // for the whole batch as matrix products, then each person's blend with their own ω.
  void run_batch(const float* windows, int count, float* out, BatchBuffers& buffers) const;
  // Sizes `buffers` for batches of up to `count` windows.
  static void reserve_batch(int count, BatchBuffers& buffers);
  static constexpr std::size_t kParameters = 563733;
};

// MLP (model.py UGNet_MLP): the 264-vector → 1056 → 264 → 24, ELU between.
struct UgnetMlp {
  Linear<kConditionSize, 4 * kConditionSize> linear1;
  Linear<4 * kConditionSize, kConditionSize> linear2;
  Linear<kConditionSize, kPoseSize> linear3;
  PanelOrder panel_order;  // alternates the weight traversal per call (panel_order.h)

  static bool recognises(const SafetensorsFile& file);
  void load(const SafetensorsFile& file);
  PoseVector run(UgnetWindow window) const;
  static constexpr std::size_t kParameters = 565248;
};

// Transformer (model.py UGNet_Transformer): 30 feature tokens (Linear 8 → 160 of each row's
// conditioning columns) and one pose token (Linear 24 → 160 of the newest x) appended last; 4
// post-norm encoder layers (4 heads of 40, feed-forward 160); the pose token → Linear 160 → 24.
struct UgnetTransformer {
  static constexpr int kDim = 160;
  static constexpr int kLayers = 4;
  static constexpr int kTokens = kWindowRows + 1;
  using Layer = TransformerEncoderLayer<kTokens, kDim, 4, kDim>;

  Linear<kPoseSize, kDim> linear_input_pose;
  Linear<kConditionColumns, kDim> linear_input_feature;
  std::array<Layer, kLayers> layers;
  Linear<kDim, kPoseSize> linear_output;
  // The first layer's projections of a feature token folded with its embedding by load():
  // qkv = c·Fᵀ + g for the row's 8 conditioning columns c, F = W_in·W_feature,
  // g = W_in·b_feature + b_in: 8 multiply-adds per value instead of 160, 13 % of a call's
  // arithmetic saved (the same function up to float rounding).
  MatrixParam<3 * kDim, kConditionColumns> feature_qkv_weight;
  VectorParam<3 * kDim> feature_qkv_bias;

  static bool recognises(const SafetensorsFile& file);
  void load(const SafetensorsFile& file);
  PoseVector run(UgnetWindow window) const;
  // run() on many windows (Ugnet::run_batch): the layers' products over a chunk of windows'
  // token rows at once; the attention per window.
  void run_batch(std::span<const float> windows, std::span<float> out) const;
  static constexpr std::size_t kParameters = 630104;

 private:
  // One window's 30 feature tokens and pose token into tokens [kTokens, kDim], and the first
  // layer's projections of the feature tokens into the top rows of qkv [kTokens, 3·kDim] (the
  // pose token's are the caller's: a batch computes them in one product).
  template <typename Tokens, typename Qkv>
  void embed(UgnetWindow window, Tokens&& tokens, Qkv&& qkv) const;
};

// Diffusion, AMDM-style (model.py UGNet_Diffusion, docs/conventions.md#ugnet-diffusion): 30 steps
// of a denoiser that predicts the clean x directly, re-noised with σ_t = √β_t between steps.
// The denoiser:
//   h = fin(c ++ x_t ++ e_t);  10 × { h = Linear(SiLU(GroupNorm16(h)) ++ x_t ++ c ++ e_t) };
//   x0 = fco(h ++ x_t ++ c ++ e_t)
// with c the 264-vector and e_t = time_mlp(sinusoidal(t)).
//
// Speed: every linear layer's input is a concatenation whose c-part is the same for all 30 steps
// and whose e_t-part (plus bias) depends only on t. So load() precomputes W_e·e_t + b for every
// layer and step, and run() computes W_c·c once per call; each step then multiplies only the
// 128 hidden and 24 noisy values. Same function, about 3× fewer multiply-adds.
struct UgnetDiffusion {
  static constexpr int kHidden = 128;
  static constexpr int kTimeEmbedding = 64;
  static constexpr int kBlocks = 10;
  static constexpr int kGroups = 16;
  static constexpr int kBlockInput = kHidden + kPoseSize + kConditionSize + kTimeEmbedding;  // 480
  static constexpr int kFirstInput = kConditionSize + kPoseSize + kTimeEmbedding;            // 352

  // A linear layer of the denoiser, its weight split by the part of the concatenated input it
  // multiplies. `hidden` is absent (0 columns) for `fin`, whose input has no h.
  template <int Out, int HiddenIn>
  struct ConditionedLinear {
    MatrixParam<Out, HiddenIn> w_hidden;
    MatrixParam<Out, kPoseSize> w_noisy;
    MatrixParam<Out, kConditionSize> w_condition;
    MatrixParam<kDiffusionSteps, Out> time_and_bias;  // row t: W_e·e_t + b
  };
  ConditionedLinear<kHidden, 0> fin;
  std::array<ConditionedLinear<kHidden, kHidden>, kBlocks> blocks;
  std::array<VectorParam<kHidden>, kBlocks> norm_weight;  // GroupNorm affine
  std::array<VectorParam<kHidden>, kBlocks> norm_bias;
  ConditionedLinear<kPoseSize, kHidden> fco;
  VectorParam<kDiffusionSteps> sigma;  // √β_t, the checkpoint's buffer

  static bool recognises(const SafetensorsFile& file);
  void load(const SafetensorsFile& file);
  PoseVector run(UgnetWindow window, std::span<const float> noise, UgnetTrace* trace) const;
  // run() on many windows (Ugnet::run_batch): each layer's products over a chunk of windows at
  // once, matrix by matrix, so the 2.6 MB of weights are read once per chunk, not per window.
  void run_batch(std::span<const float> windows, std::span<const float> noise,
                 std::span<float> out) const;
  static constexpr std::size_t kParameters = 683588;
};

}  // namespace deixis::nn
