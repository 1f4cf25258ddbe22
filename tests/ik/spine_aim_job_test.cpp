// SpineAimJob: the head ends at its target orientation, the joints below it take their shares,
// limits hold, and bad targets leave the pose alone.

#include "ik/spine_aim_job.h"

#include <gtest/gtest.h>

#include "rig_pose.h"

namespace deixis::ik {
namespace {

using testing::RigPose;

struct AimSetup {
  RigPose rig;
  std::array<int, 4> chain;
  std::array<float, 4> weights = {0.15f, 0.2f, 0.4f, 1.0f};
  std::array<float, 4> limits = {deg(20), deg(25), deg(40), deg(45)};
  bool reached = false;

  AimSetup() : chain{rig[Bone::kSpine], rig[Bone::kChest], rig[Bone::kNeck], rig[Bone::kHead]} {}

  SpineAimJob job(const Mat3& target) {
    SpineAimJob j;
    j.skeleton = &rig.skeleton();
    j.chain = chain;
    j.weights = weights;
    j.max_angles = limits;
    j.target = target;
    j.local = rig.local;
    j.model = rig.model;
    j.reached = &reached;
    return j;
  }
  float deviation(Bone b) const {
    const int j = rig[b];
    return rotation_angle(rig.skeleton().rest_local[j].rotation.transpose() *
                          rig.local[j].rotation);
  }
  Mat3 head_rest() const { return rig.solver.rest_model[rig[Bone::kHead]].rotation; }
};

TEST(SpineAimJob, ValidateRejectsEachBrokenRule) {
  AimSetup s;
  std::string_view why;
  ASSERT_TRUE(s.job(Mat3::Identity()).validate(&why)) << why;
  const auto expect_invalid = [&](const SpineAimJob& job, std::string_view expected) {
    std::string_view reason;
    EXPECT_FALSE(job.validate(&reason));
    EXPECT_EQ(reason, expected);
    EXPECT_FALSE(job.run());
  };
  SpineAimJob j = s.job(Mat3::Identity());
  j.skeleton = nullptr;
  expect_invalid(j, "skeleton is not set");
  j = s.job(Mat3::Identity());
  j.local = std::span<Pose>(s.rig.local.data(), 3);
  expect_invalid(j, "local and model must hold one pose per skeleton joint");
  j = s.job(Mat3::Identity());
  j.chain = {};
  expect_invalid(j, "chain must hold 1 to kMaxChain joints");
  const std::array<int, 9> long_chain{};
  const std::array<float, 9> long_weights{};
  j.chain = long_chain;
  j.weights = long_weights;
  j.max_angles = long_weights;
  expect_invalid(j, "chain must hold 1 to kMaxChain joints");
  j = s.job(Mat3::Identity());
  j.weights = std::span<const float>(s.weights.data(), 3);
  expect_invalid(j, "weights and max_angles must hold one value per chain joint");
  j = s.job(Mat3::Identity());
  j.max_angles = std::span<const float>(s.limits.data(), 2);
  expect_invalid(j, "weights and max_angles must hold one value per chain joint");
  std::array<int, 4> bad = s.chain;
  bad[1] = 999;
  j = s.job(Mat3::Identity());
  j.chain = bad;
  expect_invalid(j, "chain joint is not a joint of the skeleton");
  bad = {s.chain[0], s.chain[2], s.chain[1], s.chain[3]};  // chest after neck
  j.chain = bad;
  expect_invalid(j, "chain joints must be ancestors of the joints after them");
  bad = {s.chain[0], s.chain[0], s.chain[2], s.chain[3]};
  j.chain = bad;
  expect_invalid(j, "chain joints must be ancestors of the joints after them");
  std::array<float, 4> w = s.weights;
  w[0] = -0.1f;
  j = s.job(Mat3::Identity());
  j.weights = w;
  expect_invalid(j, "weights must lie in [0, 1]");
  w[0] = NAN;
  expect_invalid(j, "weights must lie in [0, 1]");
  std::array<float, 4> m = s.limits;
  m[2] = 4.0f;
  j = s.job(Mat3::Identity());
  j.max_angles = m;
  expect_invalid(j, "max_angles must lie in [0, π]");
  w = s.weights;
  w[3] = 0.9f;
  j = s.job(Mat3::Identity());
  j.weights = w;
  expect_invalid(j, "the last chain joint's weight must be 1");
}

TEST(SpineAimJob, HeadReachesItsOrientationWithinLimits) {
  std::mt19937 rng(3);
  AimSetup s;
  for (int i = 0; i < 500; ++i) {
    s.rig.reset();
    const Mat3 target = testing::random_rotation(rng, deg(110)) * s.head_rest();
    ASSERT_TRUE(s.job(target).run());
    EXPECT_TRUE(s.reached);
    EXPECT_LT(rotation_angle(target * s.rig.model[s.rig[Bone::kHead]].rotation.transpose()),
              deg(0.01f));
    const std::array<Bone, 4> bones = {Bone::kSpine, Bone::kChest, Bone::kNeck, Bone::kHead};
    for (int k = 0; k < 4; ++k) {
      EXPECT_LE(s.deviation(bones[k]), s.limits[k] + 1e-4f) << bone_name(bones[k]);
    }
  }
}

TEST(SpineAimJob, JointsTakeTheirSharesOfTheRemainingTurn) {
  AimSetup s;
  ASSERT_TRUE(s.job(axis_angle(Vec3::UnitY(), deg(60)) * s.head_rest()).run());
  EXPECT_NEAR(s.deviation(Bone::kSpine), deg(60 * 0.15f), deg(0.05f));
  EXPECT_NEAR(s.deviation(Bone::kChest), deg(60 * 0.85f * 0.2f), deg(0.05f));
  EXPECT_NEAR(s.deviation(Bone::kNeck), deg(60 * 0.85f * 0.8f * 0.4f), deg(0.05f));
  EXPECT_NEAR(s.deviation(Bone::kHead), deg(60 * 0.85f * 0.8f * 0.6f), deg(0.05f));
}

TEST(SpineAimJob, AnOrientationBeyondTheLimitsStopsAtThem) {
  AimSetup s;
  const Mat3 target = axis_angle(Vec3::UnitY(), deg(175)) * s.head_rest();
  ASSERT_TRUE(s.job(target).run());
  EXPECT_FALSE(s.reached);
  EXPECT_NEAR(s.deviation(Bone::kHead), deg(45), 1e-4f);
  EXPECT_LE(s.deviation(Bone::kNeck), deg(40) + 1e-4f);
  // Everything the limits allow went into the turn.
  EXPECT_NEAR(rotation_angle(target * s.rig.model[s.rig[Bone::kHead]].rotation.transpose()),
              deg(175 - 20 - 25 - 40 - 45), deg(0.1f));
}

TEST(SpineAimJob, BadTargetsLeaveThePoseOrAreMadeRotations) {
  AimSetup s;
  const std::vector<Pose> rest = s.rig.local;
  Mat3 nan = Mat3::Identity();
  nan(1, 2) = NAN;
  ASSERT_TRUE(s.job(nan).run());
  EXPECT_FALSE(s.reached);
  for (std::size_t i = 0; i < rest.size(); ++i) {
    EXPECT_TRUE(s.rig.local[i].rotation.isApprox(rest[i].rotation));
  }
  // A scaled rotation is projected onto the rotation.
  const Mat3 turn = axis_angle(Vec3(1, 1, 0).normalized(), deg(30)) * s.head_rest();
  ASSERT_TRUE(s.job(2.0f * turn).run());
  EXPECT_TRUE(s.reached);
  EXPECT_LT(rotation_angle(turn * s.rig.model[s.rig[Bone::kHead]].rotation.transpose()),
            deg(0.01f));
}

}  // namespace
}  // namespace deixis::ik
