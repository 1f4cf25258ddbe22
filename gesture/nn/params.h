#pragma once
// Weight storage for the fixed-size networks. The paper fixes every size, so every parameter has
// its shape in its type; storage is one aligned heap block per parameter, allocated once at load,
// and read through fixed-size Eigen maps (Eigen's fixed-size matrices themselves are limited to
// 128 KiB, and UGNet's experts are 1.4 MB). After loading, a parameter is only read.

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "core/io/safetensors.h"

namespace deixis::nn {

using AlignedFloats = std::vector<float, Eigen::aligned_allocator<float>>;

// A Rows × Cols matrix stored row-major, as PyTorch stores a contiguous 2-D tensor.
template <int Rows, int Cols>
class MatrixParam {
 public:
  using Matrix = Eigen::Matrix<float, Rows, Cols, (Cols == 1 ? Eigen::ColMajor : Eigen::RowMajor)>;
  using View = Eigen::Map<const Matrix, Eigen::AlignedMax>;
  static constexpr int kRows = Rows;
  static constexpr int kCols = Cols;

  MatrixParam() : data_(static_cast<std::size_t>(Rows) * Cols, 0.0f) {}
  View view() const { return View(data_.data()); }
  std::span<float> storage() { return data_; }
  std::span<const float> storage() const { return data_; }

 private:
  AlignedFloats data_;
};

template <int Size>
using VectorParam = MatrixParam<Size, 1>;

// dst = srcᵀ (both row-major).
template <int Rows, int Cols>
void transpose_into(const MatrixParam<Rows, Cols>& src, MatrixParam<Cols, Rows>& dst) {
  auto out = dst.storage();
  const auto in = src.storage();
  for (int r = 0; r < Rows; ++r) {
    for (int c = 0; c < Cols; ++c) {
      out[static_cast<std::size_t>(c) * Rows + r] = in[static_cast<std::size_t>(r) * Cols + c];
    }
  }
}

// Loads a tensor of exactly `shape` (which must hold Rows × Cols values) into `param`.
template <int Rows, int Cols>
void load_param(const SafetensorsFile& file, const std::string& name,
                std::initializer_list<std::int64_t> shape, MatrixParam<Rows, Cols>& param) {
  file.copy_f32(name, std::span<const std::int64_t>(shape.begin(), shape.size()), param.storage());
}

// Shorthands for PyTorch's 2-D and 1-D tensors.
template <int Rows, int Cols>
void load_matrix(const SafetensorsFile& file, const std::string& name,
                 MatrixParam<Rows, Cols>& param) {
  load_param(file, name, {Rows, Cols}, param);
}
template <int Size>
void load_vector(const SafetensorsFile& file, const std::string& name, VectorParam<Size>& param) {
  load_param(file, name, {Size}, param);
}

}  // namespace deixis::nn
