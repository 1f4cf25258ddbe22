#include "gesture/features.h"

#include <cmath>

#include "core/math/rotation_6d.h"

namespace deixis {

namespace {

const Vec3 kForward(0, 0, -1);  // world frame's forward axis of a head or root
const Vec3 kDown(0, -1, 0);

// The rotation and position parts of x for one pose, in the network frame.
void write_pose(const Pose& T_network, int forward_at, int up_at, int position_at,
                EndEffectors& x) {
  const Rotation6D r = encode_6d(T_network.rotation);
  set_vec3(x, forward_at, r.forward);
  set_vec3(x, up_at, r.up);
  if (position_at >= 0) {
    set_vec3(x, position_at, T_network.translation);
  }
}

Pose decode_pose(const EndEffectors& x, int forward_at, int up_at, int position_at) {
  const Mat3 R = decode_6d(get_vec3(x, forward_at), get_vec3(x, up_at));
  return from_network_frame(Pose{R, get_vec3(x, position_at)});
}

}  // namespace

float unsigned_angle(const Vec3& a, const Vec3& b) {
  const float cross = a.cross(b).norm();
  const float dot = a.dot(b);
  if (cross == 0.0f && dot == 0.0f) {
    return 0.0f;
  }
  return std::atan2(cross, dot);
}

TargetFeature target_feature_from_root(const Pose& T_world_root, const Vec3& head_target_world,
                                       const Vec3& hand_target_world) {
  const Pose T_root_world = inverse(T_world_root);
  return target_feature(to_network_frame(transform_point(T_root_world, head_target_world)),
                        to_network_frame(transform_point(T_root_world, hand_target_world)));
}

MpnetFeatureRow mpnet_features(const TrackingFrame& frame, const BodyCalibration& body) {
  const Hand hand = body.deictic_hand;
  const Vec3 head = frame.T_world_head.translation;
  const Vec3 head_forward = frame.T_world_head.rotation * kForward;
  const Vec3 to_head_target = frame.head_target_position - head;
  const Vec3 to_hand_target = frame.hand_target_position - head;
  const Vec3 to_finger = frame.index_tip[index(hand)] - head;
  const Vec3 rest_wrist = transform_point(body.T_world_root, body.rest_wrist_in_root[index(hand)]);
  const float wrist_from_rest = (frame.T_world_wrist[index(hand)].translation - rest_wrist).norm();

  MpnetFeatureRow row{};
  row[mf::kEyeToHeadTarget] = unsigned_angle(frame.gaze, to_head_target);
  row[mf::kHeadToHeadTarget] = unsigned_angle(head_forward, to_head_target);
  row[mf::kFingerToHandTarget] = unsigned_angle(to_finger, to_hand_target);
  row[mf::kHeadToFinger] = unsigned_angle(head_forward, to_finger);
  row[mf::kFingerToDown] = unsigned_angle(to_finger, kDown);
  row[mf::kNearRest] = wrist_from_rest < kNearRestDistance ? 1.0f : 0.0f;
  const TargetFeature t = target_feature_from_root(body.T_world_root, frame.head_target_position,
                                                   frame.hand_target_position);
  for (int k = 0; k < kTargetFeatureSize; ++k) {
    row[mf::kTarget + k] = t[k];
  }
  return row;
}

EndEffectors end_effectors(const TrackingFrame& frame, const BodyCalibration& body) {
  const Hand hand = body.deictic_hand;
  const Pose& T_world_head = frame.T_world_head;
  const Pose& T_world_wrist = frame.T_world_wrist[index(hand)];
  const Pose T_root_head = compose(inverse(body.T_world_root), T_world_head);
  const Pose T_head_wrist = compose(inverse(T_world_head), T_world_wrist);
  const Vec3 gaze_in_head = T_world_head.rotation.transpose() * frame.gaze;
  const Vec3 tip_in_wrist = transform_point(inverse(T_world_wrist), frame.index_tip[index(hand)]);

  EndEffectors x{};
  set_vec3(x, ee::kGaze, to_network_frame(gaze_in_head));
  write_pose(to_network_frame(T_root_head), ee::kHeadForward, ee::kHeadUp, ee::kHeadPosition, x);
  write_pose(to_network_frame(T_head_wrist), ee::kHandForward, ee::kHandUp, ee::kHandPosition, x);
  set_vec3(x, ee::kFingertip, to_network_frame(tip_in_wrist));
  return x;
}

EndEffectorPoses decode_end_effectors(const EndEffectors& x, const Pose& T_world_root) {
  EndEffectorPoses out;
  const Pose T_root_head = decode_pose(x, ee::kHeadForward, ee::kHeadUp, ee::kHeadPosition);
  const Pose T_head_wrist = decode_pose(x, ee::kHandForward, ee::kHandUp, ee::kHandPosition);
  out.T_world_head = compose(T_world_root, T_root_head);
  out.T_world_wrist = compose(out.T_world_head, T_head_wrist);
  Vec3 gaze_in_head = from_network_frame(get_vec3(x, ee::kGaze));
  gaze_in_head = gaze_in_head.allFinite() && gaze_in_head.norm() > 1e-6f
                     ? Vec3(gaze_in_head.normalized())
                     : Vec3(0, 0, -1);
  out.gaze = out.T_world_head.rotation * gaze_in_head;
  out.index_tip =
      transform_point(out.T_world_wrist, from_network_frame(get_vec3(x, ee::kFingertip)));
  return out;
}

}  // namespace deixis
