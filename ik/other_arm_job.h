#pragma once
// The non-deictic arm (ozz-style job; docs/conventions.md#translator, paper §IV.C; docs/ik.md): the
// hand that gestures freely keeps the user's azimuth, elevation and distance from the head H (the
// distance scaled to the avatar's size), measured in the root frame (yaw-only, −Z forward, +Y up),
// so it moves with the body, not with the head's turns. The point is projected out of an elliptic
// cylinder around the chest so the hand never passes through the torso (alternating with the arm's
// softened reach, so that an arm falling short of a far point does not fall into the chest either);
// two-bone IK takes the wrist there and the hand takes the user's wrist orientation (relative to
// the root) within its limits.

#include <span>
#include <string_view>

#include "ik/arm_rig.h"
#include "ik/chest_cylinder.h"
#include "ik/skeleton.h"

namespace deixis::ik {

// Where the non-deictic wrist is relative to the head, as the user holds it.
struct OtherHandTarget {
  float azimuth = 0.0f;                  // rad about +Y from forward (−Z), positive to the left
  float elevation = -deg(75.0f);         // rad above the horizontal
  float distance = 0.6f;                 // m from H, already scaled to the avatar's size
  Mat3 R_root_wrist = Mat3::Identity();  // wrist orientation in the root frame (tracker
                                         // convention, docs/decisions.md §7)
};

// The unit direction of (azimuth, elevation) in the root frame.
Vec3 direction_of(float azimuth, float elevation);

// The user's non-deictic hand as the avatar should hold it: from the user's root O, head H and
// wrist (all in the user's world), with positions divided by `scale` = user size / avatar size.
OtherHandTarget other_hand_target(const Pose& T_world_root, const Pose& T_world_head,
                                  const Pose& T_world_wrist, float scale);
// The same from the wrist relative to H in the root frame, already scaled (the translator's
// AvatarFrame::other_wrist_from_head).
OtherHandTarget other_hand_target(const Pose& wrist_from_head);

struct OtherArmResult {
  bool reached = false;    // the wrist is within 1 mm of the wanted point (projected out of the
                           // chest when it was inside)
  bool projected = false;  // the wanted point, or the goal on the way, was inside the chest
  Vec3 wrist_target = Vec3::Zero();  // model space: the goal the arm was solved for, out of the
                                     // chest and within reach
};

struct OtherArmJob {
  bool validate(std::string_view* reason = nullptr) const;
  bool run() const;  // validates first; false (outputs untouched) when invalid

  // ---- inputs ----
  const Skeleton* skeleton = nullptr;
  const ArmRig* arm = nullptr;
  const IkLimits* limits = nullptr;  // elbow and wrist limits
  const ChestCylinder* cylinder = nullptr;
  int chest = -1;                     // the joint the cylinder rides on
  Vec3 head_position = Vec3::Zero();  // H, model space (the model frame is the root frame)
  OtherHandTarget target;             // non-finite parts: the arm keeps its pose
  Vec3 pole = Vec3(0, -1, 0);         // model space; non-finite: the arm's natural pole
  float soften = 0.97f;               // (0, 1]; see TwoBoneJob

  // ---- in/out ----
  std::span<Pose> local;  // the arm's upper, lower and hand joints are rewritten
  std::span<Pose> model;  // current on input (the arm, its ancestors, the chest); on output
                          // updated from the upper arm down to the fingertip joint

  // ---- outputs ----
  OtherArmResult* result = nullptr;  // optional
};

}  // namespace deixis::ik
