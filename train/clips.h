#pragma once
// From recorded sequences to the training examples of each network
// (docs/conventions.md#training-data, the authors' data_parser.py):
//   - a clip is 45 consecutive rows; clips start every 7 rows, plus the last 45 rows of each
//     sequence (stored first, as the authors do);
//   - MPNet rows: the 11 features ++ the 3 progression labels of the same frame (14);
//   - UGNet rows: [x_i (24), target feature_{i+1} (5), progression_{i+1} (3), x_{i+1} (24)] (56):
//     the condition and the label come from the frame being predicted. For categories with
//     free-form movement the target x_{i+1} holds x_i's head part (gaze, head) where the next
//     frame's gaze progression is 0 and its hand part (hand, fingertip) where the deictic
//     progression is 0 (paper §IV.B, the "free-form hold");
//   - FMD segments: 30 rows of head and hand (x[3..20], 18 values), hop 15, plus the last 30.
// Everything here is plain arrays: no libtorch.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "dataset/category.h"
#include "dataset/dataset.h"

namespace deixis::train {

// The ten categories of paper §III.A, as the datasets store them (dataset/category.h).
using dataset::Category;
using dataset::kCategoryCount;

// The dataset's columns (dataset/schema.h).
inline constexpr int kFeatureColumns = dataset::kFeatureColumns;            // MPNet input per frame
inline constexpr int kTargetFeatureColumn = dataset::kTargetFeatureColumn;  // of the 11
inline constexpr int kProgressionColumns = dataset::kLabelColumns;          // gaze, deictic, idle
inline constexpr int kPoseColumns = dataset::kEndEffectorColumns;           // end-effectors x
inline constexpr int kMpnetClipColumns = kFeatureColumns + kProgressionColumns;  // 14
inline constexpr int kUgnetClipColumns = kPoseColumns + 5 + 3 + kPoseColumns;    // 56
inline constexpr int kMotionColumns = 18;  // head 6D + position, hand 6D + position: x[3..20]
inline constexpr int kMotionFirstColumn = 3;

// One recorded take, frame-major, in the network frame (docs/conventions.md#network-frame).
struct Sequence {
  Category category = Category::kPointingSingle;
  int frames = 0;
  std::vector<float> features;     // frames × 11
  std::vector<float> progression;  // frames × 3
  std::vector<float> pose;         // frames × 24
};

// The sequences of a dataset file (docs/dataset.md), in the view of the file's hand
// (`file.hand`): its network columns and labels, in file order.
std::vector<Sequence> training_sequences(const dataset::Dataset& file);

// Rows × columns × count floats, example-major.
struct ExampleSet {
  int rows = 0;
  int columns = 0;
  std::size_t count = 0;
  std::vector<float> values;

  std::span<const float> example(std::size_t i) const;
  std::size_t example_size() const { return static_cast<std::size_t>(rows) * columns; }
};

// Start rows of the clips of a sequence of `frames` rows: the last clip first, then every `hop`
// rows from 0 (torch.unfold). Empty when the sequence is shorter than one clip.
std::vector<int> clip_starts(int frames, int clip_rows, int hop);

ExampleSet mpnet_clips(std::span<const Sequence> sequences);
ExampleSet ugnet_clips(std::span<const Sequence> sequences);
ExampleSet motion_segments(std::span<const Sequence> sequences);

// Left-handed training data (paper §III.C, docs/conventions.md#left-hand-mirroring): the mirror
// image through the y–z plane. Negates x of the eight 3-vectors of every pose and both θ of the
// target feature.
void mirror(Sequence& sequence);

}  // namespace deixis::train
