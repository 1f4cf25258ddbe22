#pragma once
// The hand's orientation (ozz-style job; docs/ik.md), shared the way an arm shares it: the twist
// about the forearm's axis goes to the forearm (pronation/supination, which turns the hand without
// moving the wrist), within its range; what is left bends the wrist, its swing off the forearm axis
// clamped to a cone and a small residual twist to its own limit.

#include <span>
#include <string_view>

#include "ik/joint_limits.h"
#include "ik/skeleton.h"

namespace deixis::ik {

struct WristJob {
  bool validate(std::string_view* reason = nullptr) const;
  bool run() const;  // validates first; false (outputs untouched) when invalid

  // ---- inputs ----
  const Skeleton* skeleton = nullptr;
  int forearm = -1;                     // the lower arm joint
  int hand = -1;                        // the hand joint, below the forearm
  Vec3 forearm_axis = Vec3::UnitX();    // unit elbow→wrist direction in the forearm's frame
  HingeRange twist{-kPi / 2, kPi / 2};  // forearm twist about forearm_axis, from rest
  float swing_max = deg(70.0f);         // the hand's swing off the forearm axis, from rest
  float hand_twist_max = deg(10.0f);    // the hand's own twist, from rest
  Mat3 target = Mat3::Identity();       // wanted model rotation of the hand; projected onto a
                                        // rotation; non-finite: the pose is left unchanged

  // ---- in/out ----
  std::span<Pose> local;  // the forearm's and hand's rotations are rewritten
  std::span<Pose> model;  // current on input; on output updated from the forearm down to the
                          // hand (joints below the hand are not)

  // ---- outputs ----
  bool* reached = nullptr;  // optional: the hand is within 0.05° of the target
};

}  // namespace deixis::ik
