#pragma once
// One recorded sequence: what a tracker reports at 30 Hz, the targets, the exact progression
// labels, and (for previews and tests only) the generator's skeleton. Datasets store the tracking,
// targets and labels; nothing downstream of the capture reads `joints`
// (docs/conventions.md#synthetic-capture).

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "capture/posture.h"
#include "core/target_map.h"
#include "core/tracking.h"
#include "dataset/category.h"
#include "dataset/schema.h"

namespace deixis::capture {

// The networks' rate (docs/conventions.md#rates-and-windows).
inline constexpr double kFrameRate = 30.0;  // Hz

// The categories a person performs and the labels a recording carries are the datasets'
// (dataset/category.h; progression (gaze, deictic, idle), paper §III.B).
using dataset::Category;
using dataset::kAllCategories;
using dataset::Labels;

struct Sequence {
  std::string subject;
  Category category = Category::kPointingSingle;
  std::uint64_t seed = 0;
  float speed = 1.0f;     // 1, or the ×0.5 / ×2 augmentation
  bool mirrored = false;  // the left–right mirror image of a recording

  BodyCalibration calibration;        // what the runtime knows of the body
  Eye dominant_eye = Eye::kRight;     // (for tests; not used by the feature code)
  std::vector<TargetObject> targets;  // static during the sequence
  std::vector<TrackingFrame> frames;  // 30 Hz; frames[i].time = i / 30
  std::vector<Labels> labels;
  std::vector<std::uint8_t> phase_keys;  // 1 where a label ramp starts or ends
  std::vector<Joints> joints;            // the generator's skeleton (empty after resampling)

  std::size_t size() const { return frames.size(); }
};

}  // namespace deixis::capture
