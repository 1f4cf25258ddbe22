#pragma once
// The training step of the two MoE networks (MPNet GRU-MoE and UGNet MoE,
// docs/conventions.md#mixture-of-experts) written out on plain float buffers: forward pass, L1 loss
// and the whole backward pass, with no libtorch and no autograd.
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
// The maths is the libtorch models' (train/models.cpp), term for term:
//   gating:  ω = softmax(GRU₂(GRU₁(window[:, :, gating columns]))[:, −1])   (hidden = 9 experts)
//   MPNet:   a₀ = GRU(window)[:, −1] (hidden 24);  UGNet: a₀ = the 264-value condition vector
//   experts: u_l = Σ_e ω_e ⊙ (a_{l−1}·W_e,l + b_e,l), a_l = ELU(u_l) (l = 1, 2), output u₃
//   MPNet's output is clamped to [0, 1]; loss = mean |output − target| (torch's l1_loss).
// tests/train/moe_step_test.cpp checks the loss, the prediction and every gradient against
// libtorch's autograd through the training models at both networks' sizes.

#include <barrier>
#include <cstddef>
#include <span>
#include <vector>

#include "train/aligned_buffer.h"

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

// Expert parallelism: the nine experts of every layer are shared out among the members of a
// team of threads, member m computing experts [9·m/n, 9·(m+1)/n) — their products, their
// gradients — and member 0 the GRUs as well. The batch stays whole, so every product keeps its
// size, and each expert's gradient is computed by one member only: nothing is added across
// threads but the blended outputs and the hidden layers' input gradients (a few KB). All members
// call forward() and backward() with the same arguments and their own `member`; `sync` is the
// team's barrier, which they meet three to four times per pass (null for a team of one).
struct ExpertTeam {
  int member = 0;
  int members = 1;
  std::barrier<>* sync = nullptr;
};

class MoeStep {
 public:
  static constexpr int kWindowRows = 30;
  static constexpr int kExperts = 9;

  // Buffers for up to `max_batch` windows and a team of `members` threads, allocated once.
  MoeStep(const MoeShape& shape, int max_batch, int members = 1);

  // Forward pass of `count` ≤ max_batch windows; returns the L1 loss, the mean over them. The
  // predictions (count × expert_out, row-major) stay in prediction() until the next call.
  double forward(const MoeBuffers& parameters, WindowBatch windows, TargetBatch targets, int count,
                 ExpertTeam team = {});
  // Backward pass of the last forward: the loss's gradient for every parameter, written (not
  // added) into `gradients`.
  void backward(const MoeBuffers& parameters, const MoeBuffers& gradients, ExpertTeam team = {});

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
  // What each member of an expert team keeps of its own (every member the same values where they
  // are not partial).
  struct MemberState {
    AlignedFloats input[3];         // a_{l−1}, [batch][in]
    AlignedFloats partial[3];       // Σ over this member's experts of ω_e ⊙ products
    AlignedFloats blended[3];       // u_l = Σ over members of partial, [batch][out]
    AlignedFloats d_input_part[3];  // Σ over this member's experts of ∂u_l/∂a·…, [batch][in]
    AlignedFloats d_u, d_a, d_h;    // ∂L/∂u_l, ∂L/∂a_{l−1}, ω_e ⊙ ∂L/∂u_l
    AlignedFloats d_output;         // ∂L/∂u₃, [batch][out]
  };

  void gru_forward(GruLayerState& layer, const GruLayerBuffers& p);
  void gru_backward(GruLayerState& layer, const GruLayerBuffers& p, const GruLayerBuffers& g,
                    float* d_input);
  void gating_forward(const MoeBuffers& p, WindowBatch windows, int count);
  void gating_backward(const MoeBuffers& p, const MoeBuffers& g);
  void gather_condition(WindowBatch windows, int count, float* a) const;
  void products(const MoeBuffers& p, int layer, int first_expert, int last_expert, const float* a,
                int count);
  void experts_forward(const MoeBuffers& p, ExpertTeam team, bool layer0_products_done);
  void experts_backward(const MoeBuffers& p, const MoeBuffers& g, ExpertTeam team);

  MoeShape shape_;
  int max_batch_;
  int batch_ = 0;     // windows of the last forward
  int lanes_ = 0;     // the GRUs' batch stride: batch_ rounded up to whole vectors of 8
  int dims_[4] = {};  // the experts' widths: in, hidden, hidden, out
  GruLayerState gating_[2];
  GruLayerState encoder_;
  AlignedFloats products_[3];  // a_{l−1}·W_e + b_e, [experts][batch][out]; each member its own e
  std::vector<MemberState> members_;
  AlignedFloats omega_;    // [batch][experts]
  AlignedFloats d_omega_;  // [batch][experts]; column e written by the member owning e
  AlignedFloats output_;   // [batch][out], clamped for MPNet
  AlignedFloats scratch_;  // per-step temporaries of the GRUs
};

}  // namespace deixis::train
