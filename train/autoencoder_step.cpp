#include "train/autoencoder_step.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace deixis::train {

namespace {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using MatrixMap = Eigen::Map<RowMatrix>;
using ConstMatrixMap = Eigen::Map<const RowMatrix>;
using RowVectorMap = Eigen::Map<Eigen::RowVectorXf>;
using ConstRowVectorMap = Eigen::Map<const Eigen::RowVectorXf>;

template <typename... Extent>
std::size_t size(Extent... extents) {
  return (static_cast<std::size_t>(extents) * ...);
}

// The one index of the unfolded matrices: a (channel, tap) column, torch's weight order.
std::size_t tap(int channel, int kernel, int k) {
  return size(channel, kernel) + size(k);
}

}  // namespace

AutoencoderStep::LayerShape AutoencoderStep::layer_shape(int i) {
  // conv_encode1, conv_encode2, conv_decode2, conv_decode1.
  static constexpr LayerShape kLayers[4] = {{false, kFrames, 16, kChannels, 256, 15},
                                            {false, 16, 1, 256, 128, 16},
                                            {true, 1, 16, 128, 256, 16},
                                            {true, 16, kFrames, 256, kChannels, 15}};
  if (i < 0 || i > 3) {
    throw Error("AutoencoderStep: there is no layer " + std::to_string(i));
  }
  return kLayers[i];
}

std::size_t AutoencoderStep::parameter_count() {
  std::size_t n = 0;
  for (int i = 0; i < 4; ++i) {
    const LayerShape l = layer_shape(i);
    n += size(l.in_channels, l.out_channels, l.kernel) + size(l.out_channels);
  }
  return n;
}

AutoencoderStep::AutoencoderStep(int max_batch) : max_batch_(max_batch) {
  if (max_batch < 1) {
    throw Error("AutoencoderStep: the batch must hold at least one segment");
  }
  std::size_t widest_columns = 0, widest_frames = 0;
  for (int i = 0; i < 4; ++i) {
    Layer& l = layers_[i];
    static_cast<LayerShape&>(l) = layer_shape(i);
    const std::size_t columns = l.transposed
                                    ? size(max_batch, l.in_frames, l.out_channels, l.kernel)
                                    : size(max_batch, l.out_frames, l.in_channels, l.kernel);
    l.columns.resize(columns);
    l.output.resize(size(max_batch, l.out_frames, l.out_channels));
    widest_columns = std::max(widest_columns, columns);
    widest_frames =
        std::max({widest_frames, l.output.size(), size(max_batch, l.in_frames, l.in_channels)});
  }
  d_output_.resize(widest_frames);
  d_input_.resize(widest_frames);
  d_columns_.resize(widest_columns);
}

std::span<const float> AutoencoderStep::reconstruction() const {
  return {layers_[3].output.data(), size(batch_, kFrames, kChannels)};
}

// Conv1d: unfold the input's K-frame windows into rows, one product with the weight [O, C·K].
// ConvTranspose1d: one product of the input with the weight [I, O·K], then every input frame
// adds its K frames into the output (overlap-add).
void AutoencoderStep::layer_forward(Layer& l, const float* input, const float* weight,
                                    const float* bias, bool relu) {
  const int batch = batch_;
  const auto out_rows = static_cast<Eigen::Index>(size(batch, l.out_frames));
  MatrixMap out(l.output.data(), out_rows, l.out_channels);
  const ConstRowVectorMap b(bias, l.out_channels);
  if (!l.transposed) {
    const int width = l.in_channels * l.kernel;
    for (int s = 0; s < batch; ++s) {
      for (int t = 0; t < l.out_frames; ++t) {
        float* row = l.columns.data() + size(s * l.out_frames + t, width);
        for (int k = 0; k < l.kernel; ++k) {
          const float* frame = input + size(s * l.in_frames + t + k, l.in_channels);
          for (int c = 0; c < l.in_channels; ++c) {
            row[tap(c, l.kernel, k)] = frame[c];
          }
        }
      }
    }
    out.noalias() = ConstMatrixMap(l.columns.data(), out_rows, width) *
                    ConstMatrixMap(weight, l.out_channels, width).transpose();
    out.rowwise() += b;
  } else {
    const int width = l.out_channels * l.kernel;
    const auto in_rows = static_cast<Eigen::Index>(size(batch, l.in_frames));
    MatrixMap products(l.columns.data(), in_rows, width);
    products.noalias() = ConstMatrixMap(input, in_rows, l.in_channels) *
                         ConstMatrixMap(weight, l.in_channels, width);
    out.rowwise() = b;
    for (int s = 0; s < batch; ++s) {
      for (int t = 0; t < l.in_frames; ++t) {
        const float* row = l.columns.data() + size(s * l.in_frames + t, width);
        for (int k = 0; k < l.kernel; ++k) {
          float* frame = l.output.data() + size(s * l.out_frames + t + k, l.out_channels);
          for (int o = 0; o < l.out_channels; ++o) {
            frame[o] += row[tap(o, l.kernel, k)];
          }
        }
      }
    }
  }
  if (relu) {
    out = out.cwiseMax(0.0f);
  }
}

