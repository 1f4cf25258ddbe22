#pragma once
// Hand-built tracking frames of a standing person for translator tests (the synthetic capture
// makes realistic motion; these are simple, readable poses).

#include "core/math/pose.h"
#include "core/tracking.h"

namespace deixis::testing {

// A wrist frame per docs/decisions.md §7 with the fingers along `distal` and the back of the hand
// facing `dorsal` (both world, roughly perpendicular).
inline Pose wrist_pose(Hand hand, const Vec3& position, const Vec3& distal, const Vec3& dorsal) {
  const Vec3 x = (hand == Hand::kRight ? distal : Vec3(-distal)).normalized();
  const Vec3 y = (dorsal - dorsal.dot(x) * x).normalized();
  Mat3 R;
  R.col(0) = x;
  R.col(1) = y;
  R.col(2) = x.cross(y);
  return {R, position};
}

// A person of `height` standing at the origin facing −Z, head level, both hands hanging, looking
// at and "targeting" objects at the given positions. Root O is the head position.
struct StandingPerson {
  BodyCalibration body;
  TrackingFrame frame;

  explicit StandingPerson(Hand deictic = Hand::kRight, float height = 1.70f) {
    const float eye_height = height * 0.94f;
    body.height = height;
    body.deictic_hand = deictic;
    body.T_world_root = Pose{Mat3::Identity(), Vec3(0, eye_height, 0)};
    for (const Hand h : {Hand::kLeft, Hand::kRight}) {
      const float side = h == Hand::kRight ? 1.0f : -1.0f;
      const Vec3 wrist(0.2f * side, eye_height - 0.75f, 0.0f);
      body.rest_wrist_in_root[index(h)] = wrist - body.T_world_root.translation;
      frame.T_world_wrist[index(h)] = wrist_pose(h, wrist, Vec3(0, -1, 0), Vec3(side, 0, 0));
      frame.index_tip[index(h)] = wrist + Vec3(0, -0.15f, 0);
    }
    frame.T_world_head = Pose{Mat3::Identity(), Vec3(0, eye_height, 0)};
    frame.gaze = Vec3(0, 0, -1);
    frame.valid = tracked::kAll;
    frame.head_target = 1;
    frame.hand_target = 1;
    frame.head_target_position = Vec3(0, eye_height, -2.0f);
    frame.hand_target_position = Vec3(0, eye_height, -2.0f);
  }
};

}  // namespace deixis::testing
