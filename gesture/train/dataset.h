#pragma once
// Reading recorded sequences for training from safetensors dataset files.
//
// Layout read here (one file per subject and hand; all sequences' frames concatenated, frame-
// major, network frame, 30 Hz):
//   features           F32 [frames, 11]   MPNet input per frame (DESIGN §4)
//   progression        F32 [frames, 3]    labels (gaze, deictic, idle) in [0, 1]
//   pose               F32 [frames, 24]   end-effectors x (DESIGN §4)
//   sequence_frames    I64 [sequences]    frames of each sequence, in order; they sum to frames
//   sequence_category  I64 [sequences]    paper §III.A category, 0–9 in clips.h order
// Every field is validated and every error names the file and the field: missing or mistyped
// tensors, shapes that do not agree, counts that do not add up, categories out of range,
// non-finite values, progressions outside [0, 1].

#include <filesystem>
#include <string>
#include <vector>

#include "gesture/io/safetensors.h"
#include "gesture/train/clips.h"

namespace deixis::train {

struct Dataset {
  std::vector<Sequence> sequences;
  std::string source;
};

Dataset read_dataset(const std::filesystem::path& path);
Dataset read_dataset(const SafetensorsFile& file);

// Writes sequences in the layout above (tests, tools).
SafetensorsWriter dataset_writer(const std::vector<Sequence>& sequences);

}  // namespace deixis::train
