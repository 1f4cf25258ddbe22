// Gaze settling, hand-computed: the avatar's eyes 1.6 m up, the target 2 m ahead (−Z), the
// networks' gaze some degrees to its side. While the person's own eyes are on their target the
// avatar's end on this room's copy; as the person's gaze leaves theirs, the avatar's settles part
// of the way, then not at all; far off it turns by the bound only; the user's own pose, no copy
// of the target here and non-finite inputs leave it as it is.

#include "presence/gaze_settle.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace deixis::presence {
namespace {

constexpr float kRadPerDeg = 0.0174532925f;

const Vec3 kEyes(0, 1.6f, 0);
const Vec3 kTarget(0, 1.6f, -2.0f);

// A unit gaze `deg` degrees to the right of straight at the target (a yaw about +Y).
Vec3 off_by(float deg) {
  return Vec3(std::sin(deg * kRadPerDeg), 0, -std::cos(deg * kRadPerDeg));
}
float error_deg(const Vec3& gaze) {
  const Vec3 to = (kTarget - kEyes).normalized();
  return std::atan2(gaze.cross(to).norm(), gaze.dot(to)) / kRadPerDeg;
}

TEST(GazeSettle, WhileThePersonLooksAtTheirTargetTheAvatarLooksAtItsCopy) {
  const Vec3 g = settled_gaze(off_by(8.0f), kEyes, &kTarget, 1.0f, 0.0f);
  EXPECT_NEAR(error_deg(g), 0.0f, 1e-3f);
  EXPECT_NEAR(g.norm(), 1.0f, 1e-6f);
}

TEST(GazeSettle, FadesOutAsThePersonsGazeLeavesTheirTarget) {
  // Full within 5°, none beyond 15°: at 10°, smoothstep(0.5) = half of the 8° turn.
  EXPECT_NEAR(error_deg(settled_gaze(off_by(8.0f), kEyes, &kTarget, 5.0f, 0.0f)), 0.0f, 1e-3f);
  EXPECT_NEAR(error_deg(settled_gaze(off_by(8.0f), kEyes, &kTarget, 10.0f, 0.0f)), 4.0f, 1e-3f);
  EXPECT_EQ(settled_gaze(off_by(8.0f), kEyes, &kTarget, 15.0f, 0.0f), off_by(8.0f));
  EXPECT_EQ(settled_gaze(off_by(8.0f), kEyes, &kTarget, 90.0f, 0.0f), off_by(8.0f));
}

TEST(GazeSettle, TurnsAFarOffGazeByTheBoundOnly) {
  // 40° off, bound 15°: 25° remain, turned toward the target (not away, not past it).
  EXPECT_NEAR(error_deg(settled_gaze(off_by(40.0f), kEyes, &kTarget, 0.0f, 0.0f)), 25.0f, 1e-3f);
  EXPECT_NEAR(error_deg(settled_gaze(off_by(-40.0f), kEyes, &kTarget, 0.0f, 0.0f)), 25.0f, 1e-3f);
  GazeSettleConfig wide;
  wide.max_deg = 45.0f;
  EXPECT_NEAR(error_deg(settled_gaze(off_by(40.0f), kEyes, &kTarget, 0.0f, 0.0f, wide)), 0.0f,
              1e-3f);
}

TEST(GazeSettle, TheUsersOwnPoseIsLeftAlone) {
  // Head blend weight 1: the avatar shows the user's own head and eyes.
  EXPECT_EQ(settled_gaze(off_by(8.0f), kEyes, &kTarget, 1.0f, 1.0f), off_by(8.0f));
  EXPECT_NEAR(error_deg(settled_gaze(off_by(8.0f), kEyes, &kTarget, 1.0f, 0.5f)), 4.0f, 1e-3f);
}

TEST(GazeSettle, WithoutACopyOfTheTargetOrWithNonFiniteInputsTheGazeStays) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const Vec3 g = off_by(8.0f);
  EXPECT_EQ(settled_gaze(g, kEyes, nullptr, 1.0f, 0.0f), g);
  const Vec3 bad_target(nan, 0, 0);
  EXPECT_EQ(settled_gaze(g, kEyes, &bad_target, 1.0f, 0.0f), g);
  EXPECT_EQ(settled_gaze(g, Vec3(0, nan, 0), &kTarget, 1.0f, 0.0f), g);
  EXPECT_EQ(settled_gaze(g, kEyes, &kTarget, nan, 0.0f), g);
  EXPECT_EQ(settled_gaze(g, kEyes, &kTarget, 1.0f, nan), g);
  EXPECT_EQ(settled_gaze(Vec3::Zero(), kEyes, &kTarget, 1.0f, 0.0f), Vec3::Zero());
  // The target at the eyes: no direction to settle onto.
  EXPECT_EQ(settled_gaze(g, kEyes, &kEyes, 1.0f, 0.0f), g);
}

}  // namespace
}  // namespace deixis::presence
