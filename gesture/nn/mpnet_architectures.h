#pragma once
// The three MPNet architectures of paper Table III (docs/conventions.md#mpnet), with the authors'
// tensor names (model.py). Each has load() and a const run(); Mpnet (mpnet.h) dispatches to them.

#include "gesture/nn/expert_layer.h"
#include "gesture/nn/gru.h"
#include "gesture/nn/linear.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/transformer_encoder.h"

namespace deixis::nn {

// GRU-MoE, the paper's MPNet (docs/conventions.md#mpnet, #mixture-of-experts). Gating: 2-layer GRU
// (hidden 9) over the 5 target columns, softmax of its last output (no linear layer) → 9 expert
// weights. Recurrent module: 1-layer GRU (hidden 24) over all 11 columns. Experts 24 → 12 → 12 → 3
// with ELU; clamp to [0, 1].
struct MpnetGruMoe {
  static constexpr int kExperts = 9;
  static constexpr int kRecurrentHidden = 24;
  static constexpr int kExpertHidden = kRecurrentHidden / 2;

  GruLayer<5, kExperts> gating_l0;
  GruLayer<kExperts, kExperts> gating_l1;
  GruLayer<kMpnetFeatures, kRecurrentHidden> recurrent;
  ExpertLayer<kExperts, kRecurrentHidden, kExpertHidden> expert_l1;
  ExpertLayer<kExperts, kExpertHidden, kExpertHidden> expert_l2;
  ExpertLayer<kExperts, kExpertHidden, kProgressionSize> expert_l3;

  static bool recognises(const SafetensorsFile& file);
  void load(const SafetensorsFile& file);
  MpnetOutput run(MpnetWindow window, MpnetTrace* trace) const;
  // run() on `count` windows stored one after another (Mpnet::run_batch): the three GRUs stepped
  // for everyone at once and the experts' products for the whole batch as matrix products.
  void run_batch(const float* windows, int count, MpnetOutput* out, BatchBuffers& buffers) const;
  // Sizes `buffers` for batches of up to `count` windows.
  static void reserve_batch(int count, BatchBuffers& buffers);
  static constexpr std::size_t kParameters = 8091;
};

// MLP (model.py MPNet_MLP): the window flattened row-major (330) → 24 → 24 → 3, ELU between.
struct MpnetMlp {
  Linear<kMpnetWindowSize, 24> linear1;
  Linear<24, 24> linear2;
  Linear<24, kProgressionSize> linear3;

  static bool recognises(const SafetensorsFile& file);
  void load(const SafetensorsFile& file);
  MpnetOutput run(MpnetWindow window) const;
  static constexpr std::size_t kParameters = 8619;
};

// Transformer (model.py MPNet_Transformer): Linear 11 → 16 per row, 4 post-norm encoder layers
// (4 heads of 4, feed-forward 16, no positional encoding), newest token → Linear 16 → 3, clamp.
struct MpnetTransformer {
  static constexpr int kDim = 16;
  static constexpr int kLayers = 4;
  using Layer = TransformerEncoderLayer<kWindowRows, kDim, 4, kDim>;

  Linear<kMpnetFeatures, kDim> linear_input;
  std::array<Layer, kLayers> layers;
  Linear<kDim, kProgressionSize> linear_output;

  static bool recognises(const SafetensorsFile& file);
  void load(const SafetensorsFile& file);
  MpnetOutput run(MpnetWindow window) const;
  static constexpr std::size_t kParameters = 7027;
};

// Clamps to [0, 1] into `out.progression` and keeps the raw values in `out.preclamp`.
MpnetOutput clamp_progression(const Eigen::Matrix<float, kProgressionSize, 1>& raw);

}  // namespace deixis::nn
