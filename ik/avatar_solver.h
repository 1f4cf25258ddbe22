#pragma once
// The whole avatar's IK for one tick (docs/ik.md): the end-effectors the translator produced
// (head, gaze, deictic wrist and index fingertip) and the non-deictic hand's user-relative
// placement become local and model poses of every joint of a HumanoidRig.
//
// Order, each step an ozz-style job:
//   1. every joint at rest;
//   2. head orientation shared over spine, chest, neck and head (SpineAimJob);
//   3. lean: spine, chest and neck bend so the head joint goes where H lands on its target once
//      the head has its orientation (LeanJob); then the head alone turns to its orientation,
//      which does not move the head joint (SpineAimJob; the neck, then the whole chain, help only
//      when the head's limit stops it, and the lean is given up when even that is not enough: the
//      orientation comes first);
//   4. eyes along the gaze (EyeJob);
//   5. the deictic arm: wrist placement, two-bone, wrist orientation, index fingertip
//      (DeicticArmJob);
//   6. the other arm: azimuth, elevation and distance from H, out of the chest cylinder,
//      two-bone, wrist orientation (OtherArmJob);
//   7. model poses of the whole skeleton.
//
// Frames: local[i] = T_parent_joint; model[i] = T_model_joint, where the model frame is the
// skeleton's root frame (the rig as authored: −Z forward, +Y up). The avatar stands in the room at
// T_world_root; targets arrive in the world and are taken into the model frame with its inverse.
// The solve is stateless (it starts from the rest pose every tick) and allocates nothing.

#include <array>
#include <span>
#include <string_view>
#include <vector>

#include "core/end_effector_poses.h"
#include "ik/arm_rig.h"
#include "ik/chest_cylinder.h"
#include "ik/deictic_arm_job.h"
#include "ik/humanoid.h"
#include "ik/other_arm_job.h"

namespace deixis::ik {

struct AvatarSolverConfig {
  IkLimits limits;
  // Shares of the remaining head rotation taken by the joints below the head (the head takes
  // the rest): a 60° turn gives the spine 9°, the chest 10°, the neck 16°, the head 25°.
  float spine_share = 0.15f;
  float chest_share = 0.2f;
  float neck_share = 0.4f;
  float lean_spine_share = 0.5f;   // the spine's mobility in a lean (chest and neck: 1)
  float soften = 0.97f;            // arms: softening starts at 97 % of full reach
  float cylinder_margin = 0.025f;  // m added to the chest cylinder for the hand's thickness
};

// Everything derived from a rig once, at load time; read-only while solving, so one solver serves
// every avatar that uses the rig, from any thread.
struct AvatarSolver {
  // Throws deixis::Error naming the problem: a missing required bone, a chain out of order, a bone
  // without length, unusable limits.
  static AvatarSolver build(const HumanoidRig& rig, const AvatarSolverConfig& config = {});

  int joint_count() const { return rig.skeleton.joint_count(); }

  HumanoidRig rig;
  AvatarSolverConfig config;
  std::vector<Pose> rest_model;           // T_model_joint at rest
  Vec3 eye_midpoint_rest = Vec3::Zero();  // H in the model frame, rest pose

  // Spine, chest, neck, head (absent optional bones skipped): head orientation.
  std::array<int, 4> aim_chain{};
  std::array<float, 4> aim_shares{};
  std::array<float, 4> aim_limits{};
  int aim_count = 0;
  // Spine, chest, neck: lean.
  std::array<int, 3> lean_chain{};
  std::array<float, 3> lean_shares{};
  std::array<float, 3> lean_limits{};
  int lean_count = 0;
  // The part of the aim chain from the neck (or the head) up, for the orientation fix-ups.
  int neck_offset = 0;

  std::array<int, 2> eyes{};
  int eye_count = 0;
  std::array<ArmRig, 2> arms;  // by deixis::Hand
  ChestCylinder cylinder;
  int cylinder_joint = -1;  // chest, or spine when the rig has no chest
};

// The root placement that puts the avatar's rest eye midpoint H at the translator's root O
// (paper §IV.A: O is H's position in the upright posture, yaw-only).
Pose T_world_root_from_origin(const AvatarSolver& solver, const Pose& T_world_origin);

// One tick's targets, in the world.
struct AvatarTargets {
  Hand deictic_hand = Hand::kRight;
  EndEffectorPoses deictic;  // gaze, head H, deictic wrist (tracker convention), index tip
  OtherHandTarget other;     // the non-deictic hand, relative to H in the root frame
};

struct AvatarSolveReport {
  bool head_reached = false;       // the head has its target orientation (within 0.01°)
  float head_position_error = -1;  // m, H to its target after leaning; −1 without a target
  bool eyes_reached = false;       // the gaze was within the eyes' range
  DeicticArmResult deictic;
  OtherArmResult other;
};

struct AvatarSolveJob {
  bool validate(std::string_view* reason = nullptr) const;
  bool run() const;  // validates first; false (outputs untouched) when invalid

  // ---- inputs ----
  const AvatarSolver* solver = nullptr;
  Pose T_world_root;                       // finite, with a rotation matrix
  const AvatarTargets* targets = nullptr;  // non-finite parts leave their joints at rest

  // ---- outputs ----
  std::span<Pose> local;                // T_parent_joint, one per joint
  std::span<Pose> model;                // T_model_joint, one per joint
  AvatarSolveReport* report = nullptr;  // optional
};

}  // namespace deixis::ik
