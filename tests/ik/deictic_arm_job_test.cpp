// DeicticArmJob: the fingertip within 1 mm of every reachable target, the arm along the ray when
// the target is out of reach, the elbow on the pole's side, and bad input handled.

#include "ik/deictic_arm_job.h"

#include <gtest/gtest.h>

#include "ik/two_bone_job.h"
#include "limit_check.h"
#include "rig_pose.h"

namespace deixis::ik {
namespace {

using testing::angle_between;
using testing::RigPose;

struct ArmSetup {
  ArmSetup(Hand hand, bool bone_aligned)
      : rig(testing::TestRigOptions{.bone_aligned = bone_aligned}),
        arm(rig.solver.arms[index(hand)]) {}
  RigPose rig;
  ArmRig arm;
  IkLimits limits;
  DeicticArmResult result;

  DeicticArmJob job(const Mat3& R_model_wrist, const Vec3& tip) {
    DeicticArmJob j;
    j.skeleton = &rig.skeleton();
    j.arm = &arm;
    j.limits = &limits;
    j.pole = arm.pole;
    j.wrist_rotation = R_model_wrist;
    j.fingertip = tip;
    j.local = rig.local;
    j.model = rig.model;
    j.result = &result;
    return j;
  }
  Vec3 shoulder() const { return rig.model[arm.upper].translation; }
  Vec3 tip() const { return transform_point(rig.model[arm.tip_joint()], arm.tip_offset); }
};

// A pose of the arm the solver can produce: the wrist somewhere it reaches, the elbow where the
// pole puts it, then a forearm twist, a wrist bend and a little hand twist within the limits.
// Returns the fingertip and the wrist's tracker-convention rotation it ends with.
std::pair<Vec3, Mat3> reachable_pose(ArmSetup& s, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  s.rig.reset();
  const Vec3 S = s.shoulder();
  const float a = (s.rig.model[s.arm.lower].translation - S).norm();
  const float b =
      (s.rig.model[s.arm.hand].translation - s.rig.model[s.arm.lower].translation).norm();
  const Reach reach = reach_of(a, b, s.limits.elbow);
  const float d = reach.min + 0.02f + (0.95f * reach.max - reach.min - 0.02f) * u(rng);
  Mat3 qs, qm;
  TwoBoneJob two_bone;
  two_bone.start_joint = &s.rig.model[s.arm.upper];
  two_bone.mid_joint = &s.rig.model[s.arm.lower];
  two_bone.end_joint = &s.rig.model[s.arm.hand];
  two_bone.target = S + d * testing::random_unit(rng);
  two_bone.pole_vector = s.arm.pole;
  two_bone.mid_axis = s.arm.mid_axis;
  two_bone.flexion = s.limits.elbow;
  two_bone.start_correction = &qs;
  two_bone.mid_correction = &qm;
  EXPECT_TRUE(two_bone.run());
  s.rig.local[s.arm.upper].rotation *= qs;
  s.rig.local[s.arm.lower].rotation *= qm;
  const HingeRange& twist = s.arm.forearm_twist;
  s.rig.local[s.arm.lower].rotation *=
      axis_angle(s.arm.forearm_axis, twist.min + (twist.max - twist.min) * (0.05f + 0.9f * u(rng)));
  const Vec3 hand_axis =
      s.rig.skeleton().rest_local[s.arm.hand].rotation.transpose() * s.arm.forearm_axis;
  s.rig.local[s.arm.hand].rotation =
      s.rig.skeleton().rest_local[s.arm.hand].rotation *
      axis_angle(frame_from(hand_axis, testing::random_unit(rng)).col(1), deg(60) * u(rng)) *
      axis_angle(hand_axis, deg(8) * (2 * u(rng) - 1));
  local_to_model(s.rig.skeleton(), s.rig.local, s.rig.model);
  const std::pair<Vec3, Mat3> pose{s.tip(), s.rig.model[s.arm.hand].rotation * s.arm.R_hand_wrist};
  s.rig.reset();
  return pose;
}

TEST(DeicticArmJob, ValidateRejectsEachBrokenRule) {
  ArmSetup s(Hand::kRight, false);
  const Vec3 t = s.tip();
  std::string_view why;
  ASSERT_TRUE(s.job(Mat3::Identity(), t).validate(&why)) << why;
  const auto expect_invalid = [&](const DeicticArmJob& job, std::string_view expected) {
    std::string_view reason;
    EXPECT_FALSE(job.validate(&reason));
    EXPECT_EQ(reason, expected);
    EXPECT_FALSE(job.run());
  };
  DeicticArmJob j = s.job(Mat3::Identity(), t);
  j.arm = nullptr;
  expect_invalid(j, "skeleton, arm and limits must be set");
  j = s.job(Mat3::Identity(), t);
  j.limits = nullptr;
  expect_invalid(j, "skeleton, arm and limits must be set");
  j = s.job(Mat3::Identity(), t);
  j.model = std::span<Pose>(s.rig.model.data(), 1);
  expect_invalid(j, "local and model must hold one pose per skeleton joint");
  ArmRig broken = s.arm;
  std::swap(broken.upper, broken.hand);
  j = s.job(Mat3::Identity(), t);
  j.arm = &broken;
  expect_invalid(j, "arm: upper, lower and hand must be joints, each below the previous");
  broken = s.arm;
  broken.index_count = 4;
  j.arm = &broken;
  expect_invalid(j, "arm: index_count must lie in 0..3");
  broken = s.arm;
  broken.index[1] = s.arm.index[2];
  j.arm = &broken;
  expect_invalid(j, "arm: index joints must hang below the hand, each the parent of the next");
  broken = s.arm;
  broken.index[0] = s.arm.lower;
  j.arm = &broken;
  expect_invalid(j, "arm: index joints must hang below the hand, each the parent of the next");
  j = s.job(Mat3::Identity(), t);
  j.soften = 0.0f;
  expect_invalid(j, "soften is not in (0, 1]");
  IkLimits bad;
  bad.wrist_swing = -1.0f;
  j = s.job(Mat3::Identity(), t);
  j.limits = &bad;
  expect_invalid(j, "limits are not usable (see check(IkLimits))");
}

TEST(DeicticArmJob, FingertipWithinOneMillimetreOfReachableTargets) {
  std::mt19937 rng(17);
  for (const Hand hand : {Hand::kRight, Hand::kLeft}) {
    for (const bool bone_aligned : {false, true}) {
      ArmSetup s(hand, bone_aligned);
      float worst = 0.0f;
      for (int i = 0; i < 500; ++i) {
        const auto [tip, wrist] = reachable_pose(s, rng);
        ASSERT_TRUE(s.job(wrist, tip).run());
        EXPECT_TRUE(s.result.reached);
        EXPECT_FALSE(s.result.beyond_reach);
        worst = std::max(worst, (s.tip() - tip).norm());
        ASSERT_EQ(testing::check_limits(s.rig.solver, s.rig.local, s.rig.model), "");
      }
      EXPECT_LT(worst, 1e-3f) << (hand == Hand::kRight ? "right" : "left") << " arm";
    }
  }
}

TEST(DeicticArmJob, BeyondReachTheArmPointsAlongTheRay) {
  std::mt19937 rng(23);
  for (const Hand hand : {Hand::kRight, Hand::kLeft}) {
    ArmSetup s(hand, true);
    for (int i = 0; i < 500; ++i) {
      s.rig.reset();
      const Vec3 dir = testing::random_unit(rng);
      const Vec3 target = s.shoulder() + (1.0f + 4.0f * std::abs(dir.x())) * dir;
      ASSERT_TRUE(s.job(testing::random_rotation(rng), target).run());
      EXPECT_TRUE(s.result.beyond_reach);
      EXPECT_FALSE(s.result.reached);
      const Vec3 S = s.shoulder();
      EXPECT_LT(angle_between(s.tip() - S, dir), deg(1)) << "fingertip off the ray";
      EXPECT_LT(angle_between(s.rig.model[s.arm.hand].translation - S, dir), deg(1))
          << "wrist off the ray";
      ASSERT_EQ(testing::check_limits(s.rig.solver, s.rig.local, s.rig.model), "");
    }
  }
}

TEST(DeicticArmJob, BeyondReachWithEyesTheFingertipStaysOnTheEyeRay) {
  // Pointing is the ray from the eyes through the fingertip: with sight_origin, a target beyond
  // reach brings the fingertip onto that ray (not the shoulder's), as far out as the arm goes.
  std::mt19937 rng(29);
  for (const Hand hand : {Hand::kRight, Hand::kLeft}) {
    ArmSetup s(hand, true);
    const int head = s.rig.solver.rig[Bone::kHead];
    for (int i = 0; i < 300; ++i) {
      s.rig.reset();
      const Vec3 eyes = transform_point(s.rig.model[head], s.rig.solver.rig.eye_midpoint_in_head);
      Vec3 dir = testing::random_unit(rng);
      dir.z() = -std::abs(dir.z()) - 0.3f;  // in front of the body, where people point
      dir.normalize();
      const Vec3 target = eyes + (1.5f + 3.0f * std::abs(dir.x())) * dir;
      DeicticArmJob job = s.job(testing::random_rotation(rng), target);
      job.sight_origin = eyes;
      ASSERT_TRUE(job.run());
      EXPECT_TRUE(s.result.beyond_reach);
      EXPECT_LT(angle_between(s.tip() - eyes, target - eyes), deg(0.5f)) << "off the eye ray";
      // As far out as it goes: the fingertip is beyond the shoulder's reach minus a few cm.
      const float a = (s.rig.model[s.arm.lower].translation - s.shoulder()).norm();
      EXPECT_GT((s.tip() - s.shoulder()).norm(), 0.9f * a);
      ASSERT_EQ(testing::check_limits(s.rig.solver, s.rig.local, s.rig.model), "");
    }
  }
}

TEST(DeicticArmJob, ElbowOnThePolesSide) {
  std::mt19937 rng(29);
  ArmSetup s(Hand::kRight, false);
  for (int i = 0; i < 300; ++i) {
    const auto [tip, wrist] = reachable_pose(s, rng);
    DeicticArmJob job = s.job(wrist, tip);
    job.pole = testing::random_unit(rng);
    ASSERT_TRUE(job.run());
    const Vec3 S = s.shoulder();
    const Vec3 u = (s.rig.model[s.arm.hand].translation - S).normalized();
    const Vec3 pole_perp = job.pole - job.pole.dot(u) * u;
    if (pole_perp.norm() < 0.1f) {
      continue;
    }
    const Vec3 elbow = s.rig.model[s.arm.lower].translation - S;
    const Vec3 offset = elbow - elbow.dot(u) * u;
    EXPECT_GT(offset.dot(pole_perp.normalized()), 0.99f * offset.norm());
  }
}

TEST(DeicticArmJob, BadTargetsAreHandled) {
  ArmSetup s(Hand::kRight, false);
  const std::vector<Pose> rest = s.rig.local;
  // No fingertip: the arm keeps its pose.
  ASSERT_TRUE(s.job(Mat3::Identity(), Vec3(NAN, 1, 1)).run());
  EXPECT_FALSE(s.result.reached);
  for (std::size_t i = 0; i < rest.size(); ++i) {
    EXPECT_TRUE(s.rig.local[i].rotation.isApprox(rest[i].rotation));
  }
  // No wrist orientation: the fingertip still lands, with the hand as it was.
  const Vec3 target = s.shoulder() + Vec3(0.2f, -0.1f, -0.45f);
  Mat3 nan_rotation = Mat3::Identity();
  nan_rotation(2, 2) = NAN;
  ASSERT_TRUE(s.job(nan_rotation, target).run());
  EXPECT_TRUE(s.result.reached);
  // Targets at the shoulder, the wrist, far away: finite and within limits.
  for (const Vec3& t : {s.shoulder(), Vec3(s.rig.model[s.arm.hand].translation),
                        Vec3(s.shoulder() + Vec3(0, 0, 1e7f))}) {
    s.rig.reset();
    ASSERT_TRUE(s.job(Mat3::Identity(), t).run());
    for (const Pose& p : s.rig.local) {
      ASSERT_TRUE(is_finite(p));
    }
    EXPECT_EQ(testing::check_limits(s.rig.solver, s.rig.local, s.rig.model), "");
  }
}

}  // namespace
}  // namespace deixis::ik
