#pragma once
// The dataset files' schema (docs/dataset.md): its name, and the widths of the columns the
// networks read. The writer's callers compute those columns with gesture/features.h (capture/
// static_asserts that the widths agree); dataset/ stores and validates them.

#include <array>

#include "core/math/network_frame.h"

namespace deixis::dataset {

// Metadata "schema" of every dataset file.
inline constexpr const char* kSchema = "deixis-capture/1";

// mpnet_features: MPNet's 11 features (docs/conventions.md#mpnet-features).
inline constexpr int kFeatureColumns = 11;
// target_feature = mpnet_features[:, 6:11].
inline constexpr int kTargetFeatureColumn = 6;
inline constexpr int kTargetFeatureColumns = kTargetFeatureSize;
static_assert(kTargetFeatureColumn + kTargetFeatureColumns == kFeatureColumns);
// end_effectors: x (docs/conventions.md#end-effectors).
inline constexpr int kEndEffectorColumns = kEndEffectorSize;
// labels: progression (gaze, deictic, idle), each in [0, 1] (paper §III.B).
inline constexpr int kLabelColumns = 3;
using Labels = std::array<float, kLabelColumns>;

}  // namespace deixis::dataset
