#include "ik/eye_job.h"

#include <algorithm>
#include <cmath>

#include "ik/job_validation.h"
#include "ik/joint_rotation.h"

namespace deixis::ik {

bool EyeJob::validate(std::string_view* reason) const {
  if (skeleton == nullptr) {
    return fail(reason, "skeleton is not set");
  }
  const auto n = static_cast<std::size_t>(skeleton->joint_count());
  if (rest_model.size() != n || local.size() != n || model.size() != n) {
    return fail(reason, "rest_model, local and model must hold one pose per skeleton joint");
  }
  if (!valid_joint(*skeleton, head)) {
    return fail(reason, "head is not a joint of the skeleton");
  }
  if (eyes.empty() || eyes.size() > 2) {
    return fail(reason, "eyes must hold 1 or 2 joints");
  }
  for (const int eye : eyes) {
    if (!valid_joint(*skeleton, eye) || eye == head || !is_ancestor(*skeleton, head, eye)) {
      return fail(reason, "eyes must be joints below the head");
    }
  }
  if (!(range.yaw >= 0.0f && range.yaw <= kPi) || !(range.up >= 0.0f && range.up < kPi / 2) ||
      !(range.down >= 0.0f && range.down < kPi / 2)) {
    return fail(reason, "range: yaw must lie in [0, π], up and down in [0, π/2)");
  }
  return true;
}

bool EyeJob::run() const {
  if (!validate()) {
    return false;
  }
  // The face frame: the head's current rotation relative to its rest, applied to the rest
  // model axes (−Z forward, +Y up, +X right).
  const Mat3 F = model[head].rotation * rest_model[head].rotation.transpose();
  const Vec3 ahead = F * Vec3(0, 0, -1);
  const Vec3 g = F.transpose() * normalized_or(gaze, ahead);
  const float yaw = std::atan2(-g.x(), -g.z());
  const float pitch = std::atan2(g.y(), std::hypot(g.x(), g.z()));
  const float yaw_clamped = std::clamp(yaw, -range.yaw, range.yaw);
  const float pitch_clamped = std::clamp(pitch, -range.down, range.up);
  // Pitch about the face's x axis first, then yaw about its y axis: the line of sight is
  // (−sin yaw·cos pitch, sin pitch, −cos yaw·cos pitch).
  const Mat3 look =
      F * axis_angle(Vec3::UnitY(), yaw_clamped) * axis_angle(Vec3::UnitX(), pitch_clamped);
  for (const int eye : eyes) {
    const Mat3 R_model_eye = look * rest_model[eye].rotation;
    local[eye].rotation = parent_rotation(*skeleton, model, eye).transpose() * R_model_eye;
    model[eye] = compose(model[skeleton->parents[eye]], local[eye]);
  }
  if (reached != nullptr) {
    *reached = yaw == yaw_clamped && pitch == pitch_clamped;
  }
  return true;
}

}  // namespace deixis::ik
