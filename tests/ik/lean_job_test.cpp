// LeanJob: the eye midpoint H moves toward its target by bending spine and chest within limits.

#include "ik/lean_job.h"

#include <gtest/gtest.h>

#include "rig_pose.h"

namespace deixis::ik {
namespace {

using testing::RigPose;

struct LeanSetup {
  RigPose rig;
  std::array<int, 2> chain;
  std::array<float, 2> weights = {0.5f, 1.0f};
  std::array<float, 2> limits = {deg(20), deg(25)};
  bool reached = false;
  float error = 0.0f;

  LeanSetup() : chain{rig[Bone::kSpine], rig[Bone::kChest]} {}

  LeanJob job(const Vec3& target) {
    LeanJob j;
    j.skeleton = &rig.skeleton();
    j.chain = chain;
    j.weights = weights;
    j.max_angles = limits;
    j.end_joint = rig[Bone::kHead];
    j.end_offset = rig.solver.rig.eye_midpoint_in_head;
    j.target = target;
    j.local = rig.local;
    j.model = rig.model;
    j.reached = &reached;
    j.error = &error;
    return j;
  }
  Vec3 eye_midpoint() const {
    return transform_point(rig.model[rig[Bone::kHead]], rig.solver.rig.eye_midpoint_in_head);
  }
  float deviation(Bone b) const {
    const int j = rig[b];
    return rotation_angle(rig.skeleton().rest_local[j].rotation.transpose() *
                          rig.local[j].rotation);
  }
};

TEST(LeanJob, ValidateRejectsEachBrokenRule) {
  LeanSetup s;
  const Vec3 target = s.eye_midpoint();
  std::string_view why;
  ASSERT_TRUE(s.job(target).validate(&why)) << why;
  const auto expect_invalid = [&](const LeanJob& job, std::string_view expected) {
    std::string_view reason;
    EXPECT_FALSE(job.validate(&reason));
    EXPECT_EQ(reason, expected);
    EXPECT_FALSE(job.run());
  };
  // The chain rules are shared with SpineAimJob (job_validation.cpp); one of them here.
  LeanJob j = s.job(target);
  j.skeleton = nullptr;
  expect_invalid(j, "skeleton is not set");
  std::array<float, 2> w = {0.5f, 0.5f};
  j = s.job(target);
  j.weights = w;
  expect_invalid(j, "the last pivot's weight must be 1");
  j = s.job(target);
  j.end_joint = -1;
  expect_invalid(j, "end_joint must be a joint at or below the last pivot");
  j.end_joint = s.rig[Bone::kRightHand] + 1000;
  expect_invalid(j, "end_joint must be a joint at or below the last pivot");
  j.end_joint = s.rig[Bone::kHips];  // above the pivots
  expect_invalid(j, "end_joint must be a joint at or below the last pivot");
  j = s.job(target);
  j.end_offset = Vec3(0, INFINITY, 0);
  expect_invalid(j, "end_offset is not finite");
  j = s.job(target);
  j.iterations = 0;
  expect_invalid(j, "iterations must lie in 1..16");
  j.iterations = 17;
  expect_invalid(j, "iterations must lie in 1..16");
}

TEST(LeanJob, EyeMidpointReachesReachableLeans) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  LeanSetup s;
  const Vec3 rest = s.eye_midpoint();
  const Vec3 spine = s.rig.model[s.rig[Bone::kSpine]].translation;
  int reached = 0;
  constexpr int kCases = 300;
  for (int i = 0; i < kCases; ++i) {
    s.rig.reset();
    // A point on the sphere around the spine joint, within 15° of upright: bending the spine
    // and chest gets there (the spine alone could).
    const Mat3 tilt =
        axis_angle(Vec3(u(rng), 0, u(rng)).normalized(), deg(15) * 0.5f * (u(rng) + 1));
    const Vec3 target = spine + tilt * (rest - spine);
    ASSERT_TRUE(s.job(target).run());
    reached += s.reached;
    // Pivots nearly in line with H move it toward or away from them only slowly, so the last
    // millimetres can take more steps than the job allows.
    EXPECT_LT((s.eye_midpoint() - target).norm(), 3e-3f);
    EXPECT_NEAR(s.error, (s.eye_midpoint() - target).norm(), 1e-6f);
    EXPECT_LE(s.deviation(Bone::kSpine), deg(20) + 1e-4f);
    EXPECT_LE(s.deviation(Bone::kChest), deg(25) + 1e-4f);
  }
  EXPECT_GE(reached, kCases * 95 / 100);  // within 1 mm
}

TEST(LeanJob, FarTargetsAreApproachedWithinLimits) {
  LeanSetup s;
  const Vec3 rest = s.eye_midpoint();
  const Vec3 target = rest + Vec3(0, -0.8f, -0.8f);  // a deep bow, beyond the limits
  ASSERT_TRUE(s.job(target).run());
  EXPECT_FALSE(s.reached);
  EXPECT_LT((s.eye_midpoint() - target).norm(), (rest - target).norm());
  EXPECT_LE(s.deviation(Bone::kSpine), deg(20) + 1e-4f);
  EXPECT_LE(s.deviation(Bone::kChest), deg(25) + 1e-4f);
  EXPECT_GT(s.deviation(Bone::kChest), deg(25) - 1e-3f);  // used all it had
}

TEST(LeanJob, DegenerateTargetsAreHandled) {
  LeanSetup s;
  const std::vector<Pose> rest = s.rig.local;
  ASSERT_TRUE(s.job(Vec3(NAN, 1, 0)).run());
  EXPECT_FALSE(s.reached);
  EXPECT_EQ(s.error, -1.0f);
  // The target on a pivot: the point moves toward it, nothing goes beyond a limit.
  const Vec3 chest = s.rig.model[s.rig[Bone::kChest]].translation;
  const float before = (s.eye_midpoint() - chest).norm();
  ASSERT_TRUE(s.job(chest).run());
  for (std::size_t i = 0; i < rest.size(); ++i) {
    EXPECT_TRUE(s.rig.local[i].rotation.allFinite());
  }
  EXPECT_LE(s.error, before);
  EXPECT_LE(s.deviation(Bone::kSpine), deg(20) + 1e-4f);
  EXPECT_LE(s.deviation(Bone::kChest), deg(25) + 1e-4f);
}

}  // namespace
}  // namespace deixis::ik
