// WristJob: the forearm takes the twist, the wrist the swing, each within its limits.

#include "ik/wrist_job.h"

#include <gtest/gtest.h>

#include "rig_pose.h"

namespace deixis::ik {
namespace {

using testing::RigPose;

struct WristSetup {
  explicit WristSetup(bool bone_aligned = false)
      : rig(testing::TestRigOptions{.bone_aligned = bone_aligned}),
        arm(rig.solver.arms[index(Hand::kRight)]) {}
  RigPose rig;
  ArmRig arm;
  bool reached = false;

  WristJob job(const Mat3& target) {
    WristJob j;
    j.skeleton = &rig.skeleton();
    j.forearm = arm.lower;
    j.hand = arm.hand;
    j.forearm_axis = arm.forearm_axis;
    j.twist = arm.forearm_twist;
    j.target = target;
    j.local = rig.local;
    j.model = rig.model;
    j.reached = &reached;
    return j;
  }
  // The hand's twist axis in its rest frame (the forearm's axis there).
  Vec3 hand_axis() const {
    return rig.skeleton().rest_local[arm.hand].rotation.transpose() * arm.forearm_axis;
  }
  float forearm_twist() const {
    const int j = arm.lower;
    return swing_twist(rest_deviation(rig.local[j].rotation, rig.skeleton().rest_local[j].rotation),
                       arm.forearm_axis)
        .twist;
  }
  SwingTwist hand_deviation() const {
    const int j = arm.hand;
    return swing_twist(rest_deviation(rig.local[j].rotation, rig.skeleton().rest_local[j].rotation),
                       hand_axis());
  }
};

TEST(WristJob, ValidateRejectsEachBrokenRule) {
  WristSetup s;
  std::string_view why;
  ASSERT_TRUE(s.job(Mat3::Identity()).validate(&why)) << why;
  const auto expect_invalid = [&](const WristJob& job, std::string_view expected) {
    std::string_view reason;
    EXPECT_FALSE(job.validate(&reason));
    EXPECT_EQ(reason, expected);
    EXPECT_FALSE(job.run());
  };
  WristJob j = s.job(Mat3::Identity());
  j.skeleton = nullptr;
  expect_invalid(j, "skeleton is not set");
  j = s.job(Mat3::Identity());
  j.model = {};
  expect_invalid(j, "local and model must hold one pose per skeleton joint");
  const std::string_view order = "forearm and hand must be joints, the hand below the forearm";
  j = s.job(Mat3::Identity());
  j.hand = j.forearm;
  expect_invalid(j, order);
  j = s.job(Mat3::Identity());
  std::swap(j.hand, j.forearm);
  expect_invalid(j, order);
  j.forearm = -1;
  expect_invalid(j, order);
  j = s.job(Mat3::Identity());
  j.forearm_axis = Vec3(1, 1, 0);
  expect_invalid(j, "forearm_axis is not a unit vector");
  j = s.job(Mat3::Identity());
  j.twist = {1.0f, -1.0f};
  expect_invalid(j, "twist range is not ordered within [−π, π]");
  j = s.job(Mat3::Identity());
  j.swing_max = -0.1f;
  expect_invalid(j, "swing_max and hand_twist_max must lie in [0, π]");
  j = s.job(Mat3::Identity());
  j.hand_twist_max = NAN;
  expect_invalid(j, "swing_max and hand_twist_max must lie in [0, π]");
}

TEST(WristJob, OrientationsWithinTheLimitsAreReachedExactly) {
  std::mt19937 rng(21);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (const bool bone_aligned : {false, true}) {
    WristSetup s(bone_aligned);
    const Vec3 wrist = s.rig.model[s.arm.hand].translation;
    for (int i = 0; i < 300; ++i) {
      s.rig.reset();
      // A hand pose the limits allow: forearm twist, wrist swing, a little own twist.
      const float twist =
          s.arm.forearm_twist.min +
          (s.arm.forearm_twist.max - s.arm.forearm_twist.min) * (0.02f + 0.96f * u(rng));
      const Vec3 swing_axis =
          frame_from(s.hand_axis(), testing::random_unit(rng)).col(1);  // ⊥ the twist axis
      const float own_twist = deg(9) * (2 * u(rng) - 1);
      const Mat3 hand_local = s.rig.skeleton().rest_local[s.arm.hand].rotation *
                              axis_angle(swing_axis, deg(65) * u(rng)) *
                              axis_angle(s.hand_axis(), own_twist);
      const Mat3 forearm =
          s.rig.model[s.arm.lower].rotation * axis_angle(s.arm.forearm_axis, twist);
      const Mat3 target = forearm * hand_local;
      ASSERT_TRUE(s.job(target).run());
      EXPECT_TRUE(s.reached);
      EXPECT_LT(rotation_angle(target * s.rig.model[s.arm.hand].rotation.transpose()), deg(0.05f));
      // All the twist goes to the forearm, as far as its range allows.
      EXPECT_NEAR(s.forearm_twist(),
                  std::clamp(twist + own_twist, s.arm.forearm_twist.min, s.arm.forearm_twist.max),
                  deg(0.05f));
      EXPECT_LT((s.rig.model[s.arm.hand].translation - wrist).norm(), 1e-5f) << "the wrist moved";
    }
  }
}

TEST(WristJob, OrientationsBeyondTheLimitsStopAtThem) {
  WristSetup s;
  // Supination by 170° (palm up and past) and a 100° bend.
  const Mat3 forearm = s.rig.model[s.arm.lower].rotation * axis_angle(s.arm.forearm_axis, deg(170));
  const Vec3 swing_axis = frame_from(s.hand_axis(), Vec3::UnitY()).col(1);
  const Mat3 target =
      forearm * s.rig.skeleton().rest_local[s.arm.hand].rotation * axis_angle(swing_axis, deg(100));
  ASSERT_TRUE(s.job(target).run());
  EXPECT_FALSE(s.reached);
  EXPECT_NEAR(s.forearm_twist(), s.arm.forearm_twist.max, deg(0.01f));
  const SwingTwist hand = s.hand_deviation();
  EXPECT_NEAR(rotation_angle(hand.swing), deg(70), deg(0.01f));
  EXPECT_LE(std::abs(hand.twist), deg(10) + 1e-4f);
}

TEST(WristJob, NonFiniteTargetLeavesThePose) {
  WristSetup s;
  const std::vector<Pose> rest = s.rig.local;
  Mat3 bad = Mat3::Identity();
  bad(0, 0) = INFINITY;
  ASSERT_TRUE(s.job(bad).run());
  EXPECT_FALSE(s.reached);
  EXPECT_TRUE(s.rig.local[s.arm.hand].rotation.isApprox(rest[s.arm.hand].rotation));
  EXPECT_TRUE(s.rig.local[s.arm.lower].rotation.isApprox(rest[s.arm.lower].rotation));
}

}  // namespace
}  // namespace deixis::ik
