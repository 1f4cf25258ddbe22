#pragma once
// The deictic arm (ozz-style job; docs/ik.md): the arm that points and touches. Its goal is the
// index fingertip on the target with the hand as oriented as the networks asked:
//
//   1. place the wrist so that the fingertip, carried by the hand at the wanted orientation
//      through the index chain, lands on the target;
//   2. two-bone IK (shoulder–elbow–wrist) to that wrist, the elbow toward the pole;
//   3. the hand's orientation (WristJob: forearm twist, then wrist swing within limits);
//   4. repeat 1–3 from the orientation the limits allowed, so the fingertip still lands;
//   5. bend the index chain (IndexFingerJob) to take up what is left.
//
// When the wrist cannot go where step 1 wants (beyond the softened reach, or nearer the
// shoulder than the elbow's flexion allows), the hand turns as little as needed for the fingertip
// to still land, with the wrist on the sphere the arm reaches; beyond even that, the whole arm
// points along the ray from the shoulder to the target.

#include <limits>
#include <span>
#include <string_view>

#include "ik/arm_rig.h"
#include "ik/skeleton.h"

namespace deixis::ik {

struct DeicticArmResult {
  bool reached = false;       // the fingertip is within 1 mm of the target
  bool beyond_reach = false;  // the target is out of the arm's reach: the arm points along
                              // the sight ray (with sight_origin) or the shoulder→target ray
  float tip_error = 0.0f;     // m, fingertip to target (0 when the target was not finite)
};

struct DeicticArmJob {
  bool validate(std::string_view* reason = nullptr) const;
  bool run() const;  // validates first; false (outputs untouched) when invalid

  // ---- inputs ----
  const Skeleton* skeleton = nullptr;
  const ArmRig* arm = nullptr;
  const IkLimits* limits = nullptr;        // elbow, wrist and index limits
  Vec3 pole = Vec3(0, -1, 0);              // model space; non-finite: the arm's natural pole
  float soften = 0.97f;                    // (0, 1]; see TwoBoneJob
  Mat3 wrist_rotation = Mat3::Identity();  // wanted R_model_wrist, tracker wrist convention
  Vec3 fingertip = Vec3::Zero();           // target, model space
  // The eye midpoint H, model space (optional; non-finite: unused). A fingertip target beyond
  // the arm's reach is then brought in along the ray from H through it, so the eye–fingertip
  // ray, which is what makes a pointing gesture point (paper §III.A), is kept; without it the
  // arm points along the shoulder→target ray.
  Vec3 sight_origin = Vec3::Constant(std::numeric_limits<float>::quiet_NaN());

  // ---- in/out ----
  std::span<Pose> local;  // the arm's joints (upper arm to index tip) are rewritten
  std::span<Pose> model;  // current on input (at least the arm and its ancestors); on output
                          // updated from the upper arm down to the fingertip joint

  // ---- outputs ----
  DeicticArmResult* result = nullptr;  // optional
};

}  // namespace deixis::ik
