#pragma once
// Copying a person's pose unchanged onto an avatar (no translation): their tracked head, gaze,
// wrists and fingertip, taken relative to their own root O, scaled to the avatar's size and put
// at the avatar's root. Two uses: the site's view of its own user (the avatar copies the user
// where the user stands), and the paper's copy-paste baseline, which the remote avatar's
// pointing and touching errors are reported next to (the same recipe as
// tests/presence/end_to_end_test.cpp).

#include "gesture/tracking.h"
#include "ik/avatar_solver.h"

namespace deixis::app {

class PoseCopy {
 public:
  // `user`: the person's calibration (their room); `T_world_origin`: the avatar's root O in the
  // room it stands in; `avatar_height`: the rig's height (positions scale by avatar / user).
  PoseCopy(const BodyCalibration& user, const Pose& T_world_origin, float avatar_height);

  Vec3 point(const Vec3& p_user_world) const;
  Pose pose(const Pose& T_user_world) const;
  Vec3 direction(const Vec3& d_user_world) const;

  // The IK targets of the copy (head, gaze, deictic wrist and fingertip, the other hand).
  ik::AvatarTargets targets(const TrackingFrame& frame) const;

  float scale() const { return scale_; }  // avatar height / user height
  const BodyCalibration& user() const { return user_; }

 private:
  BodyCalibration user_;
  Pose T_world_origin_;
  Pose T_root_user_world_;  // the user's world seen from their root
  float scale_;
};

}  // namespace deixis::app
