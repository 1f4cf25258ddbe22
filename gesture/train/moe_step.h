#pragma once
// The training step of the two MoE networks (MPNet GRU-MoE and UGNet MoE, NOTES §3.2) written
// out on plain float buffers: forward pass, L1 loss and the whole backward pass, with no libtorch
// and no autograd.
//
// Why: the authors step the optimiser once per 30-row window, with batches of 16 (MPNet) and 32
// (UGNet) clips, so one step is little arithmetic, and libtorch's cost per operation (dispatch,
// autograd nodes, fresh gradient tensors, ~40 small operations around the fused GRU and expert
// nodes) was a large share of it: MPNet 0.68 ms and UGNet 1.95 ms per step for 5.5 M and 4.1 M
// steps per run (docs/training.md). Here a step is straight-line code over buffers allocated
// once (only Eigen's larger products take their packing workspace from the heap, which glibc
// serves from its free lists), the GRUs keep the batch innermost (every loop is a vector pass
// over 16 or 32 clips), and the gradients are written straight into the trainer's flat gradient
// buffer.
//
// The maths is the libtorch models' (gesture/train/models.cpp), term for term:
//   gating:  ω = softmax(GRU₂(GRU₁(window[:, :, gating columns]))[:, −1])   (hidden = 9 experts)
//   MPNet:   a₀ = GRU(window)[:, −1] (hidden 24);  UGNet: a₀ = the 264-value condition vector
//   experts: u_l = Σ_e ω_e ⊙ (a_{l−1}·W_e,l + b_e,l), a_l = ELU(u_l) (l = 1, 2), output u₃
//   MPNet's output is clamped to [0, 1]; loss = mean |output − target| (torch's l1_loss).
// tests/train/moe_step_test.cpp checks the loss, the prediction and every gradient against
// libtorch's autograd through the training models at both networks' sizes.

#include <cstddef>
#include <span>

#include "gesture/train/aligned_buffer.h"

namespace deixis::train {

// One GRU layer's tensors in torch.nn.GRU's layout: w_ih [3H, in], w_hh [3H, H], b_ih and b_hh
// [3H], gate order r | z | n.
struct GruLayerBuffers {
  float* w_ih = nullptr;
  float* w_hh = nullptr;
  float* b_ih = nullptr;
  float* b_hh = nullptr;
};

// A MoE network's parameters (or, with the same layout, their gradients) as pointers into the
// trainer's buffers, under the authors' module names.
struct MoeBuffers {
  GruLayerBuffers gating[2];      // gating_network.gru.*_l0, *_l1
  GruLayerBuffers encoder;        // MPNet's gru.*_l0 (unused by UGNet)
  float* expert_weights[3] = {};  // moe_network.w_l1..3 [experts, in, out]
  float* expert_biases[3] = {};   // moe_network.b_l1..3 [experts, out]
};

struct MoeShape {
  int window_columns = 0;  // input columns of a window row: 11 (MPNet), 32 (UGNet)
  int gating_first = 0;    // the gating GRU reads columns [first, first + count)
  int gating_columns = 0;
  int encoder_hidden = 0;  // MPNet's GRU over all input columns; 0 for UGNet
  int pose_columns = 0;    // UGNet: the newest row's pose starts the condition vector; 0 for MPNet
  int expert_in = 0, expert_hidden = 0, expert_out = 0;
  bool clamp_output = false;  // MPNet's progression is clamped to [0, 1]

  static MoeShape mpnet();  // 11 columns, gating 6..10, GRU 11 → 24, experts 24 → 12 → 12 → 3
  static MoeShape ugnet();  // 32 columns, gating 24..31, experts 264 → 144 → 144 → 24
  std::size_t parameter_count() const;
};

// Where a batch of windows and their targets lie in memory: item b's row r, column c at
// first[b·item_stride + r·row_stride + c] (the trainer's [batch, 45, columns] clips).
struct WindowBatch {
  const float* first = nullptr;
  std::size_t item_stride = 0;
  std::size_t row_stride = 0;
};
struct TargetBatch {
  const float* first = nullptr;  // item b's target at first[b·item_stride]
  std::size_t item_stride = 0;
};

class MoeStep {
 public:
  static constexpr int kWindowRows = 30;
  static constexpr int kExperts = 9;

  // Buffers for up to `max_batch` windows, allocated here once.
  MoeStep(const MoeShape& shape, int max_batch);

  // Forward pass of `count` ≤ max_batch windows; returns their share of the L1 loss, the mean
  // over `whole_batch` windows (default: count): a slice of a batch split across threads gives
  // its part of the whole batch's mean, and the slices' losses and gradients add up to the
  // batch's.
  // The predictions (count × expert_out, row-major) stay in prediction() until the next call.
  double forward(const MoeBuffers& parameters, WindowBatch windows, TargetBatch targets, int count,
                 int whole_batch = 0);
  // Backward pass of the last forward: the loss's gradient for every parameter, written (not
  // added) into `gradients`.
  void backward(const MoeBuffers& parameters, const MoeBuffers& gradients);

  std::span<const float> prediction() const;
  const MoeShape& shape() const { return shape_; }

 private:
  // A GRU layer's sequences keep the batch innermost ("lanes", padded with zero clips).
  struct GruLayerState {
    int input = 0, hidden = 0;
    AlignedFloats input_sequence;  // [input][time][lanes]
    AlignedFloats output;          // [hidden][time][lanes]
    AlignedFloats gates;           // [time][r, z, n, W_hn·h + b_hn][hidden][lanes]
    AlignedFloats d_output;        // ∂L/∂output, [hidden][time][lanes]
    AlignedFloats d_input_gates;   // [3·hidden][time][lanes]
    AlignedFloats d_hidden_gates;  // [3·hidden][time][lanes]
  };
  struct ExpertLayerState {
    int in = 0, out = 0;
    AlignedFloats input;     // a_{l−1}, [batch][in]
    AlignedFloats products;  // a_{l−1}·W_e + b_e, [experts][batch][out]
    AlignedFloats blended;   // u_l, [batch][out]
  };

  void gru_forward(GruLayerState& layer, const GruLayerBuffers& p);
  void gru_backward(GruLayerState& layer, const GruLayerBuffers& p, const GruLayerBuffers& g,
                    float* d_input);
  void experts_forward(const MoeBuffers& p);
  void experts_backward(const MoeBuffers& p, const MoeBuffers& g);

  MoeShape shape_;
  int max_batch_;
  int batch_ = 0;  // windows of the last forward
  int lanes_ = 0;  // the GRUs' batch stride: batch_ rounded up to whole vectors of 8
  GruLayerState gating_[2];
  GruLayerState encoder_;
  ExpertLayerState experts_[3];
  AlignedFloats omega_;     // [batch][experts]
  AlignedFloats d_omega_;   // [batch][experts]
  AlignedFloats output_;    // [batch][out], clamped for MPNet
  AlignedFloats d_output_;  // ∂L/∂u₃, [batch][out]
  AlignedFloats scratch_;   // per-step temporaries of the GRUs and experts_backward
};

}  // namespace deixis::train
