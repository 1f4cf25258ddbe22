// IndexFingerJob: the fingertip reaches targets on the finger's curl, nothing moves when it is
// already there, and the joints stay hinges within their ranges.

#include "ik/index_finger_job.h"

#include <gtest/gtest.h>

#include "rig_pose.h"

namespace deixis::ik {
namespace {

using testing::RigPose;

struct FingerSetup {
  explicit FingerSetup(bool bone_aligned = false)
      : rig(testing::TestRigOptions{.bone_aligned = bone_aligned}),
        arm(rig.solver.arms[index(Hand::kLeft)]) {}
  RigPose rig;
  ArmRig arm;
  IkLimits limits;
  bool reached = false;
  Vec3 tip = Vec3::Zero();

  IndexFingerJob job(const Vec3& target) {
    IndexFingerJob j;
    j.skeleton = &rig.skeleton();
    j.chain = std::span<const int>(arm.index.data(), 3);
    j.flexion_axes = std::span<const Vec3>(arm.index_axes.data(), 3);
    j.flexion = limits.index;
    j.tip_offset = arm.tip_offset;
    j.target = target;
    j.local = rig.local;
    j.model = rig.model;
    j.reached = &reached;
    j.tip = &tip;
    return j;
  }
  Vec3 tip_now() const { return transform_point(rig.model[arm.index[2]], arm.tip_offset); }
  float flexion(int k) const {
    const int j = arm.index[k];
    return swing_twist(rest_deviation(rig.local[j].rotation, rig.skeleton().rest_local[j].rotation),
                       arm.index_axes[k])
        .twist;
  }
};

TEST(IndexFingerJob, ValidateRejectsEachBrokenRule) {
  FingerSetup s;
  std::string_view why;
  ASSERT_TRUE(s.job(s.tip_now()).validate(&why)) << why;
  const auto expect_invalid = [&](const IndexFingerJob& job, std::string_view expected) {
    std::string_view reason;
    EXPECT_FALSE(job.validate(&reason));
    EXPECT_EQ(reason, expected);
    EXPECT_FALSE(job.run());
  };
  const Vec3 t = s.tip_now();
  IndexFingerJob j = s.job(t);
  j.skeleton = nullptr;
  expect_invalid(j, "skeleton is not set");
  j = s.job(t);
  j.local = {};
  expect_invalid(j, "local and model must hold one pose per skeleton joint");
  j = s.job(t);
  j.chain = {};
  expect_invalid(j, "chain must hold 1 to 3 joints");
  const std::array<int, 4> four = {s.arm.index[0], s.arm.index[1], s.arm.index[2], s.arm.index[2]};
  j.chain = four;
  expect_invalid(j, "chain must hold 1 to 3 joints");
  j = s.job(t);
  j.flexion_axes = std::span<const Vec3>(s.arm.index_axes.data(), 2);
  expect_invalid(j, "flexion_axes and flexion must hold one entry per chain joint");
  j = s.job(t);
  j.flexion = std::span<const HingeRange>(s.limits.index.data(), 1);
  expect_invalid(j, "flexion_axes and flexion must hold one entry per chain joint");
  std::array<int, 3> chain = {s.arm.index[0], 5000, s.arm.index[2]};
  j = s.job(t);
  j.chain = chain;
  expect_invalid(j, "chain joint is not a joint of the skeleton");
  chain = {s.arm.index[0], s.arm.index[2], s.arm.index[1]};
  j.chain = chain;
  expect_invalid(j, "each chain joint must be the parent of the next");
  std::array<Vec3, 3> axes = s.arm.index_axes;
  axes[1] = Vec3::Zero();
  j = s.job(t);
  j.flexion_axes = axes;
  expect_invalid(j, "flexion_axes must be unit vectors");
  std::array<HingeRange, 3> ranges = s.limits.index;
  ranges[2] = {1.0f, 0.5f};
  j = s.job(t);
  j.flexion = ranges;
  expect_invalid(j, "flexion ranges must be ordered within [−π, π]");
  j = s.job(t);
  j.tip_offset = Vec3(NAN, 0, 0);
  expect_invalid(j, "tip_offset is not finite");
}

TEST(IndexFingerJob, TipReachesTargetsTheFingerCanTouch) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (const bool bone_aligned : {false, true}) {
    FingerSetup s(bone_aligned);
    for (int i = 0; i < 300; ++i) {
      s.rig.reset();
      // A finger pose as people hold it: the last two joints curled by the same fraction of
      // their ranges, the first joint anywhere in its range.
      const float curl = u(rng);
      const HingeRange& first = s.limits.index[0];
      for (int k = 0; k < 3; ++k) {
        const int j = s.arm.index[k];
        const float angle =
            k == 0 ? first.min + (first.max - first.min) * u(rng) : curl * s.limits.index[k].max;
        s.rig.local[j].rotation = s.rig.local[j].rotation * axis_angle(s.arm.index_axes[k], angle);
      }
      local_to_model(s.rig.skeleton(), s.rig.local, s.rig.model);
      const Vec3 target = s.tip_now();
      s.rig.reset();
      ASSERT_TRUE(s.job(target).run());
      EXPECT_TRUE(s.reached);
      EXPECT_LT((s.tip - target).norm(), 1e-4f);
      for (int k = 0; k < 3; ++k) {
        EXPECT_GE(s.flexion(k), s.limits.index[k].min - 1e-4f);
        EXPECT_LE(s.flexion(k), s.limits.index[k].max + 1e-4f);
      }
    }
  }
}

TEST(IndexFingerJob, NothingMovesWhenTheTipIsThere) {
  FingerSetup s;
  const std::vector<Pose> rest = s.rig.local;
  ASSERT_TRUE(s.job(s.tip_now()).run());
  EXPECT_TRUE(s.reached);
  for (const int j : s.arm.index) {
    EXPECT_TRUE(s.rig.local[j].rotation.isApprox(rest[j].rotation));
  }
}

TEST(IndexFingerJob, UnreachableTargetsKeepTheFingerInRange) {
  FingerSetup s;
  const Vec3 hand = s.rig.model[s.arm.hand].translation;
  for (const Vec3& target : {Vec3(hand + Vec3(0, 0.3f, 0)), Vec3(hand + Vec3(0.5f, 0, 0)),
                             Vec3(hand), Vec3(NAN, 0, 0)}) {
    s.rig.reset();
    ASSERT_TRUE(s.job(target).run());
    EXPECT_FALSE(s.reached);
    EXPECT_TRUE(s.tip.allFinite());
    for (int k = 0; k < 3; ++k) {
      EXPECT_GE(s.flexion(k), s.limits.index[k].min - 1e-4f);
      EXPECT_LE(s.flexion(k), s.limits.index[k].max + 1e-4f);
    }
  }
}

}  // namespace
}  // namespace deixis::ik
