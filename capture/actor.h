#pragma once
// The behaviours a recorded person performs, each planned as minimum-jerk moves on the motion's
// tracks with its progression labels written alongside (labelling.h):
//
//   gaze shift   the eyes lead with a saccade (duration by the main sequence, Bahill et al.
//                1975); the head starts a few tens of ms later and takes a share of the amplitude
//                that grows with it (none inside the eye-only range), so the eyes stay within
//                their range; gaze is settled when the head stops.
//   point/touch  the hand leaves 50–150 ms after the eyes (eye–hand coordination), reaching its
//                completion state (completion.h) by a minimum-jerk path with Fitts-like duration;
//                the torso twists toward the target and, for touches out of reach, leans.
//   gesticulate  free-form strokes and beats in the gesture space in front of the chest
//                (McNeill 1992), palm orientations varied.
//   look freely  free-form gaze shifts around the scene.
//   rest         back to the upright posture; idle rises over the next 0.5 s.

#include <optional>

#include "capture/labelling.h"
#include "capture/motion.h"
#include "core/target_map.h"

namespace deixis::capture {

struct GazeShift {
  double onset = 0;
  double settled = 0;
};
struct Reach {
  double onset = 0;     // the hand starts moving
  double complete = 0;  // completion state
};

// The torso a touch of `target` needs: twisted toward it and leaning forward only as far as the
// wrist needs to be within reach. Empty when even a 23° lean does not bring it within reach.
std::optional<TorsoKey> touch_torso(const Motion& motion, const TargetObject& target);
// The torso twist toward a target (a small share of its azimuth).
float twist_toward(const Motion& motion, const Vec3& target);

class Actor {
 public:
  Actor(Motion& motion, Labelling& labels, Random& rng);

  // Gaze (eyes and head) to a target that becomes the head target at `t`; labelled.
  GazeShift look_at(double t, const TargetObject& target);
  // Points at / touches `target` (the hand target from `t`), optionally looking at it too.
  Reach point(double t, const TargetObject& target, bool with_gaze);
  Reach touch(double t, const TargetObject& target, bool with_gaze);
  // Free-form hand movement for `duration`; returns when the last stroke ends. Strokes keep the
  // fingertip away from `hand_target` (a free-form gesture that touched or pointed at the target
  // would be a deictic gesture, and its label would lie).
  // `next_hand_target`, when given, becomes the hand target as the first stroke starts (its
  // progression is 0 from then on; otherwise the deictic label falls during the first stroke).
  double gesticulate(double t, double duration, bool both_hands, const Vec3& hand_target,
                     TargetId next_hand_target = kNoTarget);
  // Free-form gaze for `duration` (the gaze label falls during the first shift), never toward
  // `head_target`, for the same reason.
  double look_freely(double t, double duration, const Vec3& head_target);
  // Small head movements while the eyes stay on their fixation (listening, explaining).
  double nod(double t, double duration);
  // Back to the upright posture; returns when idle reaches 1.
  double rest(double t);

 private:
  GazeShift shift_gaze(double t, const GazeKey& key, const Vec3& point);
  Reach reach(double t, const TargetObject& target, bool with_gaze, bool touching);
  Pose predicted_torso(double t) const;
  Mat3 predicted_head(double t) const;
  Pose predicted_wrist(Hand hand, double t) const;
  Pose gesture_pose(Hand hand, float amplitude, const Vec3& avoid);
  Pose random_gesture_pose(Hand hand, float amplitude);
  double scaled(double seconds) const;  // a duration at this subject's speed
  // Fitts' law at this subject's speed, ±10 %, no faster than a comfortable peak speed.
  double movement_duration(double distance, double width, double intercept, double slope);

  Motion& motion_;
  Labelling& labels_;
  Random& rng_;
  Hand hand_;
};

}  // namespace deixis::capture
