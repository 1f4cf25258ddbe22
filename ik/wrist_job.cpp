#include "ik/wrist_job.h"

#include <algorithm>
#include <cmath>

#include "ik/job_validation.h"

namespace deixis::ik {

bool WristJob::validate(std::string_view* reason) const {
  if (skeleton == nullptr) {
    return fail(reason, "skeleton is not set");
  }
  const auto n = static_cast<std::size_t>(skeleton->joint_count());
  if (local.size() != n || model.size() != n) {
    return fail(reason, "local and model must hold one pose per skeleton joint");
  }
  if (!valid_joint(*skeleton, forearm) || !valid_joint(*skeleton, hand) || forearm == hand ||
      !is_ancestor(*skeleton, forearm, hand)) {
    return fail(reason, "forearm and hand must be joints, the hand below the forearm");
  }
  if (!(std::abs(forearm_axis.norm() - 1.0f) < 1e-3f)) {
    return fail(reason, "forearm_axis is not a unit vector");
  }
  if (!(twist.min >= -kPi && twist.min <= twist.max && twist.max <= kPi)) {
    return fail(reason, "twist range is not ordered within [−π, π]");
  }
  if (!(swing_max >= 0.0f && swing_max <= kPi) ||
      !(hand_twist_max >= 0.0f && hand_twist_max <= kPi)) {
    return fail(reason, "swing_max and hand_twist_max must lie in [0, π]");
  }
  return true;
}

bool WristJob::run() const {
  if (!validate()) {
    return false;
  }
  if (!target.allFinite()) {
    if (reached != nullptr) {
      *reached = false;
    }
    return true;
  }
  const Mat3 R_target = orthonormalized(target);
  const int hand_parent = skeleton->parents[hand];
  const Mat3& L0_forearm = skeleton->rest_local[forearm].rotation;
  const Mat3& L0_hand = skeleton->rest_local[hand].rotation;
  // The forearm axis in the hand's rest frame: the axis the hand's twist is measured about.
  const Mat3 K = model[forearm].rotation.transpose() * model[hand_parent].rotation;
  const Vec3 hand_axis = (L0_hand.transpose() * K.transpose() * forearm_axis).normalized();
  const auto wanted_deviation = [&] {
    return rest_deviation(model[hand_parent].rotation.transpose() * R_target, L0_hand);
  };

  // 1. The forearm takes the twist, within its range.
  const float forearm_twist =
      swing_twist(rest_deviation(local[forearm].rotation, L0_forearm), forearm_axis).twist;
  const float wanted_twist = swing_twist(wanted_deviation(), hand_axis).twist;
  const float new_twist = std::clamp(forearm_twist + wanted_twist, twist.min, twist.max);
  local[forearm].rotation =
      local[forearm].rotation * axis_angle(forearm_axis, new_twist - forearm_twist);
  update_model_path(*skeleton, local, model, forearm, hand_parent);

  // 2. The wrist bends by the rest, within its cone, keeping a small twist of its own.
  const SwingTwist rest = swing_twist(wanted_deviation(), hand_axis);
  const float hand_twist = std::clamp(rest.twist, -hand_twist_max, hand_twist_max);
  local[hand].rotation =
      L0_hand * clamp_rotation(rest.swing, swing_max) * axis_angle(hand_axis, hand_twist);
  model[hand] = compose(model[hand_parent], local[hand]);
  if (reached != nullptr) {
    *reached = rotation_angle(R_target * model[hand].rotation.transpose()) < deg(0.05f);
  }
  return true;
}

}  // namespace deixis::ik
