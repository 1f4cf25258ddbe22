#pragma once
// Copying a person's pose unchanged onto an avatar (no translation): their tracked head, gaze,
// wrists and fingertip, taken relative to their own root O, scaled to the avatar's size and put
// at the avatar's root. Two uses: the site's view of its own user (the avatar copies the user
// where the user stands), and the paper's copy-paste baseline, which the remote avatar's
// pointing and touching errors are reported next to (the same recipe as
// tests/presence/end_to_end_test.cpp).

#include <span>
#include <vector>

#include "core/tracking.h"
#include "ik/avatar_solver.h"

namespace deixis::presence {

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

  float scale() const { return scale_; }                          // avatar height / user height
  const Pose& T_world_origin() const { return T_world_origin_; }  // the copy's root O
  const BodyCalibration& user() const { return user_; }

 private:
  BodyCalibration user_;
  Pose T_world_origin_;
  Pose T_root_user_world_;  // the user's world seen from their root
  float scale_;
};

// An avatar copying a person's pose where it stands: PoseCopy's targets solved by the whole-avatar
// IK every tick (a site's or the simulator's view of its own user). Sized at construction;
// solve() allocates nothing.
class CopiedAvatar {
 public:
  // `solver` must outlive the CopiedAvatar.
  CopiedAvatar(const BodyCalibration& user, const ik::AvatarSolver& solver,
               const Pose& T_world_origin);

  // A refused solve (never for the copy of a finite tracked pose) keeps the last pose.
  void solve(const TrackingFrame& frame);

  const Pose& T_world_model() const { return T_world_model_; }
  std::span<const Pose> model_pose() const { return model_; }
  const ik::AvatarTargets& targets() const { return targets_; }

 private:
  const ik::AvatarSolver* solver_;
  PoseCopy copy_;
  Pose T_world_model_;
  ik::AvatarTargets targets_;
  std::vector<Pose> local_;
  std::vector<Pose> model_;
};

}  // namespace deixis::presence
