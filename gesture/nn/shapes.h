#pragma once
// Sizes the paper fixes (docs/conventions.md#mpnet, #ugnet). Every network input is a window of 30
// rows (1 s at 30 Hz), oldest row first; the output refers to the newest row.

#include <array>
#include <span>

namespace deixis::nn {

inline constexpr int kWindowRows = 30;

// MPNet: 11 features per row = 5 behavioural angles, the rest distance d, 5 target features.
inline constexpr int kMpnetFeatures = 11;
inline constexpr int kMpnetTargetColumn = 6;  // first target-feature column
inline constexpr int kProgressionSize = 3;    // (gaze, deictic, idle)
inline constexpr int kMpnetWindowSize = kWindowRows * kMpnetFeatures;

// UGNet: 32 per row = end-effectors x (24) ++ avatar target feature (5) ++ progression (3). Only
// the newest row's x is read; the 8 conditioning columns of all 30 rows are.
inline constexpr int kPoseSize = 24;
inline constexpr int kConditionColumns = 8;
inline constexpr int kUgnetColumns = kPoseSize + kConditionColumns;
inline constexpr int kUgnetWindowSize = kWindowRows * kUgnetColumns;
// The vector the UGNet MoE experts, MLP and diffusion condition read: newest x ++ the 8
// conditioning columns of all rows flattened oldest first (index 24 + row·8 + k).
inline constexpr int kConditionSize = kPoseSize + kConditionColumns * kWindowRows;  // 264

// Diffusion sampling draws 30 Gaussian vectors: the initial x and one per step t = 29 … 1.
inline constexpr int kDiffusionSteps = 30;
inline constexpr int kDiffusionNoiseSize = kDiffusionSteps * kPoseSize;

using MpnetWindow = std::span<const float, kMpnetWindowSize>;
using UgnetWindow = std::span<const float, kUgnetWindowSize>;
using Progression = std::array<float, kProgressionSize>;
using PoseVector = std::array<float, kPoseSize>;
// Row 0: the initial sample; row i (1…29): the noise added after denoising step t = 30 − i.
using DiffusionNoise = std::span<const float, kDiffusionNoiseSize>;

}  // namespace deixis::nn
