#pragma once
// Reading recorded sequences for training: the synthetic capture's dataset files (docs/dataset.md,
// schema deixis-capture/1). Only the network columns are read (the capture computed them with
// the runtime's own feature code, gesture/features.h):
//   mpnet_features     F32 [frames, 11]    MPNet input (docs/conventions.md#mpnet-features)
//   labels             F32 [frames, 3]     progression (gaze, deictic, idle) in [0, 1]
//   end_effectors      F32 [frames, 24]    end-effectors x (docs/conventions.md#end-effectors)
//   sequence_offsets   I64 [sequences + 1] first frame of each sequence; 0 first, frames last
//   sequence_category  I32 [sequences]     paper §III.A category, 0–9 in clips.h order
// Every field is validated and every error names the file and the field: missing or mistyped
// tensors, shapes that do not agree, offsets that do not tile the frames, categories out of
// range, non-finite values, progressions outside [0, 1].

#include <filesystem>
#include <string>
#include <vector>

#include "core/io/safetensors.h"
#include "core/tracking.h"
#include "train/clips.h"

namespace deixis::train {

struct Dataset {
  std::vector<Sequence> sequences;
  std::string source;
  // Whose view the columns are in (metadata "deictic_hand"; right when absent): a left-handed
  // person's own view is the mirror image of a right-handed one's (docs/decisions.md §17).
  Hand hand = Hand::kRight;
};

Dataset read_dataset(const std::filesystem::path& path);
Dataset read_dataset(const SafetensorsFile& file);

// Writes sequences with the tensors above (a subset of the capture schema; tests, tools).
SafetensorsWriter dataset_writer(const std::vector<Sequence>& sequences);

}  // namespace deixis::train
