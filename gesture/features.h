#pragma once
// The feature code shared by the runtime and the dataset writer (one implementation): from a
// person's tracking frame and calibration, MPNet's 11 inputs and the 24 end-effectors, exactly as
// DESIGN §4 and NOTES §2–§4 define them; and back from end-effectors to world poses for IK.
//
// Conventions: angles in radians; vectors entering or leaving a network pass through the
// network-frame adapter (gesture/math/network_frame.h); left-handed people are mirrored so that
// the networks always see a right-handed person (DESIGN §4).

#include <array>

#include "gesture/math/network_frame.h"
#include "gesture/tracking.h"

namespace deixis {

inline constexpr int kMpnetFeatureCount = 11;
using MpnetFeatureRow = std::array<float, kMpnetFeatureCount>;

// Columns of an MPNet row (NOTES §3.1).
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

// The target feature (θ^H, φ^H, θ^R, φ^R, r^R) of two world positions seen from a root (NOTES
// §2.4), in the network frame, mirrored for a left-handed person.
TargetFeature target_feature_from_root(const Pose& T_world_root, const Vec3& head_target_world,
                                       const Vec3& hand_target_world, Hand deictic_hand);

// MPNet's 11 inputs for one frame of a person whose tracking is complete (the caller substitutes
// held frames for missing ones). Targets are the frame's head and hand target positions.
MpnetFeatureRow mpnet_features(const TrackingFrame& frame, const BodyCalibration& body);

// The person's end-effectors x (network frame; a left-handed person is mirrored): gaze in the head
// frame, head relative to root O, deictic wrist in the head frame, index fingertip in the wrist
// frame.
EndEffectors end_effectors(const TrackingFrame& frame, const BodyCalibration& body);

// World poses decoded from end-effectors x (as the networks produce them: network frame, mirrored
// for a left-handed person), for a body whose root is T_world_root. Rotations are decoded with
// Gram–Schmidt (always proper). The input of IK and of the metrics.
struct EndEffectorPoses {
  Vec3 gaze;           // unit, world
  Pose T_world_head;   // H
  Pose T_world_wrist;  // the deictic hand's wrist
  Vec3 index_tip;      // world
};
EndEffectorPoses decode_end_effectors(const EndEffectors& x, const Pose& T_world_root,
                                      Hand deictic_hand);

}  // namespace deixis
