#pragma once
// Touch contact (docs/decisions.md §33): UGNet brings the avatar's fingertip to a touch target
// within a few centimetres, and a finger that hovers 3–7 cm off the object it touches reads as a
// miss to the person watching. So once the deictic gesture is nearly complete and the fingertip is
// already close to the designated object's surface, the hand is moved the remaining way onto the
// surface, fading in with the progression and out with the distance. Pointing at far objects is
// untouched (the fingertip is nowhere near them), so are free-form gestures (deictic progression
// low) and moments where the user's own pose is shown (hand blend weight 1).

#include "core/target_map.h"
#include "core/tracking.h"

namespace deixis::presence {

struct TouchContactConfig {
  float radius = 0.12f;  // m (for a 1.70 m avatar; scaled with its height): beyond, no contact
  float onset = 0.5f;    // deictic progression where contact starts to fade in; full at 1
};

// The offset (world) to add to the deictic wrist and fingertip targets so that the fingertip
// `index_tip` rests on `object` (zero when contact does not apply or `object` is null).
Vec3 touch_contact_offset(const Vec3& index_tip, const TargetObject* object,
                          float deictic_progression, float hand_weight, float radius,
                          const TouchContactConfig& config = {});

}  // namespace deixis::presence
