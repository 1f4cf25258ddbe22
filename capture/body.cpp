#include "capture/body.h"

namespace deixis::capture {

namespace {

// The authors' tracker puts the right index fingertip at (0.135, −0.056, 0.017) m in the wrist
// frame (network frame, docs/decisions.md §7) for their 74 cm-arm subject; z flips into ours.
const Vec3 kTipInRightWrist(0.135f, -0.056f, -0.017f);
constexpr float kReferenceArm = 0.74f;

Mat3 frame_from(const Vec3& a, const Vec3& b_hint) {
  const Vec3 x = a.normalized();
  const Vec3 y = (b_hint - b_hint.dot(x) * x).normalized();
  Mat3 R;
  R.col(0) = x;
  R.col(1) = y;
  R.col(2) = x.cross(y);
  return R;
}

}  // namespace

float Body::eye_height() const {
  return hip_in_stance.y() + neck_in_torso.y() + eyes_in_head.y();
}

Mat3 wrist_rotation(Hand hand, const Vec3& distal, const Vec3& dorsal) {
  return frame_from(hand == Hand::kRight ? distal : Vec3(-distal), dorsal);
}

Mat3 wrist_rotation_for_finger(const Body& body, Hand hand, const Vec3& finger,
                               const Vec3& dorsal) {
  // Align the local (fingertip direction, dorsal axis) pair with the world (finger, dorsal) pair.
  const Mat3 local = frame_from(body.tip_in_wrist[index(hand)], Vec3::UnitY());
  const Mat3 world = frame_from(finger, dorsal);
  return world * local.transpose();
}

Body make_body(const Subject& subject) {
  validate(subject);
  Body b;
  b.subject = subject;
  const float h = subject.height;
  const float s = h / 1.70f;  // head and trunk details scale with height
  const float eye = 0.936f * h;
  b.hip_height = 0.52f * h;
  b.hip_in_stance = Vec3(0, b.hip_height, 0.03f * s);
  // Head pivot (upper cervical joints) below and behind the eyes.
  b.eyes_in_head = Vec3(0, 0.10f * s, -0.09f * s);
  const Vec3 neck_in_stance(0, eye - b.eyes_in_head.y(), -b.eyes_in_head.z());
  b.neck_in_torso = neck_in_stance - b.hip_in_stance;
  b.eye_separation = 0.063f * s;
  // Shoulder joint centres: 0.818 h high, inside the acromia, a little behind the eyes.
  const float half = 0.5f * subject.shoulder_width - 0.025f;
  for (const Hand hand : {Hand::kLeft, Hand::kRight}) {
    const float side = hand == Hand::kRight ? 1.0f : -1.0f;
    b.shoulder_in_torso[index(hand)] = Vec3(side * half, 0.818f * h, 0.06f * s) - b.hip_in_stance;
  }
  // Fixed bone lengths: the fingertip offset scales with the arm; upper arm and forearm share the
  // rest of the straight-arm reach 0.545 : 0.455 (Winter's segment table: 0.186 h : 0.146 h plus
  // the wrist-joint offset of the tracker).
  const float k = subject.arm_length / kReferenceArm;
  b.tip_in_wrist[index(Hand::kRight)] = k * kTipInRightWrist;
  b.tip_in_wrist[index(Hand::kLeft)] =
      k * Vec3(-kTipInRightWrist.x(), kTipInRightWrist.y(), kTipInRightWrist.z());
  const float arm = subject.arm_length - b.tip_in_wrist[1].norm();
  b.upper_arm = 0.545f * arm;
  b.forearm = 0.455f * arm;
  // Upright posture: arms hanging with a slight elbow bend, palms facing the thighs.
  for (const Hand hand : {Hand::kLeft, Hand::kRight}) {
    const float side = hand == Hand::kRight ? 1.0f : -1.0f;
    const Vec3 shoulder = b.shoulder_in_torso[index(hand)];
    const Vec3 wrist = shoulder + Vec3(side * 0.03f * s, -0.975f * b.reach(), -0.04f * s);
    b.rest_wrist_in_torso[index(hand)] =
        Pose{wrist_rotation(hand, Vec3(0, -1, -0.12f), Vec3(side, 0, 0)), wrist};
  }
  return b;
}

}  // namespace deixis::capture
