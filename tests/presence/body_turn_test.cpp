// The body turn's two rules (presence/body_turn.h): how far the body wants to turn for a target,
// and how fast it gets there.
#include "presence/body_turn.h"

#include <gtest/gtest.h>

#include <cmath>

namespace deixis::presence {
namespace {

constexpr float kDeg = 3.14159265f / 180.0f;

// A spot at (1, 1.6, 2) facing −Z turned 30° to the left; a target `azimuth_deg` from that
// facing (+ left), 2 m away.
struct Spot {
  Pose T_world_spot{yaw_rotation(30 * kDeg), Vec3(1, 1.6f, 2)};
  Vec3 at(float azimuth_deg) const {
    const Vec3 local(-2 * std::sin(azimuth_deg * kDeg), 0.3f, -2 * std::cos(azimuth_deg * kDeg));
    return transform_point(T_world_spot, local);
  }
};

TEST(BodyTurn, TargetsInFrontTurnNothingAndOnesBehindComeToTheComfortAngle) {
  const Spot s;
  for (float az : {0.0f, 20.0f, -44.9f, 44.9f}) {
    const Vec3 t = s.at(az);
    EXPECT_EQ(wanted_turn(s.T_world_spot, &t, 1.0f, true), 0.0f) << az;
  }
  for (float az : {60.0f, 100.0f, 150.0f, -60.0f, -120.0f}) {
    const Vec3 t = s.at(az);
    const float turn = wanted_turn(s.T_world_spot, &t, 1.0f, true);
    // After turning, the target stands at the comfort angle on the same side.
    EXPECT_NEAR((az * kDeg - turn) / kDeg, az > 0 ? 45.0f : -45.0f, 0.01f) << az;
  }
  const Vec3 behind = s.at(179.0f);  // capped at the furthest turn
  EXPECT_NEAR(wanted_turn(s.T_world_spot, &behind, 1.0f, true) / kDeg, 134.0f, 0.01f);
}

TEST(BodyTurn, AGazeTurnsTheBodyOnlyPastWhereTheHeadReaches) {
  const Spot s;
  const Vec3 aside = s.at(61.0f);
  EXPECT_EQ(wanted_turn(s.T_world_spot, &aside, 1.0f, false), 0.0f);
  EXPECT_GT(wanted_turn(s.T_world_spot, &aside, 1.0f, true), 0.0f);
  const Vec3 behind = s.at(-120.0f);
  EXPECT_NEAR(wanted_turn(s.T_world_spot, &behind, 1.0f, false) / kDeg, -40.0f, 0.01f);
}

TEST(BodyTurn, TheTurnFollowsTheDesignationAndNothingTurnsNothing) {
  const Spot s;
  const Vec3 t = s.at(105.0f);
  EXPECT_NEAR(wanted_turn(s.T_world_spot, &t, 0.5f, true) / kDeg, 30.0f, 0.01f);
  EXPECT_EQ(wanted_turn(s.T_world_spot, &t, 0.0f, true), 0.0f);
  EXPECT_EQ(wanted_turn(s.T_world_spot, nullptr, 1.0f, true), 0.0f);
  EXPECT_EQ(wanted_turn(s.T_world_spot, &t, std::nanf(""), true), 0.0f);
  const Vec3 above = s.T_world_spot.translation + Vec3(0, 1, 0);  // no direction to turn to
  EXPECT_EQ(wanted_turn(s.T_world_spot, &above, 1.0f, true), 0.0f);
}

TEST(BodyTurn, TurnsAtBoundedSpeed) {
  const BodyTurnConfig config;
  const float dt = 1.0f / 30.0f;
  const float step = config.speed_deg_per_s * kDeg * dt;
  EXPECT_NEAR(turned(0.0f, 1.0f, dt), step, 1e-6f);
  EXPECT_NEAR(turned(0.0f, -1.0f, dt), -step, 1e-6f);
  EXPECT_EQ(turned(0.5f, 0.5f + step / 2, dt), 0.5f + step / 2);  // arrives, no overshoot
  float yaw = 0.0f;
  int ticks = 0;
  while (yaw < 90 * kDeg - 1e-4f && ticks < 100) {
    yaw = turned(yaw, 90 * kDeg, dt);
    ++ticks;
  }
  EXPECT_EQ(ticks, 18);  // 90° at 150°/s: 0.6 s
}

}  // namespace
}  // namespace deixis::presence
