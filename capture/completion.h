#pragma once
// Completion states of deictic gestures (paper §III.A, after Kang et al. 2023): pointing is
// complete when the ray from the *dominant* eye through the index fingertip passes through the
// target (so eye dominance changes the pose); touching when the fingertip is on the target's
// surface.

#include <optional>

#include "capture/body.h"
#include "core/target_map.h"

namespace deixis::capture {

struct CompletionPose {
  Pose wrist;
  Vec3 tip = Vec3::Zero();
  float ray_distance = 0;  // pointing: dominant eye → fingertip (m)
};

// Pointing at `target` from a torso and head pose. The fingertip sits on the dominant eye's ray
// at the distance where the shoulder-to-fingertip distance is the subject's arm extension (a
// near target stops the fingertip short of it); the finger follows the arm, tilted up a little,
// back of the hand up (the authors' completion poses, docs/decisions.md §7).
CompletionPose pointing_pose(const Body& body, Hand hand, const Pose& T_world_torso,
                             const Mat3& R_world_head, const Vec3& target);

// Touching `target` from a torso pose: the fingertip on the point of the surface nearest the
// shoulder, the finger along the shoulder → contact line. Empty when the wrist would be out of
// reach from this torso pose.
std::optional<CompletionPose> touching_pose(const Body& body, Hand hand, const Pose& T_world_torso,
                                            const TargetObject& target);

// The largest shoulder → wrist distance a completion pose may use (a fully straight arm looks
// locked and leaves the elbow undefined).
inline float comfortable_reach(const Body& body) {
  return 0.97f * body.reach();
}

}  // namespace deixis::capture
