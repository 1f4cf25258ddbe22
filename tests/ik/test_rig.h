#pragma once
// A procedural humanoid for the IK tests and benchmarks, independent of the glTF avatars in
// avatar/: a 1.70 m person (the paper's training subject: 74 cm from shoulder to index fingertip)
// facing −Z in a palms-down T-pose, with legs, a VRM-style upper chest between chest and neck
// (a joint no role names, so chains have joints in between), eyes, clavicles, thumbs, middle
// fingers and three-joint index fingers. Arms come before the neck in depth-first order, as in
// Mixamo rigs, so a job that updated whole index ranges would pay for it.
//
// Joint frames are either the model's axes (as VRM 1.0 normalises them) or bone-aligned with an
// arbitrary roll (+Y along the bone, as Mixamo exports), so the IK is tested against both.

#include <cmath>
#include <string>
#include <vector>

#include "core/tracking.h"
#include "ik/humanoid.h"
#include "ik/rotations.h"

namespace deixis::ik::testing {

struct TestRigOptions {
  float height = 1.70f;       // m, floor to top of head
  float arm_scale = 1.0f;     // multiplies every arm and hand length
  bool bone_aligned = false;  // joint frames along the bones with a roll, else model axes
  bool with_chest = true;     // optional bones, to test rigs that lack them
  bool with_neck = true;
  bool with_eyes = true;
  int index_joints = 3;  // 0..3 per hand
};

namespace detail {

struct JointSpec {
  std::string name;
  int parent;
  Vec3 position;  // model space, 1.70 m person
  Vec3 aim;       // a point the joint's bone points at (for bone-aligned frames)
  Bone bone;      // Bone::kCount: no role
};

// +Y along the bone toward `aim`, rolled about it by an arbitrary but fixed angle.
inline Mat3 bone_frame(const Vec3& position, const Vec3& aim, int joint) {
  const Vec3 y = normalized_or(aim - position, Vec3::UnitY());
  const Mat3 F = frame_from(y, any_perpendicular(y));  // columns: y, x', z'
  Mat3 R;
  R.col(0) = F.col(1);
  R.col(1) = y;
  R.col(2) = F.col(1).cross(y);
  return axis_angle(y, 0.7f * static_cast<float>(joint) + 0.3f) * R;
}

}  // namespace detail

inline HumanoidRig make_test_rig(const TestRigOptions& o = {}) {
  using detail::JointSpec;
  const float k = o.height / 1.70f;
  const float arm = o.arm_scale;
  std::vector<JointSpec> specs;
  const auto add = [&](const std::string& name, int parent, const Vec3& position, const Vec3& aim,
                       Bone bone) {
    specs.push_back({name, parent, position, aim, bone});
    return static_cast<int>(specs.size()) - 1;
  };
  const int hips = add("hips", -1, Vec3(0, 0.95f, 0) * k, Vec3(0, 1.05f, 0.01f) * k, Bone::kHips);
  for (const float side : {-1.0f, 1.0f}) {
    const std::string s = side < 0 ? "left" : "right";
    const int upper_leg = add(s + "UpperLeg", hips, Vec3(0.09f * side, 0.90f, 0) * k,
                              Vec3(0.09f * side, 0.49f, 0) * k, Bone::kCount);
    const int lower_leg = add(s + "LowerLeg", upper_leg, Vec3(0.09f * side, 0.49f, 0) * k,
                              Vec3(0.09f * side, 0.08f, 0) * k, Bone::kCount);
    add(s + "Foot", lower_leg, Vec3(0.09f * side, 0.08f, 0) * k,
        Vec3(0.09f * side, 0.02f, -0.12f) * k, Bone::kCount);
  }
  int spine_top =
      add("spine", hips, Vec3(0, 1.05f, 0.01f) * k, Vec3(0, 1.20f, 0.01f) * k, Bone::kSpine);
  if (o.with_chest) {
    spine_top =
        add("chest", spine_top, Vec3(0, 1.20f, 0.01f) * k, Vec3(0, 1.33f, 0) * k, Bone::kChest);
  }
  const int upper_chest =
      add("upperChest", spine_top, Vec3(0, 1.33f, 0) * k, Vec3(0, 1.45f, 0) * k, Bone::kCount);
  for (const float side : {-1.0f, 1.0f}) {
    const bool left = side < 0;
    const std::string s = left ? "left" : "right";
    const auto role = [&](Bone l, Bone r) { return left ? l : r; };
    const Vec3 out(side, 0, 0);
    const Vec3 shoulder_at = Vec3(0.185f * side, 1.42f, 0) * k;
    const int clavicle = add(s + "Shoulder", upper_chest, Vec3(0.03f * side, 1.42f, -0.01f) * k,
                             shoulder_at, role(Bone::kLeftShoulder, Bone::kRightShoulder));
    const Vec3 elbow_at = shoulder_at + out * (0.30f * k * arm);
    const Vec3 wrist_at = elbow_at + out * (0.26f * k * arm);
    const int upper = add(s + "UpperArm", clavicle, shoulder_at, elbow_at,
                          role(Bone::kLeftUpperArm, Bone::kRightUpperArm));
    const int lower = add(s + "LowerArm", upper, elbow_at, wrist_at,
                          role(Bone::kLeftLowerArm, Bone::kRightLowerArm));
    const Vec3 middle_at = wrist_at + out * (0.09f * k * arm);
    const int hand =
        add(s + "Hand", lower, wrist_at, middle_at, role(Bone::kLeftHand, Bone::kRightHand));
    // Palms down, facing −Z: the thumb and index are on the −Z (radial) side.
    const Vec3 thumb_at = wrist_at + (out * 0.03f + Vec3(0, -0.01f, -0.03f)) * (k * arm);
    add(s + "ThumbProximal", hand, thumb_at, thumb_at + (out + Vec3(0, 0, -1)) * 0.03f,
        Bone::kCount);
    const std::array<Bone, 3> index_roles = {
        role(Bone::kLeftIndexProximal, Bone::kRightIndexProximal),
        role(Bone::kLeftIndexIntermediate, Bone::kRightIndexIntermediate),
        role(Bone::kLeftIndexDistal, Bone::kRightIndexDistal)};
    const std::array<float, 4> index_lengths = {0.045f, 0.026f, 0.022f, 0.0f};
    Vec3 at = wrist_at + (out * 0.09f + Vec3(0, 0, -0.02f)) * (k * arm);
    int parent = hand;
    const std::array<std::string, 3> names = {"IndexProximal", "IndexIntermediate", "IndexDistal"};
    for (int j = 0; j < o.index_joints; ++j) {
      const Vec3 next = at + out * (index_lengths[j] * k * arm);
      parent = add(s + names[j], parent, at, next, index_roles[j]);
      at = next;
    }
    add(s + "MiddleProximal", hand, middle_at, middle_at + out * 0.05f, Bone::kCount);
  }
  if (o.with_neck) {
    spine_top = add("neck", upper_chest, Vec3(0, 1.45f, 0) * k, Vec3(0, 1.53f, 0) * k, Bone::kNeck);
  } else {
    spine_top = upper_chest;
  }
  const Vec3 head_at = Vec3(0, 1.53f, 0) * k;
  const int head = add("head", spine_top, head_at, Vec3(0, 1.70f, 0) * k, Bone::kHead);
  const Vec3 eye_midpoint = Vec3(0, 1.585f, -0.08f) * k;
  if (o.with_eyes) {
    for (const float side : {-1.0f, 1.0f}) {
      const Vec3 eye = eye_midpoint + Vec3(0.032f * side, 0, 0) * k;
      add(side < 0 ? "leftEye" : "rightEye", head, eye, eye + Vec3(0, 0, -0.05f),
          side < 0 ? Bone::kLeftEye : Bone::kRightEye);
    }
  }

  // Model poses → local poses.
  HumanoidRig rig;
  rig.joint.fill(-1);
  std::vector<Pose> model(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    const JointSpec& j = specs[i];
    model[i].translation = j.position;
    model[i].rotation = o.bone_aligned ? detail::bone_frame(j.position, j.aim, static_cast<int>(i))
                                       : Mat3::Identity();
    rig.skeleton.joint_names.push_back(j.name);
    rig.skeleton.parents.push_back(static_cast<std::int16_t>(j.parent));
    rig.skeleton.rest_local.push_back(j.parent < 0 ? model[i]
                                                   : compose(inverse(model[j.parent]), model[i]));
    if (j.bone != Bone::kCount) {
      rig.joint[static_cast<int>(j.bone)] = static_cast<int>(i);
    }
  }
  rig.eye_midpoint_in_head = transform_point(inverse(model[head]), eye_midpoint);
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const bool right = h == Hand::kRight;
    const float side = right ? 1.0f : -1.0f;
    // Hand, proximal, intermediate, distal follow each other in the Bone enumeration.
    const Bone hand = right ? Bone::kRightHand : Bone::kLeftHand;
    const int last = rig.joint[static_cast<int>(hand) + o.index_joints];
    // The fingertip, 2.2 cm past the distal joint, on the line of the finger.
    const Vec3 wrist_at = model[rig[hand]].translation;
    const Vec3 tip =
        wrist_at + Vec3(side * (0.09f + 0.045f + 0.026f + 0.022f), 0, -0.02f) * (k * arm);
    rig.index_tip_in_distal[index(h)] = transform_point(inverse(model[last]), tip);
    if (right) {
      rig.arm_length = (tip - model[rig[Bone::kRightUpperArm]].translation).norm();
    }
  }
  rig.height = o.height;
  return rig;
}

}  // namespace deixis::ik::testing
