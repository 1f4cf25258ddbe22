#include "train/conv_as_matmul.h"

namespace deixis::train {

torch::Tensor conv1d_as_matmul(const torch::Tensor& x, const torch::Tensor& weight,
                               const torch::Tensor& bias) {
  const std::int64_t batch = x.size(0), channels = x.size(2);
  const std::int64_t outputs = weight.size(0), kernel = weight.size(2);
  const std::int64_t length = x.size(1) - kernel + 1;
  // unfold(1, K, 1): [B, L, C, K], the C-major, K-minor order of a row of the weight [O, C·K].
  const torch::Tensor windows = x.unfold(1, kernel, 1).reshape({batch, length, channels * kernel});
  return torch::matmul(windows, weight.reshape({outputs, channels * kernel}).t()) + bias;
}

torch::Tensor conv_transpose1d_as_matmul(const torch::Tensor& x, const torch::Tensor& weight,
                                         const torch::Tensor& bias) {
  const std::int64_t batch = x.size(0), length = x.size(1), inputs = x.size(2);
  const std::int64_t outputs = weight.size(1), kernel = weight.size(2);
  const std::int64_t frames = length + kernel - 1;
  // Each input frame's contribution, O·K values in the weight's O-major, K-minor order.
  const torch::Tensor contributions = torch::matmul(x, weight.reshape({inputs, outputs * kernel}));
  torch::Tensor y;
  if (length == 1) {
    y = contributions.reshape({batch, outputs, kernel});  // nothing overlaps
  } else {
    // fold (col2im) sums the overlapping contributions: columns [B, O·K, L] → [B, O, 1, T].
    namespace F = torch::nn::functional;
    y = F::fold(contributions.permute({0, 2, 1}), F::FoldFuncOptions({1, frames}, {1, kernel}))
            .reshape({batch, outputs, frames});
  }
  return y.permute({0, 2, 1}) + bias;
}

}  // namespace deixis::train
