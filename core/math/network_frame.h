#pragma once
// The network boundary. The authors' networks were trained on Unity data: left-handed, +Y up,
// +Z forward. Deixis' world frame is OpenXR's: right-handed, +Y up, −Z forward
// (docs/conventions.md#network-frame). Every vector that enters or leaves a network passes
// through this adapter and nowhere else: positions and directions flip z, a rotation R becomes
// S·R·S with S = diag(1, 1, −1). The map is its own inverse, so one function serves both
// directions.
//
// Also here: the layout of the networks' vectors (the 24 end-effectors x, the 5-value target
// feature) and the left-hand mirroring (docs/conventions.md#left-hand-mirroring).

#include <array>
#include <span>

#include "core/math/pose.h"

namespace deixis {

// ---- world <-> network frame -------------------------------------------------------------------

inline Vec3 to_network_frame(const Vec3& v) {
  return {v.x(), v.y(), -v.z()};
}
inline Vec3 from_network_frame(const Vec3& v) {
  return to_network_frame(v);
}

// S·R·S with S = diag(1, 1, −1): negate the entries that mix z with x or y.
inline Mat3 to_network_frame(const Mat3& R) {
  Mat3 out = R;
  out(0, 2) = -out(0, 2);
  out(1, 2) = -out(1, 2);
  out(2, 0) = -out(2, 0);
  out(2, 1) = -out(2, 1);
  return out;
}
inline Mat3 from_network_frame(const Mat3& R) {
  return to_network_frame(R);
}

inline Pose to_network_frame(const Pose& T) {
  return {to_network_frame(T.rotation), to_network_frame(T.translation)};
}
inline Pose from_network_frame(const Pose& T) {
  return to_network_frame(T);
}

// ---- the 24 end-effectors x (docs/conventions.md#end-effectors), network frame -----------------

inline constexpr int kEndEffectorSize = 24;
using EndEffectors = std::array<float, kEndEffectorSize>;

// Offsets of the parts of x.
namespace ee {
inline constexpr int kGaze = 0;           // eye-gaze unit direction, head frame
inline constexpr int kHeadForward = 3;    // head 6D forward, root frame
inline constexpr int kHeadUp = 6;         // head 6D up, root frame
inline constexpr int kHeadPosition = 9;   // head position relative to root O (m)
inline constexpr int kHandForward = 12;   // deictic hand 6D forward, head frame
inline constexpr int kHandUp = 15;        // deictic hand 6D up, head frame
inline constexpr int kHandPosition = 18;  // wrist position, head frame (m)
inline constexpr int kFingertip = 21;     // index fingertip position, hand frame (m)
inline constexpr std::array<int, 8> kAllVectors = {
    kGaze, kHeadForward, kHeadUp, kHeadPosition, kHandForward, kHandUp, kHandPosition, kFingertip};
}  // namespace ee

inline Vec3 get_vec3(std::span<const float, kEndEffectorSize> x, int offset) {
  return {x[offset], x[offset + 1], x[offset + 2]};
}
inline void set_vec3(std::span<float, kEndEffectorSize> x, int offset, const Vec3& v) {
  x[offset] = v.x();
  x[offset + 1] = v.y();
  x[offset + 2] = v.z();
}

// ---- the target feature (θ^H, φ^H, θ^R, φ^R, r^R), docs/conventions.md#target-feature ----------

inline constexpr int kTargetFeatureSize = 5;
using TargetFeature = std::array<float, kTargetFeatureSize>;
namespace tf {
inline constexpr int kHeadTheta = 0;
inline constexpr int kHeadPhi = 1;
inline constexpr int kHandTheta = 2;
inline constexpr int kHandPhi = 3;
inline constexpr int kHandDistance = 4;
}  // namespace tf

// Pointing is distance-invariant beyond arm's reach, so r is clamped (paper §IV.A).
inline constexpr float kTargetDistanceClamp = 1.0f;

// θ = atan2(−x, z) (positive to the left), φ = atan2(z, y) (angle from +Y in the y–z plane; not a
// true elevation, but what the released weights expect), r = min(|p|, 1 m). `p` is the target
// relative to root O, in the network frame.
struct TargetAngles {
  float theta;
  float phi;
  float distance;
};
TargetAngles target_angles(const Vec3& p_root_target_network);

// Fills the 5-value target feature from head-target and hand-target positions (root frame O,
// network frame).
TargetFeature target_feature(const Vec3& head_target, const Vec3& hand_target);

// ---- left-hand mirroring (docs/conventions.md#left-hand-mirroring) ------------------------------
// The left-hand checkpoints expect right-handed data mirrored through the y–z plane: negate the x
// component of all eight 3-vectors of x and negate both θ. φ, r and the MPNet angles are mirror
// invariant. Each function is its own inverse, applied on the way in and on the way out.

void mirror_end_effectors(std::span<float, kEndEffectorSize> x);
void mirror_target_feature(std::span<float, kTargetFeatureSize> t);

}  // namespace deixis
