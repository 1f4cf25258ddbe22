#include "gesture/upright_calibration.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace deixis {

namespace {

constexpr float kEyeHeightRatio = 0.936f;   // eye height / stature
constexpr float kArmRatio = 0.74f / 1.70f;  // shoulder-to-fingertip / stature
constexpr float kReferenceHeight = 1.70f;   // the default rest wrists' stature
constexpr float kHangingBelowHead = 0.45f;  // m: a wrist this far below the eyes hangs

// The head's heading as a rotation about +Y (its −Z projected on the floor).
Mat3 yaw_of(const Mat3& R_world_head) {
  const Vec3 forward = R_world_head * Vec3(0, 0, -1);
  const float yaw = std::atan2(-forward.x(), -forward.z());
  return Eigen::AngleAxisf(yaw, Vec3::UnitY()).toRotationMatrix();
}

}  // namespace

BodyCalibration calibrate_upright(const TrackingFrame& upright, const UprightBody& body) {
  if ((upright.valid & tracked::kHead) == 0) {
    throw Error("calibration: the head is not tracked in the upright frame");
  }
  const Vec3& head = upright.T_world_head.translation;
  BodyCalibration c;
  c.deictic_hand = body.deictic_hand;
  c.height = body.height > 0.0f ? body.height : head.y() / kEyeHeightRatio;
  if (!(c.height >= 1.0f && c.height <= 2.3f)) {
    throw Error("calibration: a stature of " + std::to_string(c.height) +
                " m is outside 1.0–2.3 m (eye height " + std::to_string(head.y()) +
                " m above the floor; is the STAGE floor at y = 0?)");
  }
  c.arm_length = body.arm_length > 0.0f ? body.arm_length : kArmRatio * c.height;
  c.T_world_root = Pose{yaw_of(upright.T_world_head.rotation), head};
  const Pose T_root_world = inverse(c.T_world_root);
  const BodyCalibration defaults;
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const auto i = static_cast<std::size_t>(index(h));
    const Vec3& wrist = upright.T_world_wrist[i].translation;
    const bool hanging =
        (upright.valid & tracked::hand(h)) != 0 && head.y() - wrist.y() >= kHangingBelowHead;
    c.rest_wrist_in_root[i] = hanging
                                  ? transform_point(T_root_world, wrist)
                                  : defaults.rest_wrist_in_root[i] * (c.height / kReferenceHeight);
  }
  return c;
}

}  // namespace deixis
