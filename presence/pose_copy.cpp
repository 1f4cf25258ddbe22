#include "presence/pose_copy.h"

#include "ik/other_arm_job.h"

namespace deixis::presence {

PoseCopy::PoseCopy(const BodyCalibration& user, const Pose& T_world_origin, float avatar_height)
    : user_(user),
      T_world_origin_(T_world_origin),
      T_root_user_world_(inverse(user.T_world_root)),
      scale_(avatar_height / user.height) {}

Vec3 PoseCopy::point(const Vec3& p_user_world) const {
  return transform_point(T_world_origin_,
                         scale_ * transform_point(T_root_user_world_, p_user_world));
}

Vec3 PoseCopy::direction(const Vec3& d_user_world) const {
  return transform_direction(T_world_origin_,
                             transform_direction(T_root_user_world_, d_user_world));
}

Pose PoseCopy::pose(const Pose& T_user_world) const {
  return {T_world_origin_.rotation * T_root_user_world_.rotation * T_user_world.rotation,
          point(T_user_world.translation)};
}

ik::AvatarTargets PoseCopy::targets(const TrackingFrame& frame) const {
  const Hand hand = user_.deictic_hand;
  ik::AvatarTargets t;
  t.deictic_hand = hand;
  t.deictic.gaze = direction(frame.gaze);
  t.deictic.T_world_head = pose(frame.T_world_head);
  t.deictic.T_world_wrist = pose(frame.T_world_wrist[index(hand)]);
  t.deictic.index_tip = point(frame.index_tip[index(hand)]);
  // The other hand relative to the head in the root frame is the same wherever the root is; the
  // job scales its distance by user size / avatar size.
  t.other = ik::other_hand_target(user_.T_world_root, frame.T_world_head,
                                  frame.T_world_wrist[index(other(hand))], 1.0f / scale_);
  return t;
}

CopiedAvatar::CopiedAvatar(const BodyCalibration& user, const ik::AvatarSolver& solver,
                           const Pose& T_world_origin)
    : solver_(&solver),
      copy_(user, T_world_origin, solver.rig.height),
      T_world_model_(ik::T_world_root_from_origin(solver, T_world_origin)),
      local_(solver.rig.skeleton.rest_local),
      model_(solver.rest_model) {}

void CopiedAvatar::solve(const TrackingFrame& frame) {
  targets_ = copy_.targets(frame);
  ik::AvatarSolveJob job;
  job.solver = solver_;
  job.T_world_root = T_world_model_;
  job.targets = &targets_;
  job.local = local_;
  job.model = model_;
  job.run();
}

}  // namespace deixis::presence
