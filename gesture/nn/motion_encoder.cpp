#include "gesture/nn/motion_encoder.h"

#include "gesture/nn/params.h"

namespace deixis::nn {

namespace {

constexpr int kHidden = 256;
constexpr int kKernel1 = 15;
constexpr int kKernel2 = 16;
constexpr int kLength1 = kMotionSegmentFrames - kKernel1 + 1;  // 16
static_assert(kLength1 - kKernel2 + 1 == 1, "the second convolution reduces to one position");

}  // namespace

// Conv1d weights [out, in, kernel] are re-laid out at load as [out, kernel·in] so that each output
// position is one matrix-vector product over a contiguous window of frame-major input.
struct MotionEncoder::Weights {
  MatrixParam<kHidden, kKernel1 * kMotionChannels> conv1;
  VectorParam<kHidden> bias1;
  MatrixParam<kMotionCodeSize, kKernel2 * kHidden> conv2;
  VectorParam<kMotionCodeSize> bias2;
};

namespace {

template <int Out, int In, int Kernel>
void load_conv(const SafetensorsFile& file, const std::string& name,
               MatrixParam<Out, Kernel * In>& dst) {
  const std::int64_t shape[] = {Out, In, Kernel};
  const std::vector<float> w = file.read_f32(name, shape);
  auto out = dst.storage();
  for (int o = 0; o < Out; ++o) {
    for (int i = 0; i < In; ++i) {
      for (int k = 0; k < Kernel; ++k) {
        out[(static_cast<std::size_t>(o) * Kernel + k) * In + i] =
            w[(static_cast<std::size_t>(o) * In + i) * Kernel + k];
      }
    }
  }
}

}  // namespace

MotionEncoder MotionEncoder::load(const SafetensorsFile& file) {
  auto w = std::make_shared<Weights>();
  load_conv<kHidden, kMotionChannels, kKernel1>(file, "conv_encode1.weight", w->conv1);
  load_vector(file, "conv_encode1.bias", w->bias1);
  load_conv<kMotionCodeSize, kHidden, kKernel2>(file, "conv_encode2.weight", w->conv2);
  load_vector(file, "conv_encode2.bias", w->bias2);
  return MotionEncoder(std::move(w));
}

MotionEncoder MotionEncoder::load(const std::filesystem::path& path) {
  return load(SafetensorsFile::read(path));
}

MotionCode MotionEncoder::run(std::span<const float, kMotionSegmentSize> segment) const noexcept {
  const Weights& w = *weights_;
  // Hidden activations frame-major: position p holds 256 channels, contiguous for conv2.
  Eigen::Matrix<float, kLength1 * kHidden, 1> hidden;
  for (int p = 0; p < kLength1; ++p) {
    const Eigen::Map<const Eigen::Matrix<float, kKernel1 * kMotionChannels, 1>> window(
        segment.data() + p * kMotionChannels);
    auto h = hidden.segment<kHidden>(p * kHidden);
    h.noalias() = w.conv1.view() * window;
    h += w.bias1.view();
    h = h.cwiseMax(0.0f);
  }
  MotionCode code;
  Eigen::Map<Eigen::Matrix<float, kMotionCodeSize, 1>> out(code.data());
  out.noalias() = w.conv2.view() * hidden;
  out += w.bias2.view();
  return code;
}

}  // namespace deixis::nn
