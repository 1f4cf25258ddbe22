#pragma once
// Gaze settling (docs/decisions.md §70): UGNet turns the avatar's eyes toward this room's copy of
// what the person looks at, but not always onto it: in rooms whose layouts mirror each other the
// avatar's gaze at a person ends 6–11° off (§68), and someone in that room reads that as looking
// past them. The person's own eyes say exactly when they are on their target (their tracking
// carries both), so while they are, the avatar's eyes turn the remaining way onto this room's
// copy, as a person's eyes make the last small correction after the head has turned. It fades
// out as the person's gaze leaves their target; the turn is bounded (the networks' head and eye
// motion stays what the watcher sees; a gaze far off is the networks' to answer for); free
// movement shown as the user's own pose (head blend weight 1) is untouched; and the networks
// never see it (it is not fed back).

#include "core/tracking.h"

namespace deixis::presence {

struct GazeSettleConfig {
  // The person's gaze within `full_deg` of their target in their room: the avatar's eyes settle
  // all the way (up to max_deg); beyond `none_deg`: not at all; smooth in between.
  float full_deg = 5.0f;
  float none_deg = 15.0f;
  float max_deg = 15.0f;  // the largest turn settling adds to the networks' gaze
};

// The avatar's gaze (unit, world) after settling `gaze` from the eyes at `eyes` onto `target`
// (world; null when this room has no copy of what the person looks at: `gaze` unchanged), when
// the person's own gaze is `person_off_deg` from their target in their room.
Vec3 settled_gaze(const Vec3& gaze, const Vec3& eyes, const Vec3* target, float person_off_deg,
                  float head_weight, const GazeSettleConfig& config = {});

}  // namespace deixis::presence
