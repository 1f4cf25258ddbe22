#pragma once
// The FMD autoencoder's 1-D convolutions written as matrix products on time-major tensors.
//
// Why: its segments are tiny (batch 8 × 30 frames × 18 channels), and libtorch 1.13's Conv1d and
// ConvTranspose1d spend most of a training step in per-call set-up (oneDNN primitive creation,
// layout permutes, im2col through conv2d), not in arithmetic: forward + backward took 10.5 ms of
// CPU per step against 4 ms for the same maths as unfold/matmul/fold (docs/training.md). The
// parameters keep the torch module layouts ([out, in, k] for Conv1d, [in, out, k] for
// ConvTranspose1d), so the exported tensors are the authors' and load in the runtime unchanged.
//
// Shapes are time-major, [batch, time, channels], as the segments are stored.

#include <torch/torch.h>

namespace deixis::train {

// Conv1d with stride 1, no padding: x [B, T, C], weight [O, C, K], bias [O] → [B, T − K + 1, O].
torch::Tensor conv1d_as_matmul(const torch::Tensor& x, const torch::Tensor& weight,
                               const torch::Tensor& bias);

// ConvTranspose1d with stride 1, no padding: x [B, L, I], weight [I, O, K], bias [O] →
// [B, L + K − 1, O]; every input frame adds its K-frame contribution (overlap-add).
torch::Tensor conv_transpose1d_as_matmul(const torch::Tensor& x, const torch::Tensor& weight,
                                         const torch::Tensor& bias);

}  // namespace deixis::train
