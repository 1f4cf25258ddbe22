#pragma once
// The feature code shared by the runtime and the dataset writer (one implementation): from a
// person's tracking frame and calibration, MPNet's 11 inputs and the 24 end-effectors, exactly as
// docs/conventions.md defines them (#mpnet-features, #end-effectors); and back from end-effectors
// to world poses for IK.
//
// Conventions: angles in radians; vectors entering or leaving a network pass through the
// network-frame adapter (core/math/network_frame.h). A person is seen as they are: a
// left-handed person's deictic hand is their left hand, in their own (unmirrored) view, which is
// what left-hand weights expect, because they are trained on the mirror image of right-handed
// data (paper §III.C; docs/conventions.md#left-hand-mirroring; docs/decisions.md §17). So a
// left-handed person needs the left-hand weights; the mirroring itself happens only where training
// data is made.

#include <array>

#include "core/end_effector_poses.h"
#include "core/math/network_frame.h"
#include "core/tracking.h"

namespace deixis {

inline constexpr int kMpnetFeatureCount = 11;
using MpnetFeatureRow = std::array<float, kMpnetFeatureCount>;

// Columns of an MPNet row (docs/conventions.md#mpnet-features).
namespace mf {
inline constexpr int kEyeToHeadTarget = 0;     // ET^H: gaze vs H→head target
inline constexpr int kHeadToHeadTarget = 1;    // FT^H: head forward vs H→head target
inline constexpr int kFingerToHandTarget = 2;  // IT^R: H→fingertip vs H→hand target
inline constexpr int kHeadToFinger = 3;        // FI: head forward vs H→fingertip
inline constexpr int kFingerToDown = 4;        // I: H→fingertip vs world down
inline constexpr int kNearRest = 5;            // d: 1 while the hand is near its rest position
inline constexpr int kTarget = 6;              // the 5-value target feature
}  // namespace mf

// d = 1 while the deictic wrist is within this distance of its upright-posture position.
inline constexpr float kNearRestDistance = 0.25f;

// Unsigned angle between two vectors in [0, π]; 0 when either is (near) zero.
float unsigned_angle(const Vec3& a, const Vec3& b);

// The target feature (θ^H, φ^H, θ^R, φ^R, r^R) of two world positions seen from a root, in the
// network frame (docs/conventions.md#target-feature).
TargetFeature target_feature_from_root(const Pose& T_world_root, const Vec3& head_target_world,
                                       const Vec3& hand_target_world);

// MPNet's 11 inputs for one frame of a person whose tracking is complete (the caller substitutes
// held frames for missing ones). Targets are the frame's head and hand target positions.
MpnetFeatureRow mpnet_features(const TrackingFrame& frame, const BodyCalibration& body);

// The person's end-effectors x (network frame): gaze in the head frame, head relative to root O,
// the deictic hand's wrist in the head frame, its index fingertip in the wrist frame.
EndEffectors end_effectors(const TrackingFrame& frame, const BodyCalibration& body);

// World poses decoded from end-effectors x (as the networks produce them, network frame) for a
// body whose root is T_world_root; the wrist is the deictic hand's. Rotations are decoded with
// Gram–Schmidt (always proper). The input of IK.
// (EndEffectorPoses: core/end_effector_poses.h, shared with ik/.)
EndEffectorPoses decode_end_effectors(const EndEffectors& x, const Pose& T_world_root);

}  // namespace deixis
