#pragma once
// Which object a tracked person looks at and which one their hand designates (the sender's side;
// paper §I: "identifying the target object of upper-body gestures is essential", which the
// authors predefined by hand). The synthetic capture and the simulator know their targets; a
// headset user does not, so `deixis xr` selects them from the tracking, tick by tick
// (docs/decisions.md 44):
//
// - Head target: the candidate nearest in angle to the gaze ray (the head's −Z when gaze is not
//   tracked), when within `acquire_deg` of it.
// - Hand target: the candidate nearest in angle to the eye–fingertip ray (H → I, the ray people
//   aim along when pointing) when the arm is extended (`pointing_reach_m`) and within
//   `acquire_deg`, or one whose surface the fingertip is within `touch_m` of. Otherwise the hand
//   target follows the head target: people look at what they are about to point at, so when the
//   hand starts to rise the target is already the one the gesture will end on (MPNet reads the
//   angles to the target from the first frame of the window).
// - Hysteresis: a new candidate replaces the current one only when it is nearer by
//   `switch_margin_deg`, so two objects close together do not make the target flicker.
// - Candidates: the room's objects and the other person (kPartnerTarget) at their head; in a
//   room of several people, its people (person_target(id), core/target_map.h) at their heads,
//   the user's own id excepted.
//
// Nothing is allocated; state is the current pair of targets.

#include <span>

#include "core/target_map.h"
#include "core/tracking.h"

namespace deixis {

struct TargetSelectionConfig {
  Hand deictic_hand = Hand::kRight;
  float acquire_deg = 12.0f;
  float switch_margin_deg = 2.0f;
  float touch_m = 0.04f;
  // A pointing ray counts only with the arm extended: the fingertip at least this far from the
  // eyes (pointing puts it 0.55–0.7 m away for a 74 cm arm; gesturing and resting hands stay
  // nearer). Set from the calibration's arm length (0.6 of it).
  float pointing_reach_m = 0.45f;
  // A hand target other than what the eyes are on must hold this many ticks first: a reach sweeps
  // the ray past other objects on its way (0.2 s at 30 Hz).
  int dwell_ticks = 6;
};

// What a user can designate: the room's objects, the other person of a direct session (null in
// a room of several people, where nobody is "the other person") and the room's people by id,
// their heads where this room shows them (`self`, the user's own id, is never a candidate).
// In a direct session the targets stay the other person (kPartnerTarget) until a candidate is
// designated; in a room they are nothing (kNoTarget: nothing_designated_point, core/target_map.h),
// and so is a target that left the room.
struct SelectionCandidates {
  const TargetMap* map = nullptr;
  const Vec3* partner_head = nullptr;
  std::span<const PersonTarget> people;
  PersonId self = kNoPerson;
};

// The configuration for a calibrated person: their deictic hand and pointing reach.
TargetSelectionConfig target_selection_for(const BodyCalibration& body);

struct TargetSelector {
  TargetSelectionConfig config;
  TargetId head_target = kPartnerTarget;
  TargetId hand_target = kPartnerTarget;
  TargetId pending_hand_target = kNoTarget;  // a candidate the eyes are not on, and for how long
  int pending_ticks = 0;

  // Fills frame.head_target, hand_target and their positions from the frame's head, gaze and
  // deictic hand and the candidates. Untracked parts keep their previous targets.
  void select(TrackingFrame& frame, const SelectionCandidates& candidates);
  // A direct two-site session: this room's objects and where the other person's head is.
  void select(TrackingFrame& frame, const TargetMap& room, const Vec3& partner_head) {
    select(frame, SelectionCandidates{&room, &partner_head, {}, kNoPerson});
  }
};

}  // namespace deixis
