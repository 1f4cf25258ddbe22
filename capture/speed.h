#pragma once
// Speed augmentation (paper §III.C; docs/conventions.md#training-data): a sequence played ×0.5 or
// ×2 by monotone cubic (PCHIP) resampling over its normalised time, as the authors did for the
// single- and two-target categories. Positions, rotation matrices (re-orthonormalised), gaze
// (renormalised) and labels are resampled; fingertips are recomposed from the resampled wrists so
// the hand stays rigid; targets and phase keys go to the nearest frame. Resample clean sequences
// (before tracker noise): noise is a property of the tracker, not of the motion's speed.

#include "capture/sequence.h"

namespace deixis::capture {

// `speed` > 0: 2 plays twice as fast (half the frames), 0.5 half as fast. The result has
// floor(n / speed) frames (at least 2) at 30 Hz and no skeleton.
Sequence resample_speed(const Sequence& sequence, float speed);

}  // namespace deixis::capture
