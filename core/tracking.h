#pragma once
// What a site knows about its user at one tick, and about the user's body. These are the data the
// synthetic capture records, the network carries and the translator reads
// (docs/conventions.md#tracking-frame).
//
// Everything is in the sender's world frame (OpenXR convention: right-handed, +Y up, −Z forward),
// in metres and seconds. Wrist frames follow docs/decisions.md §7: x = distal for the right hand
// and proximal for the left, y = dorsal (back of the hand), z = ulnar (little-finger side).

#include <array>
#include <cstdint>

#include "core/math/pose.h"

namespace deixis {

enum class Hand : std::uint8_t { kLeft = 0, kRight = 1 };
inline constexpr Hand other(Hand h) {
  return h == Hand::kLeft ? Hand::kRight : Hand::kLeft;
}
inline constexpr int index(Hand h) {
  return static_cast<int>(h);
}

// Objects are identified across sites by id (docs/target-map.md). kNoTarget: nothing designated.
using TargetId = std::int32_t;
inline constexpr TargetId kNoTarget = -1;

// Validity flags of a tracking frame; a part whose flag is clear must not be read.
namespace tracked {
inline constexpr std::uint8_t kHead = 1u << 0;
inline constexpr std::uint8_t kGaze = 1u << 1;
inline constexpr std::uint8_t kLeftHand = 1u << 2;   // wrist pose and index fingertip
inline constexpr std::uint8_t kRightHand = 1u << 3;  // wrist pose and index fingertip
inline constexpr std::uint8_t kAll = kHead | kGaze | kLeftHand | kRightHand;
inline constexpr std::uint8_t hand(Hand h) {
  return h == Hand::kLeft ? kLeftHand : kRightHand;
}
}  // namespace tracked

struct TrackingFrame {
  double time = 0.0;                  // sender's clock (s)
  Pose T_world_head;                  // H: the midpoint between the eyes; −Z forward, +Y up
  Vec3 gaze = Vec3(0, 0, -1);         // combined eye-gaze direction, unit, world frame
  std::array<Pose, 2> T_world_wrist;  // indexed by Hand
  std::array<Vec3, 2> index_tip = {Vec3::Zero(), Vec3::Zero()};  // world positions, by Hand
  std::uint8_t valid = 0;                                        // tracked::* flags

  // What the person looks at and points at or touches, with the objects' positions in the
  // sender's room (target selection is the sender's business; paper §I).
  TargetId head_target = kNoTarget;
  TargetId hand_target = kNoTarget;
  Vec3 head_target_position = Vec3::Zero();
  Vec3 hand_target_position = Vec3::Zero();
};

// A person's body and calibrated upright posture (paper §IV.A): root O sits at the head's position
// in the upright posture with a yaw-only orientation (its −Z is the facing direction). Sent once
// per session (docs/protocol.md §4.4, hello).
struct BodyCalibration {
  float height = 1.70f;      // m, standing; the blend's size ratio (docs/conventions.md#blending)
  float arm_length = 0.74f;  // m, shoulder to fingertip
  Hand deictic_hand = Hand::kRight;  // the hand that points and touches
  Pose T_world_root;                 // O, yaw-only
  // Wrist positions in the upright posture, in the root frame (for MPNet's distance feature d).
  std::array<Vec3, 2> rest_wrist_in_root = {Vec3(-0.2f, -0.75f, 0.0f), Vec3(0.2f, -0.75f, 0.0f)};
};

}  // namespace deixis
