#pragma once
// The FMD autoencoder's training step (docs/eval.md#what-each-number-is; the authors'
// ConvolutionalAutoEncoder with 18 channels, width 256, kernel 15) written out on plain float
// buffers: forward pass, L1 reconstruction loss and backward pass, with no libtorch and no
// autograd.
//
// Why: 600 epochs of 4,595 steps with batches of 8 segments are 2.76 M optimiser steps per hand;
// even as matrix products inside libtorch (conv_as_matmul.h) a step cost ≈ 5 ms, two thirds of it
// per-operation overhead and copies around ≈ 1.5 ms of arithmetic (docs/training.md). Here each
// layer is one unfold or fold pass and one matrix product on buffers allocated once (Eigen's
// products take their packing workspace from the heap), and the gradients go straight into the
// trainer's flat gradient buffer.
//
//   x [batch, 30, 18] (time-major, as the segments are stored)
//   h₁ = ReLU(Conv1d(x; W₁ [256, 18, 15]))            [batch, 16, 256]
//   c  = Conv1d(h₁; W₂ [128, 256, 16])                [batch, 1, 128]   the latent code
//   h₂ = ReLU(ConvTranspose1d(c; W₃ [128, 256, 16]))  [batch, 16, 256]
//   y  = ConvTranspose1d(h₂; W₄ [256, 18, 15])        [batch, 30, 18]
//   loss = mean |y − x|
// The weights keep torch's layouts ([out, in, k] for Conv1d, [in, out, k] for ConvTranspose1d).
// tests/train/autoencoder_step_test.cpp checks the loss, the reconstruction and every gradient
// against libtorch's autograd through the training model.

#include <cstddef>
#include <span>

#include "train/aligned_buffer.h"

namespace deixis::train {

// conv_encode1, conv_encode2, conv_decode2, conv_decode1 in the order the data flows.
struct AutoencoderBuffers {
  float* weight[4] = {};
  float* bias[4] = {};
};

class AutoencoderStep {
 public:
  static constexpr int kFrames = 30;
  static constexpr int kChannels = 18;

  // Layer i (0 = conv_encode1 … 3 = conv_decode1): frames in and out, channels, kernel.
  struct LayerShape {
    bool transposed = false;
    int in_frames = 0, out_frames = 0, in_channels = 0, out_channels = 0, kernel = 0;
  };
  static LayerShape layer_shape(int i);
  static std::size_t parameter_count();

  explicit AutoencoderStep(int max_batch);

  // Forward pass of `count` ≤ max_batch segments ([count, 30, 18], contiguous); returns their
  // share of the L1 reconstruction loss, the mean over `whole_batch` segments (default: count;
  // a slice of a batch split across threads, as MoeStep::forward). The reconstruction stays in
  // reconstruction() until the next call.
  double forward(const AutoencoderBuffers& parameters, const float* segments, int count,
                 int whole_batch = 0);
  // Backward pass of the last forward: every parameter's gradient, written (not added) into
  // `gradients`.
  void backward(const AutoencoderBuffers& parameters, const AutoencoderBuffers& gradients);

  std::span<const float> reconstruction() const;

 private:
  // One layer: its shape and its buffers.
  struct Layer : LayerShape {
    AlignedFloats columns;  // Conv1d: the unfolded input; transposed: the products
    AlignedFloats output;   // [batch, out_frames, out_channels], after the ReLU if any
  };

  void layer_forward(Layer& layer, const float* input, const float* weight, const float* bias,
                     bool relu);
  // ∂L/∂output in d_output_ (overwritten by ∂L/∂input when `want_input`).
  void layer_backward(Layer& layer, const float* input, const float* weight, float* d_weight,
                      float* d_bias, bool want_input);

  int max_batch_;
  int batch_ = 0;
  const float* segments_ = nullptr;
  Layer layers_[4];
  AlignedFloats d_output_;  // the gradient flowing back, [batch, frames, channels]
  AlignedFloats d_input_;
  AlignedFloats d_columns_;
};

}  // namespace deixis::train
