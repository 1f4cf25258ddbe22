#pragma once
// The tracking a site would have sent for a recorded skeleton (docs/bvh.md#tracking): per frame,
// forward kinematics, then H between the eyes, the gaze (head forward: recordings have no eyes),
// both wrist poses in the wrist-frame convention of docs/decisions.md §7 and both index
// fingertips; and a BodyCalibration from the first upright frame.
//
// Joints are found by role (JointRoles): the CMU, Mixamo and generic names of docs/bvh.md. A
// missing required joint (the head, either hand) is a deixis::Error naming it.

#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "core/tracking.h"
#include "mocap/bvh.h"

namespace deixis::mocap {

// Node indices into Bvh::nodes; -1 where the recording has none.
struct JointRoles {
  int head = -1;
  int head_top = -1;                        // an end site or "top"/"end" joint above the head
  std::array<int, 2> hand = {-1, -1};       // the wrist joint, by Hand
  std::array<int, 2> elbow = {-1, -1};      // nearest ancestor of the hand at a distance
  std::array<int, 2> shoulder = {-1, -1};   // nearest ancestor of the elbow at a distance
  std::array<int, 2> index_tip = {-1, -1};  // the end of the index (or fingers) chain
};

// Roles from names (docs/bvh.md#joint-names); throws naming a missing head or hand.
JointRoles find_roles(const Bvh& bvh);

class SkeletonTracking {
 public:
  // Sizes everything; throws when a required joint is missing.
  SkeletonTracking(const Bvh& bvh, double metres_per_unit);

  // Frame `i` of the recording (time = i x frame time). Allocates nothing.
  void track(std::size_t i, TrackingFrame& out);
  // Any row of channel values (e.g. interpolated), at `time`. Allocates nothing.
  void track_row(std::span<const float> row, double time, TrackingFrame& out);

  // The body calibration from the first upright frame (spine within 30° of vertical, head above
  // both wrists); deixis::Error when no frame is upright.
  BodyCalibration calibrate(Hand deictic_hand = Hand::kRight);
  std::size_t upright_frame();
  // Where the person stands at frame `i` (docs/bvh.md#driving-a-site): under the root joint, at
  // the height of the frame's lowest node, facing where the root faces (the rest pose's forward
  // turned by the root joint's rotation, about the vertical only; the head's where the root
  // points up or down). Yaw only, −Z forward. Allocates nothing; poses() become frame i's.
  Pose ground(std::size_t i);

  const JointRoles& roles() const { return roles_; }
  double rest_stature() const { return stature_; }                // m, the rest pose's height
  const std::vector<JointPose>& poses() const { return poses_; }  // of the last track call

 private:
  const Bvh& bvh_;
  double scale_;
  JointRoles roles_;
  double stature_ = 0;
  Eigen::Matrix3d rest_frame_;                    // columns right, up, back of the rest pose
  Eigen::Vector3d head_top_in_head_;              // head-local (rest axes), metres
  std::array<Eigen::Matrix3d, 2> wrist_in_hand_;  // §7 wrist frame in the hand joint's frame
  std::array<Eigen::Vector3d, 2> tip_in_wrist_;   // estimated tip, §7 wrist frame (no fingers)
  std::vector<JointPose> poses_;
};

}  // namespace deixis::mocap
