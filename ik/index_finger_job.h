#pragma once
// The index fingertip brought to a target by bending the index chain (ozz-style job; docs/ik.md),
// the way a finger bends: the joints after the first curl together (each by the same fraction of
// its flexion range, so the finger shortens smoothly), the curl chosen so the fingertip is as far
// from the first joint as the target is; then the first joint turns about its flexion axis to
// point the finger at the target. Exact for targets in the finger's plane within its ranges. Used
// after the arm has placed the wrist, to take up what the arm could not (a target nearer the palm
// than the straight finger, or a wrist held back by its limits); when the tip is already on the
// target nothing moves.

#include <span>
#include <string_view>

#include "ik/joint_limits.h"
#include "ik/skeleton.h"

namespace deixis::ik {

inline constexpr int kMaxFingerJoints = 3;

struct IndexFingerJob {
  bool validate(std::string_view* reason = nullptr) const;
  bool run() const;  // validates first; false (outputs untouched) when invalid

  // ---- inputs ----
  const Skeleton* skeleton = nullptr;
  std::span<const int> chain;           // 1..3 joints, proximal first, each the parent of the
                                        // next (the last carries the tip)
  std::span<const Vec3> flexion_axes;   // per joint, unit, in its own frame: a positive turn
                                        // curls the finger toward the palm
  std::span<const HingeRange> flexion;  // per joint, from rest, within [−π, π]; the curl runs
                                        // the joints after the first from 0 (or min) to max
  Vec3 tip_offset = Vec3::Zero();       // the fingertip in the last joint's frame
  Vec3 target = Vec3::Zero();           // model space; non-finite: the pose is left unchanged

  // ---- in/out ----
  std::span<Pose> local;  // the chain's rotations are rewritten
  std::span<Pose> model;  // current on input (at least the chain and its parent); the chain's
                          // model poses are updated

  // ---- outputs ----
  bool* reached = nullptr;  // optional: the tip is within 1 mm of the target
  Vec3* tip = nullptr;      // optional: where the tip ends, model space
};

}  // namespace deixis::ik
