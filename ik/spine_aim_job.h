#pragma once
// Head orientation shared along the spine (ozz-style job; docs/ik.md). The head must end at a
// target orientation; the joints below it (spine, chest, neck) each take a share of what is left,
// so a person turning to look at something turns the torso a little, the neck more, the head the
// rest, as people do.
//
// For each chain joint in order (root first), the remaining error E = R_target · R_headᵀ (model
// space) is applied with the joint's weight (E^w, a fraction of the angle), then the joint is
// clamped to its limit; the last joint has weight 1, so the head ends exactly at the target when
// the limits allow it. Weights are fractions of the *remaining* error, so a clamped joint hands
// its share on to the joints above it.

#include <span>
#include <string_view>

#include "ik/skeleton.h"

namespace deixis::ik {

inline constexpr int kMaxChain = 8;

struct SpineAimJob {
  bool validate(std::string_view* reason = nullptr) const;
  bool run() const;  // validates first; false (outputs untouched) when invalid

  // ---- inputs ----
  const Skeleton* skeleton = nullptr;
  std::span<const int> chain;         // joints, root first, each an ancestor of the next; the
                                      // last is the one aimed (the head). 1..kMaxChain joints.
  std::span<const float> weights;     // per joint, in [0, 1]; the last must be 1
  std::span<const float> max_angles;  // per joint: largest rotation away from rest, [0, π]
  Mat3 target = Mat3::Identity();     // wanted model rotation of the last joint; a finite matrix
                                      // that is not a rotation is projected onto one, a
                                      // non-finite one leaves the pose unchanged

  // ---- in/out ----
  std::span<Pose> local;  // joint_count() poses; the chain joints' rotations are rewritten
  std::span<Pose> model;  // joint_count() poses, current on input; on output the path from the
                          // first chain joint to the last is updated (other joints are not)

  // ---- outputs ----
  bool* reached = nullptr;  // optional: the last joint is within 0.01° of the target
};

}  // namespace deixis::ik
