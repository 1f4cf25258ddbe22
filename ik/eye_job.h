#pragma once
// The eyes look along the gaze direction (ozz-style job; docs/ik.md). The networks give one
// combined gaze direction; both eyes turn to it (parallel lines of sight: the gaze carries no
// fixation distance), clamped to the eyes' range of motion measured in the face's frame (−Z
// forward, +Y up in the rest pose): yaw left/right, pitch up, pitch down.

#include <span>
#include <string_view>

#include "ik/joint_limits.h"
#include "ik/skeleton.h"

namespace deixis::ik {

struct EyeJob {
  bool validate(std::string_view* reason = nullptr) const;
  bool run() const;  // validates first; false (outputs untouched) when invalid

  // ---- inputs ----
  const Skeleton* skeleton = nullptr;
  std::span<const Pose> rest_model;  // T_model_joint of every joint in the rest pose
  int head = -1;                     // the joint whose rest frame defines the face
  std::span<const int> eyes;         // 1 or 2 eye joints below the head
  Vec3 gaze = Vec3(0, 0, -1);        // model space; zero or non-finite: eyes look straight ahead
  EyeRange range;

  // ---- in/out ----
  std::span<Pose> local;  // the eyes' rotations are rewritten
  std::span<Pose> model;  // current on input for the head and the eyes' parents; the eyes'
                          // model poses are updated

  // ---- outputs ----
  bool* reached = nullptr;  // optional: the gaze was within range (nothing clamped)
};

}  // namespace deixis::ik
