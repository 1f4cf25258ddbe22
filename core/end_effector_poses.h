#pragma once
// The avatar's end-effectors as world poses: what the translator decodes from the networks'
// output (gesture/features.h, decode_end_effectors) and what whole-avatar IK reaches for
// (ik/avatar_solver.h). Plain data, here so that neither library includes the other.

#include "core/math/pose.h"

namespace deixis {

struct EndEffectorPoses {
  Vec3 gaze;           // unit, world
  Pose T_world_head;   // H
  Pose T_world_wrist;  // the deictic hand's wrist
  Vec3 index_tip;      // world
};

}  // namespace deixis
