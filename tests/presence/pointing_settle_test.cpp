// Pointing settling, hand-computed: the avatar's eyes 1.6 m up, a low target 2 m ahead and 1.2 m
// down (−Z), the networks' fingertip some degrees off the eye → target ray. While the person
// points at their target and the gesture is deictic, the avatar's eye → fingertip ray ends on
// this room's copy; as the person's finger leaves theirs or the progression falls it settles
// part of the way, then not at all; far off it turns by the bound only; the user's own pose, no
// copy of the target here and non-finite inputs leave it as it is. The rotation turns about the
// eyes, so the fingertip keeps its distance from them.

#include "presence/pointing_settle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace deixis::presence {
namespace {

constexpr float kRadPerDeg = 0.0174532925f;

const Vec3 kEyes(0, 1.6f, 0);
const Vec3 kTarget(0, 0.4f, -2.0f);

// The fingertip 0.6 m from the eyes, `down_deg` further down than the ray to the target (a turn
// about +X), the way the steep rooms' worst completions missed (docs/live-rooms.md).
Vec3 tip_off_by(float down_deg) {
  const Vec3 to = (kTarget - kEyes).normalized();
  return kEyes + Eigen::AngleAxisf(-down_deg * kRadPerDeg, Vec3::UnitX()) * to * 0.6f;
}
float error_deg(const Vec3& tip) {
  const Vec3 ray = tip - kEyes;
  const Vec3 to = kTarget - kEyes;
  return std::atan2(ray.cross(to).norm(), ray.dot(to)) / kRadPerDeg;
}
Vec3 settled(const Vec3& tip, float person_off_deg, float progression, float hand_weight,
             const PointingSettleConfig& config = {}) {
  const Mat3 R = pointing_settle_rotation(tip, kEyes, &kTarget, person_off_deg, progression,
                                          hand_weight, config);
  return kEyes + R * (tip - kEyes);
}

TEST(PointingSettle, WhileThePersonPointsAtTheirTargetTheAvatarPointsAtItsCopy) {
  const Vec3 tip = settled(tip_off_by(7.0f), 1.0f, 1.0f, 0.0f);
  EXPECT_NEAR(error_deg(tip_off_by(7.0f)), 7.0f, 1e-3f);
  EXPECT_NEAR(error_deg(tip), 0.0f, 1e-2f);
  EXPECT_NEAR((tip - kEyes).norm(), 0.6f, 1e-5f);
}

TEST(PointingSettle, FadesOutAsThePersonsFingerLeavesTheirTarget) {
  // Full within 5°, none beyond 15°: at 10°, smoothstep(0.5) = half of the 8° turn.
  EXPECT_NEAR(error_deg(settled(tip_off_by(8.0f), 5.0f, 1.0f, 0.0f)), 0.0f, 1e-2f);
  EXPECT_NEAR(error_deg(settled(tip_off_by(8.0f), 10.0f, 1.0f, 0.0f)), 4.0f, 1e-2f);
  EXPECT_TRUE(pointing_settle_rotation(tip_off_by(8.0f), kEyes, &kTarget, 15.0f, 1.0f, 0.0f)
                  .isIdentity(0.0f));
}

TEST(PointingSettle, FadesInWithTheDeicticProgression) {
  // None up to the onset 0.5, full at 1: at 0.75, smoothstep(0.5) = half.
  EXPECT_TRUE(pointing_settle_rotation(tip_off_by(8.0f), kEyes, &kTarget, 1.0f, 0.5f, 0.0f)
                  .isIdentity(0.0f));
  EXPECT_TRUE(pointing_settle_rotation(tip_off_by(8.0f), kEyes, &kTarget, 1.0f, 0.1f, 0.0f)
                  .isIdentity(0.0f));
  EXPECT_NEAR(error_deg(settled(tip_off_by(8.0f), 1.0f, 0.75f, 0.0f)), 4.0f, 1e-2f);
}

TEST(PointingSettle, TurnsAFarOffPointByTheBoundOnly) {
  // 30° off, bound 10°: 20° remain, turned toward the target (not away, not past it).
  EXPECT_NEAR(error_deg(settled(tip_off_by(30.0f), 0.0f, 1.0f, 0.0f)), 20.0f, 1e-2f);
  EXPECT_NEAR(error_deg(settled(tip_off_by(-30.0f), 0.0f, 1.0f, 0.0f)), 20.0f, 1e-2f);
  PointingSettleConfig wide;
  wide.max_deg = 45.0f;
  EXPECT_NEAR(error_deg(settled(tip_off_by(30.0f), 0.0f, 1.0f, 0.0f, wide)), 0.0f, 1e-2f);
}

TEST(PointingSettle, TheUsersOwnPoseIsLeftAlone) {
  // Hand blend weight 1: the avatar shows the user's own arm.
  EXPECT_TRUE(pointing_settle_rotation(tip_off_by(8.0f), kEyes, &kTarget, 1.0f, 1.0f, 1.0f)
                  .isIdentity(0.0f));
  EXPECT_NEAR(error_deg(settled(tip_off_by(8.0f), 1.0f, 1.0f, 0.5f)), 4.0f, 1e-2f);
}

TEST(PointingSettle, WithoutACopyOfTheTargetOrWithNonFiniteInputsNothingTurns) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const Vec3 tip = tip_off_by(8.0f);
  auto identity = [&](const Vec3& t, const Vec3& eyes, const Vec3* target, float off, float p,
                      float w) {
    return pointing_settle_rotation(t, eyes, target, off, p, w).isIdentity(0.0f);
  };
  EXPECT_TRUE(identity(tip, kEyes, nullptr, 1.0f, 1.0f, 0.0f));
  const Vec3 bad_target(nan, 0, 0);
  EXPECT_TRUE(identity(tip, kEyes, &bad_target, 1.0f, 1.0f, 0.0f));
  EXPECT_TRUE(identity(tip, Vec3(0, nan, 0), &kTarget, 1.0f, 1.0f, 0.0f));
  EXPECT_TRUE(identity(Vec3(nan, 0, 0), kEyes, &kTarget, 1.0f, 1.0f, 0.0f));
  EXPECT_TRUE(identity(tip, kEyes, &kTarget, nan, 1.0f, 0.0f));
  EXPECT_TRUE(identity(tip, kEyes, &kTarget, 1.0f, nan, 0.0f));
  EXPECT_TRUE(identity(tip, kEyes, &kTarget, 1.0f, 1.0f, nan));
  // The fingertip or the target at the eyes: no direction to settle from or onto.
  EXPECT_TRUE(identity(kEyes, kEyes, &kTarget, 1.0f, 1.0f, 0.0f));
  EXPECT_TRUE(identity(tip, kEyes, &kEyes, 1.0f, 1.0f, 0.0f));
}

}  // namespace
}  // namespace deixis::presence
