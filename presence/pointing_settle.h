#pragma once
// Pointing settling (docs/decisions.md §91): UGNet turns the avatar's pointing toward this room's
// copy of what the person points at, but not always onto it: for targets below the synthetic
// capture's range (steeper than 35° under the eyes) the avatar's eye → fingertip ray ends up to
// 7° off, and someone in that room reads that as pointing at something else (docs/live-rooms.md).
// The person's own tracking says exactly when they are on their target (MPNet's IT^R feature:
// their eye → fingertip ray against the ray to their target), so while they are, and while the
// networks read the gesture as deictic, the avatar's hand turns the remaining way about its eyes
// onto this room's copy, the wrist and the fingertip together, as a person makes the last small
// correction of an arm that has arrived. It is the pointing counterpart of gaze settling
// (gaze_settle.h): it fades out as the person's finger leaves their target or as the deictic
// progression falls, the turn is bounded (the networks' arm motion stays what the watcher sees;
// an arm far off is the networks' to answer for), free movement shown as the user's own pose
// (hand blend weight 1) is untouched, and the networks never see it (it is not fed back).

#include "core/math/pose.h"

namespace deixis::presence {

struct PointingSettleConfig {
  // The person's eye → fingertip ray within `full_deg` of their target in their room: the
  // avatar's hand settles all the way (up to max_deg); beyond `none_deg`: not at all; smooth in
  // between.
  float full_deg = 5.0f;
  float none_deg = 15.0f;
  float max_deg = 10.0f;  // the largest turn settling adds to the networks' pointing
  float onset = 0.5f;     // deictic progression where settling starts to fade in; full at 1
};

// The rotation (world, about `eyes`) to apply to the deictic wrist and fingertip so that the
// ray from the avatar's eyes `eyes` through `index_tip` settles onto `target` (world; null when
// this room has no copy of what the person points at: the identity), when the person's own ray is
// `person_off_deg` from their target in their room. Identity when settling does not apply.
Mat3 pointing_settle_rotation(const Vec3& index_tip, const Vec3& eyes, const Vec3* target,
                              float person_off_deg, float deictic_progression, float hand_weight,
                              const PointingSettleConfig& config = {});

}  // namespace deixis::presence
