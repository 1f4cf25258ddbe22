#pragma once
// The three blended expert layers of the MoE networks (docs/conventions.md#mixture-of-experts) for
// training, as one autograd node with a hand-written backward pass.
//
// Why: UGNet MoE steps the optimiser once per 30-row window with a batch of only 32, so a step's
// arithmetic (~86 MFLOP) is small enough that libtorch's per-operation cost (the broadcast
// batched product's copies, the ω products and sums, ELU, their backward nodes, ~1.4 MB of fresh
// gradient tensors per step) took as long as the products themselves (profile in
// docs/training.md). Here the nine per-expert products of each layer run on raw buffers with
// Eigen, the blending and ELU are single passes, and nothing but the returned gradients is
// allocated. tests/train/fused_experts_test.cpp checks values and every gradient against the
// libtorch composition.
//
// Per layer l with input a (a₀ = x), per-expert weights W_e [in, out], biases b_e [out] and the
// gating weights ω [batch, experts]:  u = Σ_e ω_e ⊙ (a·W_e + b_e),  a' = ELU(u) (not after the
// last layer). That is the authors' x·(Σ_e ω_e W_e) + Σ_e ω_e b_e without forming a [batch, in,
// out] blended weight per sample.

#include <torch/types.h>

#include <array>

namespace deixis::train {

// x [batch, in], omega [batch, experts]; weights[l] [experts, in_l, out_l], biases[l]
// [experts, out_l] → [batch, out_3]. Differentiable in every argument.
torch::Tensor expert_layers(const torch::Tensor& x, const torch::Tensor& omega,
                            const std::array<torch::Tensor, 3>& weights,
                            const std::array<torch::Tensor, 3>& biases);

}  // namespace deixis::train
