#include "ik/joint_rotation.h"

#include "ik/joint_limits.h"

namespace deixis::ik {

Mat3 rotate_joint_limited(const Skeleton& skeleton, std::span<Pose> local, std::span<Pose> model,
                          int joint, const Mat3& C_model, float max_angle, int path_end) {
  const Mat3 R_model_parent = parent_rotation(skeleton, model, joint);
  const Mat3 R_before = model[joint].rotation;
  const Mat3 wanted = renormalized(R_model_parent.transpose() * C_model * R_before);
  local[joint].rotation = clamp_to_rest(wanted, skeleton.rest_local[joint].rotation, max_angle);
  update_model_path(skeleton, local, model, joint, path_end);
  return model[joint].rotation * R_before.transpose();
}

}  // namespace deixis::ik
