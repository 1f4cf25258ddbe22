// A headset user's body calibration from an upright frame (gesture/upright_calibration.h).

#include "gesture/upright_calibration.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace deixis {
namespace {

constexpr float kDeg = 3.14159265f / 180.0f;

// Standing at (1, ·, 2) with eyes 1.60 m up, turned 30° left and looking 10° down, the arms
// hanging 0.75 m below the eyes.
TrackingFrame standing() {
  TrackingFrame f;
  f.T_world_head.rotation =
      (Eigen::AngleAxisf(30 * kDeg, Vec3::UnitY()) * Eigen::AngleAxisf(-10 * kDeg, Vec3::UnitX()))
          .toRotationMatrix();
  f.T_world_head.translation = Vec3(1.0f, 1.6f, 2.0f);
  const Mat3 yaw = Eigen::AngleAxisf(30 * kDeg, Vec3::UnitY()).toRotationMatrix();
  f.T_world_wrist[0].translation = f.T_world_head.translation + yaw * Vec3(-0.21f, -0.75f, 0.02f);
  f.T_world_wrist[1].translation = f.T_world_head.translation + yaw * Vec3(0.19f, -0.76f, 0.01f);
  f.valid = tracked::kAll;
  return f;
}

TEST(UprightCalibration, RootAtTheHeadWithItsYawOnly) {
  const BodyCalibration c = calibrate_upright(standing(), {});
  EXPECT_TRUE(c.T_world_root.translation.isApprox(Vec3(1.0f, 1.6f, 2.0f)));
  const Mat3 expected = Eigen::AngleAxisf(30 * kDeg, Vec3::UnitY()).toRotationMatrix();
  EXPECT_TRUE(c.T_world_root.rotation.isApprox(expected, 1e-5f));  // the 10° pitch is gone
}

TEST(UprightCalibration, StatureFromTheEyeHeightArmFromTheStature) {
  const BodyCalibration c = calibrate_upright(standing(), {});
  EXPECT_NEAR(c.height, 1.6f / 0.936f, 1e-4f);
  EXPECT_NEAR(c.arm_length, 0.74f / 1.70f * c.height, 1e-4f);
  const BodyCalibration given = calibrate_upright(standing(), {Hand::kLeft, 1.82f, 0.8f});
  EXPECT_EQ(given.height, 1.82f);
  EXPECT_EQ(given.arm_length, 0.8f);
  EXPECT_EQ(given.deictic_hand, Hand::kLeft);
}

TEST(UprightCalibration, RestWristsWhereTheHandsHang) {
  const BodyCalibration c = calibrate_upright(standing(), {});
  EXPECT_TRUE(c.rest_wrist_in_root[0].isApprox(Vec3(-0.21f, -0.75f, 0.02f), 1e-4f));
  EXPECT_TRUE(c.rest_wrist_in_root[1].isApprox(Vec3(0.19f, -0.76f, 0.01f), 1e-4f));
}

TEST(UprightCalibration, UntrackedOrRaisedHandsGetTheScaledDefault) {
  TrackingFrame f = standing();
  f.valid = tracked::kHead | tracked::kGaze | tracked::kRightHand;
  f.T_world_wrist[1].translation.y() = 1.4f;  // raised: not the rest posture
  const BodyCalibration c = calibrate_upright(f, {Hand::kRight, 1.87f, 0.0f});
  const BodyCalibration defaults;
  for (int h = 0; h < 2; ++h) {
    EXPECT_TRUE(c.rest_wrist_in_root[h].isApprox(defaults.rest_wrist_in_root[h] * 1.1f, 1e-4f))
        << h;
  }
}

TEST(UprightCalibration, RefusesAnUntrackedHeadOrAnImpossibleStature) {
  TrackingFrame f = standing();
  f.valid = tracked::kRightHand;
  EXPECT_THROW(calibrate_upright(f, {}), Error);
  TrackingFrame floor = standing();
  floor.T_world_head.translation.y() = 0.3f;  // a LOCAL-space origin at the eyes, not the floor
  try {
    calibrate_upright(floor, {});
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("STAGE floor"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace deixis
