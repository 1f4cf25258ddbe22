#pragma once
// The UGNet Diffusion's denoiser (model.py NoiseDecoder) for training, as one autograd node with a
// hand-written backward pass.
//
// Why: the denoiser is 12 small layers (batch 32, width 128) and the authors step the optimiser
// once per 30-row window, so libtorch spent a step (3.8–4.9 ms) largely in per-operation dispatch,
// the concatenations every block makes and autograd's bookkeeping of ≈ 60 operations, at about a
// third of a core's arithmetic rate. Here the whole network runs on raw float buffers with Eigen.
//
// The maths is NoiseDecoder's:
//   h = fin(condition ++ noisy ++ time)
//   for each block: h = Linear(SiLU(GroupNorm(h)) ++ noisy ++ condition ++ time)
//   out = fco(h ++ noisy ++ condition ++ time)
// with GroupNorm's eps 1e-5 and biased variance. The parameters are the torch modules' own
// tensors, so names, layouts, checkpoints and exports are unchanged.
// tests/train/fused_denoiser_test.cpp checks the output and every gradient against the libtorch
// composition.

#include <torch/types.h>

#include <cstdint>
#include <vector>

namespace deixis::train {

// One residual-free block: GroupNorm(groups, hidden) → SiLU → Linear(hidden + rest, hidden).
struct DenoiserBlockWeights {
  torch::Tensor norm_weight, norm_bias;  // [hidden]
  torch::Tensor weight, bias;            // [hidden, hidden + pose + condition + time], [hidden]
};

struct DenoiserWeights {
  torch::Tensor fin_weight, fin_bias;  // [hidden, condition + pose + time], [hidden]
  std::vector<DenoiserBlockWeights> blocks;
  torch::Tensor fco_weight, fco_bias;  // [pose, hidden + pose + condition + time], [pose]
  std::int64_t groups = 1;             // GroupNorm's groups; divides hidden
};

// The denoiser's prediction [batch, pose] from condition [batch, C], noisy [batch, pose] and the
// step embedding time [batch, E]; differentiable in the three inputs and every weight.
torch::Tensor denoise(const torch::Tensor& condition, const torch::Tensor& noisy,
                      const torch::Tensor& time, const DenoiserWeights& weights);

}  // namespace deixis::train
