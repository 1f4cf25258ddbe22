#pragma once
// What Deixis measures on an avatar's rest pose (model frame: +Y up, facing −Z): the eye midpoint
// H, the index fingertips, the height and the arm length (ik::HumanoidRig's measured fields).
//
//   H          midpoint of the two eye joints; without them, estimated from the head's mesh: the
//              eye line 0.064 × height below the top of the head (eyes at 0.936 of stature) and
//              0.02 × height behind the front of the face.
//   fingertip  the file's end site below the distal index joint; else the farthest point of the
//              distal joint's own vertices along the bone; else the distal bone extended by 0.8
//              of the previous phalanx.
//   height     top of the mesh minus its bottom.
//   arm length summed along the chain upper arm → lower arm → hand → index joints → fingertip
//              (the straight-line distance when the arm and finger are straight); the mean of
//              both arms. Without an index chain the hand adds 0.108 × height (Winter).

#include <array>
#include <optional>

#include "avatar/skinned_mesh.h"
#include "ik/humanoid.h"

namespace deixis::avatar {

// `tip_end_sites`, by deixis::Hand: the fingertip in the distal index joint's frame when the file
// has one. The rig's skeleton and bone map must be complete.
void measure_rig(ik::HumanoidRig& rig, const SkinnedMesh& mesh,
                 const std::array<std::optional<Vec3>, 2>& tip_end_sites);

}  // namespace deixis::avatar
