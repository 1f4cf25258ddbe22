#pragma once
// The Eigen types the fused training kernels compute with: row-major float32, as torch lays its
// tensors out, so a kernel's products run on the tensors' own memory (tensor_maps.h maps them).

#include <Eigen/Core>

namespace deixis::train {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using MatrixMap = Eigen::Map<RowMatrix>;
using ConstMatrixMap = Eigen::Map<const RowMatrix>;
using VectorMap = Eigen::Map<Eigen::RowVectorXf>;
using ConstVectorMap = Eigen::Map<const Eigen::RowVectorXf>;

}  // namespace deixis::train
