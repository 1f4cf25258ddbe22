#pragma once
// Eigen views of contiguous float32 torch tensors, for the fused training kernels (fused_*.cpp):
// their products run on the tensors' own memory, row-major as torch lays them out.

#include "train/row_matrix.h"

#include <torch/types.h>

namespace deixis::train {

// t's memory from `offset` floats on as a rows × cols row-major matrix; t must be contiguous.
inline ConstMatrixMap map(const torch::Tensor& t, Eigen::Index rows, Eigen::Index cols,
                          Eigen::Index offset = 0) {
  return ConstMatrixMap(t.data_ptr<float>() + offset, rows, cols);
}
inline MatrixMap map_mut(torch::Tensor& t, Eigen::Index rows, Eigen::Index cols,
                         Eigen::Index offset = 0) {
  return MatrixMap(t.data_ptr<float>() + offset, rows, cols);
}
inline ConstVectorMap vec(const torch::Tensor& t) {
  return ConstVectorMap(t.data_ptr<float>(), t.numel());
}
inline VectorMap vec_mut(torch::Tensor& t) {
  return VectorMap(t.data_ptr<float>(), t.numel());
}

}  // namespace deixis::train
