#pragma once
// What gaze settling (gaze_settle.h) and pointing settling (pointing_settle.h) share: a direction
// the networks gave turned the rest of the way onto this room's copy of the target, as far as
// the person's own direction is on their target in their room, and bounded.

#include <Eigen/Geometry>

#include "core/math/pose.h"

namespace deixis::presence {

struct SettleBounds {
  float full_deg;  // the person's own direction within this of their target: settle all the way
  float none_deg;  // beyond this: not at all; smooth in between
  float max_deg;   // the largest turn settling adds
};

// The turn of direction `from` toward direction `to` (any non-zero lengths): their angle, at most
// bounds.max_deg, times the person's fade (person_off_deg against bounds.full_deg and
// bounds.none_deg) and `weight` (the caller's other fades, 0..1). The angle is 0 when nothing
// applies: a zero-length direction, no turn left, or `from` exactly away from `to`. Inputs must
// be finite (the callers check).
Eigen::AngleAxisf settle_turn(const Vec3& from, const Vec3& to, float person_off_deg,
                              const SettleBounds& bounds, float weight);

}  // namespace deixis::presence
