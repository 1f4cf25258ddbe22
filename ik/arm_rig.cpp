#include "ik/arm_rig.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "ik/rotations.h"
#include "ik/two_bone_job.h"
#include "ik/wrist_job.h"

namespace deixis::ik {
namespace {

constexpr float kMinBone = 1e-3f;  // m: a shorter bone has no usable direction

struct SideBones {
  Bone upper, lower, hand;
  std::array<Bone, 3> index;
};

SideBones bones_of(Hand side) {
  if (side == Hand::kLeft) {
    return {Bone::kLeftUpperArm,
            Bone::kLeftLowerArm,
            Bone::kLeftHand,
            {Bone::kLeftIndexProximal, Bone::kLeftIndexIntermediate, Bone::kLeftIndexDistal}};
  }
  return {Bone::kRightUpperArm,
          Bone::kRightLowerArm,
          Bone::kRightHand,
          {Bone::kRightIndexProximal, Bone::kRightIndexIntermediate, Bone::kRightIndexDistal}};
}

int required_joint(const HumanoidRig& rig, Bone bone) {
  const int j = rig[bone];
  if (j < 0 || j >= rig.skeleton.joint_count()) {
    throw Error("avatar rig: required bone '" + std::string(bone_name(bone)) + "' is missing");
  }
  return j;
}

Vec3 bone_direction(const Vec3& from, const Vec3& to, Bone bone) {
  const Vec3 d = to - from;
  if (!(d.norm() > kMinBone)) {
    throw Error("avatar rig: bone '" + std::string(bone_name(bone)) +
                "' has no length in the rest pose");
  }
  return d.normalized();
}

}  // namespace

ArmRig make_arm_rig(const HumanoidRig& rig, std::span<const Pose> rest_model, Hand side,
                    const IkLimits& limits) {
  const SideBones b = bones_of(side);
  ArmRig arm;
  arm.side = side;
  arm.upper = required_joint(rig, b.upper);
  arm.lower = required_joint(rig, b.lower);
  arm.hand = required_joint(rig, b.hand);
  for (const Bone bone : b.index) {
    const int j = rig[bone];
    if (j < 0) {
      break;  // the index chain is optional, and so is its tail
    }
    arm.index[arm.index_count++] = j;
  }
  const Vec3 S = rest_model[arm.upper].translation;
  const Vec3 E = rest_model[arm.lower].translation;
  const Vec3 W = rest_model[arm.hand].translation;
  const Vec3 upper_dir = bone_direction(S, E, b.upper);
  const Vec3 distal = bone_direction(E, W, b.lower);
  const float outward = side == Hand::kRight ? 1.0f : -1.0f;  // the avatar faces −Z: right is +X

  // Palms down: the back of the hand is +Y made perpendicular to the forearm (or, for an arm
  // hanging straight down, the outward side).
  const Vec3 dorsal = std::abs(distal.y()) < 0.95f ? frame_from(distal, Vec3::UnitY()).col(1)
                                                   : frame_from(distal, Vec3(outward, 0, 0)).col(1);
  Mat3 R_model_wrist;
  R_model_wrist.col(0) = side == Hand::kRight ? distal : Vec3(-distal);
  R_model_wrist.col(1) = dorsal;
  R_model_wrist.col(2) = R_model_wrist.col(0).cross(dorsal);
  arm.R_hand_wrist = rest_model[arm.hand].rotation.transpose() * R_model_wrist;
  arm.forearm_axis = rest_model[arm.lower].rotation.transpose() * distal;

  // The elbow bends toward the pole: hinge = v × u with u along shoulder→wrist and v toward the
  // pole (TwoBoneJob's convention). A rest arm bent the other way still gets this hinge.
  arm.pole = Vec3(0.3f * outward, -1.0f, 0.3f).normalized();
  const Vec3 u = normalized_or(W - S, upper_dir);
  const Vec3 v = frame_from(u, arm.pole).col(1);
  arm.mid_axis = rest_model[arm.lower].rotation.transpose() * v.cross(u);

  // Index joints curl toward the palm: about bone × palmar.
  const Vec3 palmar = -dorsal;
  for (int k = 0; k < arm.index_count; ++k) {
    const int j = arm.index[k];
    const Vec3 next = k + 1 < arm.index_count
                          ? rest_model[arm.index[k + 1]].translation
                          : transform_point(rest_model[j], rig.index_tip_in_distal[index(side)]);
    // A fingertip offset of zero leaves the last bone without a direction: use the forearm's.
    const Vec3 bone = normalized_or(next - rest_model[j].translation, distal);
    arm.index_axes[k] =
        rest_model[j].rotation.transpose() * normalized_or(bone.cross(palmar), dorsal.cross(bone));
  }
  arm.tip_offset = rig.index_tip_in_distal[index(side)];
  if (!arm.tip_offset.allFinite()) {
    throw Error("avatar rig: the " + std::string(side == Hand::kRight ? "right" : "left") +
                " index fingertip offset is not finite");
  }

  // Supination turns the right forearm positively about its distal axis and the left one
  // negatively (mirror images).
  arm.forearm_twist = side == Hand::kRight ? HingeRange{-limits.pronation, limits.supination}
                                           : HingeRange{-limits.supination, limits.pronation};
  return arm;
}

void bend_arm_and_turn_hand(const Skeleton& skeleton, const ArmRig& a, const IkLimits& limits,
                            const Vec3& wrist_target, const Vec3& pole, const Mat3& R_model_hand,
                            std::span<Pose> local, std::span<Pose> model) {
  Mat3 start_correction;
  Mat3 mid_correction;
  TwoBoneJob two_bone;
  two_bone.start_joint = &model[a.upper];
  two_bone.mid_joint = &model[a.lower];
  two_bone.end_joint = &model[a.hand];
  two_bone.target = wrist_target;
  two_bone.pole_vector = pole;
  two_bone.mid_axis = a.mid_axis;
  two_bone.flexion = limits.elbow;
  two_bone.start_correction = &start_correction;
  two_bone.mid_correction = &mid_correction;
  two_bone.run();
  local[a.upper].rotation = local[a.upper].rotation * start_correction;
  local[a.lower].rotation = local[a.lower].rotation * mid_correction;
  update_model_path(skeleton, local, model, a.upper, a.hand);

  WristJob wrist;
  wrist.skeleton = &skeleton;
  wrist.forearm = a.lower;
  wrist.hand = a.hand;
  wrist.forearm_axis = a.forearm_axis;
  wrist.twist = a.forearm_twist;
  wrist.swing_max = limits.wrist_swing;
  wrist.hand_twist_max = limits.wrist_twist;
  wrist.target = R_model_hand;
  wrist.local = local;
  wrist.model = model;
  wrist.run();
}

}  // namespace deixis::ik
