#pragma once
// The encoder half of the FMD autoencoder (paper §V.A; docs/eval.md#what-each-number-is): a
// 30-frame segment of head and hand motion (18 values per frame: head 6D + position, hand 6D +
// position, x[3..20]) → a 128-d latent code:
//   Conv1d(18 → 256, kernel 15) → ReLU → Conv1d(256 → 128, kernel 16); lengths 30 → 16 → 1.
// Tensor names as the authors' ConvolutionalAutoEncoder (conv_encode1.*, conv_encode2.*); the
// weights are trained by deixis-train on the training subject (the authors' file is missing from
// their release, docs/conventions.md#authors-checkpoints). Like the other networks: shared
// read-only weights, const run(), no allocation.

#include <array>
#include <filesystem>
#include <memory>
#include <span>

#include "core/io/safetensors.h"

namespace deixis::nn {

inline constexpr int kMotionSegmentFrames = 30;
inline constexpr int kMotionChannels = 18;
inline constexpr int kMotionSegmentSize = kMotionSegmentFrames * kMotionChannels;
inline constexpr int kMotionCodeSize = 128;
using MotionCode = std::array<float, kMotionCodeSize>;

// What the paper reports for its own encoder (§V), per hand (the left one trained on mirrored
// motion and validated on the left-handed subjects): per-frame position (cm) and rotation (°)
// error of head and hand on the training subject and on the validation subjects. deixis-train's
// log and deixis eval's notes set ours beside these.
struct PaperReconstruction {
  double training_cm, training_deg, validation_cm, validation_deg;
};
inline constexpr PaperReconstruction kPaperReconstructionRight{0.38, 0.97, 1.29, 3.90};
inline constexpr PaperReconstruction kPaperReconstructionLeft{0.38, 0.95, 1.57, 3.96};

class MotionEncoder {
 public:
  static MotionEncoder load(const SafetensorsFile& file);
  static MotionEncoder load(const std::filesystem::path& path);

  // `segment`: 30 frames × 18 channels, frame-major (oldest first).
  MotionCode run(std::span<const float, kMotionSegmentSize> segment) const noexcept;

  struct Weights;

 private:
  explicit MotionEncoder(std::shared_ptr<const Weights> weights) : weights_(std::move(weights)) {}
  std::shared_ptr<const Weights> weights_;
};

}  // namespace deixis::nn
