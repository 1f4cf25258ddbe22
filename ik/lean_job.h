#pragma once
// Head position by leaning (ozz-style job; docs/ik.md): bends the spine so that a point on the
// head (the eye midpoint H) moves toward a target position, within each joint's limit. People
// lean forward to look closer or sideways to look past something; the networks move H relative
// to the root O and this job follows.
//
// Each iteration is a damped least-squares step (Levenberg–Marquardt on the point's position; a
// step that does not bring the point nearer is undone and retried with more damping): the pivots
// turn by the smallest weighted rotations that move the point onto the target, each joint then
// clamped to its limit; a pivot's weight is its mobility, so with weights (0.5, 1) the chest
// bends about twice as much as the spine. Iterations stop when the point is within 0.1 mm, or
// when a step gains less than a tenth of the remaining distance: rotations about pivots nearly in
// line with the point barely change its distance from them, so a target nearer or farther than
// the chain allows is approached as closely as it can be (`reached` says whether the point got
// there). The hips are not a pivot: turning them would swing the legs.

#include <span>
#include <string_view>

#include "ik/skeleton.h"

namespace deixis::ik {

struct LeanJob {
  bool validate(std::string_view* reason = nullptr) const;
  bool run() const;  // validates first; false (outputs untouched) when invalid

  // ---- inputs ----
  const Skeleton* skeleton = nullptr;
  std::span<const int> chain;         // pivots (e.g. spine, chest), root first, each an ancestor
                                      // of the next and of end_joint; 1..kMaxChain joints
  std::span<const float> weights;     // per pivot mobility, in [0, 1]; the last must be 1
  std::span<const float> max_angles;  // per pivot: largest rotation away from rest, [0, π]
  int end_joint = -1;                 // the joint that carries the point (the head)
  Vec3 end_offset = Vec3::Zero();     // the point in end_joint's frame (H)
  Vec3 target = Vec3::Zero();         // model space; non-finite: the pose is left unchanged
  int iterations = 12;                // least-squares steps, 1..16

  // ---- in/out ----
  std::span<Pose> local;  // joint_count() poses; the pivots' rotations are rewritten
  std::span<Pose> model;  // current on input; on output the path from the first pivot to
                          // end_joint is updated (other joints are not)

  // ---- outputs ----
  bool* reached = nullptr;  // optional: the point is within 1 mm of the target
  float* error = nullptr;   // optional: the point's distance to the target afterwards (m);
                            // −1 when the target is not finite
};

}  // namespace deixis::ik