void AutoencoderStep::layer_backward(Layer& l, const float* input, const float* weight,
                                     float* d_weight, float* d_bias, bool want_input) {
  const int batch = batch_;
  const auto out_rows = static_cast<Eigen::Index>(size(batch, l.out_frames));
  const ConstMatrixMap d_out(d_output_.data(), out_rows, l.out_channels);
  RowVectorMap(d_bias, l.out_channels) = d_out.colwise().sum();
  if (!l.transposed) {
    const int width = l.in_channels * l.kernel;
    const ConstMatrixMap columns(l.columns.data(), out_rows, width);
    MatrixMap(d_weight, l.out_channels, width).noalias() = d_out.transpose() * columns;
    if (!want_input) {
      return;
    }
    MatrixMap d_columns(d_columns_.data(), out_rows, width);
    d_columns.noalias() = d_out * ConstMatrixMap(weight, l.out_channels, width);
    // Fold: each input frame collects the taps that read it.
    std::fill_n(d_input_.begin(), size(batch, l.in_frames, l.in_channels), 0.0f);
    for (int s = 0; s < batch; ++s) {
      for (int t = 0; t < l.out_frames; ++t) {
        const float* row = d_columns_.data() + size(s * l.out_frames + t, width);
        for (int k = 0; k < l.kernel; ++k) {
          float* frame = d_input_.data() + size(s * l.in_frames + t + k, l.in_channels);
          for (int c = 0; c < l.in_channels; ++c) {
            frame[c] += row[tap(c, l.kernel, k)];
          }
        }
      }
    }
  } else {
    const int width = l.out_channels * l.kernel;
    const auto in_rows = static_cast<Eigen::Index>(size(batch, l.in_frames));
    // Unfold ∂L/∂output the way the forward folded the products.
    for (int s = 0; s < batch; ++s) {
      for (int t = 0; t < l.in_frames; ++t) {
        float* row = d_columns_.data() + size(s * l.in_frames + t, width);
        for (int k = 0; k < l.kernel; ++k) {
          const float* frame = d_output_.data() + size(s * l.out_frames + t + k, l.out_channels);
          for (int o = 0; o < l.out_channels; ++o) {
            row[tap(o, l.kernel, k)] = frame[o];
          }
        }
      }
    }
    const ConstMatrixMap d_columns(d_columns_.data(), in_rows, width);
    const ConstMatrixMap in(input, in_rows, l.in_channels);
    MatrixMap(d_weight, l.in_channels, width).noalias() = in.transpose() * d_columns;
    if (!want_input) {
      return;
    }
    MatrixMap(d_input_.data(), in_rows, l.in_channels).noalias() =
        d_columns * ConstMatrixMap(weight, l.in_channels, width).transpose();
  }
}

double AutoencoderStep::forward(const AutoencoderBuffers& p, const float* segments, int count,
                                int whole_batch) {
  if (count < 1 || count > max_batch_) {
    throw Error("AutoencoderStep: " + std::to_string(count) + " segments, the buffers hold 1 to " +
                std::to_string(max_batch_));
  }
  if (whole_batch == 0) {
    whole_batch = count;
  }
  if (whole_batch < count) {
    throw Error("AutoencoderStep: a slice of " + std::to_string(count) +
                " segments of a batch of " + std::to_string(whole_batch));
  }
  batch_ = count;
  segments_ = segments;
  const float* input = segments;
  for (int i = 0; i < 4; ++i) {
    layer_forward(layers_[i], input, p.weight[i], p.bias[i], i == 0 || i == 2);
    input = layers_[i].output.data();
  }
  // L1 loss against the input and its gradient (torch: mean |y − x|, sgn(0) = 0).
  const std::size_t n = size(count, kFrames, kChannels);
  const float scale = 1.0f / static_cast<float>(size(whole_batch, kFrames, kChannels));
  double loss = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const float difference = layers_[3].output[i] - segments[i];
    loss += std::abs(static_cast<double>(difference));
    d_output_[i] = difference > 0.0f ? scale : (difference < 0.0f ? -scale : 0.0f);
  }
  return loss / static_cast<double>(size(whole_batch, kFrames, kChannels));
}

void AutoencoderStep::backward(const AutoencoderBuffers& p, const AutoencoderBuffers& g) {
  for (int i = 3; i >= 0; --i) {
    Layer& l = layers_[i];
    if (i == 0 || i == 2) {
      // Through the ReLU: its output is 0 exactly where it cut.
      const std::size_t n = size(batch_, l.out_frames, l.out_channels);
      for (std::size_t j = 0; j < n; ++j) {
        d_output_[j] = l.output[j] > 0.0f ? d_output_[j] : 0.0f;
      }
    }
    const float* input = i == 0 ? segments_ : layers_[i - 1].output.data();
    layer_backward(l, input, p.weight[i], g.weight[i], g.bias[i], i > 0);
    std::swap(d_output_, d_input_);
  }
}

}  // namespace deixis::train
