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

// The designation the body turns for. A person pointing at a cup looks at it too; as the hold
// ends the deictic progression falls a tick before the gaze's (0.99 against 1.00, live rooms
// seed 60613, pair 15), which must not hand the turn to the eyes' wider comfort for that tick.
TEST(BodyTurn, TheHandRulesWhenItAndTheEyesDesignateTheSameTarget) {
  const Vec3 cup(2, 1, -1);
  const Vec3 person(-2, 1.6f, -1);
  const TurnDesignation same = turn_designation(&cup, 7, 0.99f, &cup, 7, 1.0f);
  EXPECT_TRUE(same.pointing);
  EXPECT_EQ(same.target, &cup);
  EXPECT_FLOAT_EQ(same.weight, 1.0f);
  // Looking at someone else while the hand is still low: the eyes rule.
  const TurnDesignation other = turn_designation(&cup, 7, 0.2f, &person, 0, 0.9f);
  EXPECT_FALSE(other.pointing);
  EXPECT_EQ(other.target, &person);
  EXPECT_FLOAT_EQ(other.weight, 1.0f);
  // A hand ahead of the eyes rules whatever they look at; its weight is twice its progression.
  const TurnDesignation ahead = turn_designation(&cup, 7, 0.3f, &person, 0, 0.1f);
  EXPECT_TRUE(ahead.pointing);
  EXPECT_FLOAT_EQ(ahead.weight, 0.6f);
  // A hand target this room lacks leaves the eyes; nothing designated turns nothing.
  EXPECT_EQ(turn_designation(nullptr, 7, 1.0f, &person, 0, 0.5f).target, &person);
  EXPECT_EQ(turn_designation(nullptr, kNoTarget, 0.0f, nullptr, kNoTarget, 0.0f).target, nullptr);
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
