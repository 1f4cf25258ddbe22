#include "capture/completion.h"

#include <algorithm>
#include <cmath>

#include "capture/posture.h"

namespace deixis::capture {

namespace {

// The finger points a little above the shoulder → fingertip line (≈ 10°; in the authors'
// pointing pose the wrist → fingertip vector rises 28° while the shoulder → fingertip line rises
// about 18°).
Vec3 finger_direction(const Vec3& shoulder, const Vec3& tip) {
  return ((tip - shoulder).normalized() + Vec3(0, 0.18f, 0)).normalized();
}

Vec3 dorsal_reference(const Vec3& finger) {
  // Back of the hand up; when the finger is near vertical, back of the hand toward the finger's
  // horizontal heading's opposite (the palm faces the target).
  if (std::abs(finger.y()) < 0.9f) {
    return Vec3::UnitY();
  }
  return Vec3(0, 0, 1);
}

}  // namespace

CompletionPose pointing_pose(const Body& body, Hand hand, const Pose& T_world_torso,
                             const Mat3& R_world_head, const Vec3& target) {
  const Vec3 eye = eye_position(body, T_world_torso, R_world_head, body.subject.dominant_eye);
  const Vec3 shoulder = shoulder_position(body, T_world_torso, hand);
  const Vec3 to_target = target - eye;
  const float target_distance = to_target.norm();
  const Vec3 u = to_target / target_distance;
  const Vec3 eye_from_shoulder = eye - shoulder;
  const float b = u.dot(eye_from_shoulder);
  const float c0 = eye_from_shoulder.squaredNorm();

  float extension = body.subject.style.arm_extension;
  CompletionPose pose;
  for (int attempt = 0; attempt < 40; ++attempt, extension -= 0.01f) {
    // |eye + λu − shoulder| = extension · (arm length): the far root of the quadratic.
    const float L = extension * (body.reach() + body.tip_in_wrist[index(hand)].norm());
    const float disc = b * b - (c0 - L * L);
    float lambda = disc > 0 ? -b + std::sqrt(disc) : 0.3f;
    lambda = std::clamp(lambda, 0.15f, 0.85f * target_distance);
    pose.ray_distance = lambda;
    pose.tip = eye + lambda * u;
    const Vec3 finger = finger_direction(shoulder, pose.tip);
    const Mat3 R = wrist_rotation_for_finger(body, hand, finger, dorsal_reference(finger));
    pose.wrist = Pose{R, pose.tip - R * body.tip_in_wrist[index(hand)]};
    if ((pose.wrist.translation - shoulder).norm() <= comfortable_reach(body)) {
      break;
    }
  }
  return pose;
}

std::optional<CompletionPose> touching_pose(const Body& body, Hand hand, const Pose& T_world_torso,
                                            const TargetObject& target) {
  const Vec3 shoulder = shoulder_position(body, T_world_torso, hand);
  CompletionPose pose;
  pose.tip = closest_surface_point(target, shoulder);
  const Vec3 finger = finger_direction(shoulder, pose.tip);
  const Mat3 R = wrist_rotation_for_finger(body, hand, finger, dorsal_reference(finger));
  pose.wrist = Pose{R, pose.tip - R * body.tip_in_wrist[index(hand)]};
  if ((pose.wrist.translation - shoulder).norm() > comfortable_reach(body)) {
    return std::nullopt;
  }
  return pose;
}

}  // namespace deixis::capture
