#include "api/conversions.h"

#include <cmath>

#include "core/error.h"

namespace deixis::api {

namespace {

Hand hand_from_c(std::int32_t hand, const char* what) {
  if (hand != DEIXIS_HAND_LEFT && hand != DEIXIS_HAND_RIGHT) {
    throw Error(std::string(what) + ": " + std::to_string(hand) +
                " is not a hand (DEIXIS_HAND_LEFT 0 or DEIXIS_HAND_RIGHT 1)");
  }
  return static_cast<Hand>(hand);
}

}  // namespace

Vec3 from_c(const deixis_vec3& v) {
  return {v.x, v.y, v.z};
}

deixis_vec3 to_c(const Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

Pose from_c(const deixis_pose& pose) {
  const Quat q(pose.orientation.w, pose.orientation.x, pose.orientation.y, pose.orientation.z);
  const float norm = q.norm();
  // A zero quaternion becomes NaN here on purpose: it is not a rotation, and the translator
  // holds the last valid frame over a non-finite one.
  const Quat unit(q.coeffs() / norm);
  return {unit.toRotationMatrix(), from_c(pose.position)};
}

deixis_pose to_c(const Pose& pose) {
  const Quat q(pose.rotation);
  return {to_c(pose.translation), {q.x(), q.y(), q.z(), q.w()}};
}

TrackingFrame from_c(const deixis_tracking_frame& c) {
  TrackingFrame f;
  f.time = c.time;
  f.T_world_head = from_c(c.head);
  f.gaze = from_c(c.gaze);
  for (int h = 0; h < 2; ++h) {
    f.T_world_wrist[h] = from_c(c.wrist[h]);
    f.index_tip[h] = from_c(c.index_tip[h]);
  }
  f.valid = static_cast<std::uint8_t>(c.valid & tracked::kAll);
  f.head_target = c.head_target;
  f.hand_target = c.hand_target;
  f.head_target_position = from_c(c.head_target_position);
  f.hand_target_position = from_c(c.hand_target_position);
  return f;
}

deixis_tracking_frame to_c(const TrackingFrame& f) {
  deixis_tracking_frame c{};
  c.time = f.time;
  c.head = to_c(f.T_world_head);
  c.gaze = to_c(f.gaze);
  for (int h = 0; h < 2; ++h) {
    c.wrist[h] = to_c(f.T_world_wrist[h]);
    c.index_tip[h] = to_c(f.index_tip[h]);
  }
  c.valid = f.valid;
  c.head_target = f.head_target;
  c.hand_target = f.hand_target;
  c.head_target_position = to_c(f.head_target_position);
  c.hand_target_position = to_c(f.hand_target_position);
  return c;
}

BodyCalibration from_c(const deixis_body_calibration& c) {
  BodyCalibration b;
  b.height = c.height;
  b.arm_length = c.arm_length;
  b.deictic_hand = hand_from_c(c.deictic_hand, "deictic_hand");
  b.T_world_root = from_c(c.root);
  for (int h = 0; h < 2; ++h) {
    b.rest_wrist_in_root[h] = from_c(c.rest_wrist_in_root[h]);
  }
  return b;
}

deixis_body_calibration to_c(const BodyCalibration& b) {
  deixis_body_calibration c{};
  c.height = b.height;
  c.arm_length = b.arm_length;
  c.deictic_hand = index(b.deictic_hand);
  c.root = to_c(b.T_world_root);
  for (int h = 0; h < 2; ++h) {
    c.rest_wrist_in_root[h] = to_c(b.rest_wrist_in_root[h]);
  }
  return c;
}

}  // namespace deixis::api
