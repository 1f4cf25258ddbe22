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

}  // namespace deixis::dataset
