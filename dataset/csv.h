#pragma once
// A dataset as CSV for inspection (`deixis capture csv`): one row per frame, one named column per
// value (docs/dataset.md lists them).

#include <cstddef>
#include <optional>
#include <ostream>

#include "dataset/dataset.h"

namespace deixis::dataset {

// All sequences, or only `sequence` (an index into the file; out of range: deixis::Error).
void write_csv(const Dataset& dataset, std::optional<std::size_t> sequence, std::ostream& out);

// The names of a tracking frame's columns, each after a comma: head_x … head_q_w, gaze_x …,
// then per hand (left, right) its wrist, wrist rotation and fingertip (what write_csv writes
// after its first columns, and `deixis capture bvh` after its own).
void write_tracking_column_names(std::ostream& out);

}  // namespace deixis::dataset
