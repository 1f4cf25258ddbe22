#pragma once
// The one step the chain jobs (spine aim, lean) share: turn a joint by a model-space rotation
// about its own position, keep it within its limit, and refresh the model poses below it.

#include <span>

#include "ik/skeleton.h"

namespace deixis::ik {

// Rotates `joint` by `C_model` (model space), clamps its rotation away from its rest local pose to
// `max_angle`, writes the new local rotation and recomputes model poses on the path from `joint`
// down to `path_end` (a descendant, or `joint` itself). Returns the model-space rotation actually
// applied (C_model after the clamp): the whole subtree below `joint` turned by it about the
// joint, so a caller can follow a point further down without recomputing the path to it. No
// allocation.
Mat3 rotate_joint_limited(const Skeleton& skeleton, std::span<Pose> local, std::span<Pose> model,
                          int joint, const Mat3& C_model, float max_angle, int path_end);

// The model rotation of `joint`'s parent (identity for a root).
inline Mat3 parent_rotation(const Skeleton& skeleton, std::span<const Pose> model, int joint) {
  const int parent = skeleton.parents[joint];
  return parent == kNoParent ? Mat3::Identity() : model[parent].rotation;
}

}  // namespace deixis::ik
