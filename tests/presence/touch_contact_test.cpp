// Touch contact, hand-computed: a fingertip 4 cm off a sphere's surface is moved exactly onto it
// at a completed touch, half way at three quarters of the radius, and not at all during free-form
// movement, far from the object, for the partner, or while the user's own pose is shown.

#include "presence/touch_contact.h"

#include <gtest/gtest.h>

#include <limits>

namespace deixis::presence {
namespace {

// A sphere of radius 0.05 m at (0, 1, −0.5); the fingertip `gap` in front of its surface (+Z).
TargetObject ball() {
  return {3, "ball", TargetKind::kSphere, Vec3(0, 1, -0.5f), Vec3::Constant(0.1f)};
}
Vec3 tip_at(float gap) {
  return Vec3(0, 1, -0.5f + 0.05f + gap);
}

constexpr float kRadius = 0.12f;

TEST(TouchContact, ACompletedTouchEndsOnTheSurface) {
  const TargetObject object = ball();
  const Vec3 tip = tip_at(0.04f);
  const Vec3 offset = touch_contact_offset(tip, &object, 1.0f, 0.0f, kRadius);
  EXPECT_TRUE((tip + offset).isApprox(Vec3(0, 1, -0.45f), 1e-6f)) << (tip + offset).transpose();
}

TEST(TouchContact, FadesOutWithDistance) {
  const TargetObject object = ball();
  // At 0.75 R: smoothstep(0.5) = 0.5 of the way.
  const Vec3 offset = touch_contact_offset(tip_at(0.09f), &object, 1.0f, 0.0f, kRadius);
  EXPECT_NEAR(offset.z(), -0.045f, 1e-6f);
  EXPECT_EQ(touch_contact_offset(tip_at(0.12f), &object, 1.0f, 0.0f, kRadius), Vec3::Zero());
  EXPECT_EQ(touch_contact_offset(tip_at(0.5f), &object, 1.0f, 0.0f, kRadius), Vec3::Zero());
}

TEST(TouchContact, FadesInWithTheDeicticProgression) {
  const TargetObject object = ball();
  EXPECT_EQ(touch_contact_offset(tip_at(0.04f), &object, 0.3f, 0.0f, kRadius), Vec3::Zero());
  EXPECT_EQ(touch_contact_offset(tip_at(0.04f), &object, 0.5f, 0.0f, kRadius), Vec3::Zero());
  // Progression 0.75: smoothstep(0.5) = 0.5.
  EXPECT_NEAR(touch_contact_offset(tip_at(0.04f), &object, 0.75f, 0.0f, kRadius).z(), -0.02f,
              1e-6f);
}

TEST(TouchContact, NothingForThePartnerTheUsersOwnPoseOrBadInput) {
  TargetObject partner = ball();
  partner.id = kPartnerTarget;
  const TargetObject object = ball();
  EXPECT_EQ(touch_contact_offset(tip_at(0.04f), &partner, 1.0f, 0.0f, kRadius), Vec3::Zero());
  EXPECT_EQ(touch_contact_offset(tip_at(0.04f), nullptr, 1.0f, 0.0f, kRadius), Vec3::Zero());
  EXPECT_EQ(touch_contact_offset(tip_at(0.04f), &object, 1.0f, 1.0f, kRadius), Vec3::Zero());
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(touch_contact_offset(Vec3(nan, 0, 0), &object, 1.0f, 0.0f, kRadius), Vec3::Zero());
  EXPECT_TRUE(touch_contact_offset(tip_at(0.04f), &object, nan, 0.0f, kRadius).allFinite());
}

}  // namespace
}  // namespace deixis::presence
