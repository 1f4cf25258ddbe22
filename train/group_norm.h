#pragma once
// Group normalisation with its affine map, forward and backward, for the fused training kernels:
// the diffusion denoiser's GroupNorm and the Transformer's LayerNorm (one group per row) share it.

#include "train/row_matrix.h"

namespace deixis::train {

// Each row of x is cut into `groups` equal column groups; per (row, group),
// x̂ = (x − mean) / √(var + eps) and rstd = 1 / √(var + eps) are kept for the backward pass
// (rstd is rows × groups), and y = γ ⊙ x̂ + β.
void group_norm(const Eigen::Ref<const RowMatrix>& x, Eigen::Index groups, float eps,
                const ConstVectorMap& gamma, const ConstVectorMap& beta,
                Eigen::Ref<RowMatrix> x_hat, float* rstd, Eigen::Ref<RowMatrix> y);

// group_norm's backward from dy, the gradient at y: writes ∂L/∂γ, ∂L/∂β and ∂L/∂x into dx
// (which must not alias dy). Per group, ∂L/∂x = rstd · (g − mean(g) − x̂ · mean(g ⊙ x̂)) with
// g = dy ⊙ γ.
void group_norm_backward(const Eigen::Ref<const RowMatrix>& dy,
                         const Eigen::Ref<const RowMatrix>& x_hat, const float* rstd,
                         Eigen::Index groups, const ConstVectorMap& gamma, VectorMap d_gamma,
                         VectorMap d_beta, Eigen::Ref<RowMatrix> dx);

}  // namespace deixis::train
