// OtherArmJob and ChestCylinder: the free hand keeps the user's azimuth, elevation and distance
// from the head and never ends inside the chest cylinder.

#include "ik/other_arm_job.h"

#include <gtest/gtest.h>

#include "limit_check.h"
#include "rig_pose.h"

namespace deixis::ik {
namespace {

using testing::RigPose;

struct OtherSetup {
  explicit OtherSetup(Hand hand = Hand::kLeft, bool bone_aligned = false)
      : rig(testing::TestRigOptions{.bone_aligned = bone_aligned}),
        arm(rig.solver.arms[index(hand)]) {}
  RigPose rig;
  ArmRig arm;
  OtherArmResult result;

  OtherArmJob job(const OtherHandTarget& target) {
    OtherArmJob j;
    j.skeleton = &rig.skeleton();
    j.arm = &arm;
    j.limits = &rig.solver.config.limits;
    j.cylinder = &rig.solver.cylinder;
    j.chest = rig.solver.cylinder_joint;
    j.head_position = eye_midpoint();
    j.target = target;
    j.pole = arm.pole;
    j.local = rig.local;
    j.model = rig.model;
    j.result = &result;
    return j;
  }
  Vec3 eye_midpoint() const {
    return transform_point(rig.model[rig[Bone::kHead]], rig.solver.rig.eye_midpoint_in_head);
  }
  // The wrist in the cylinder's frame.
  Vec3 wrist_in_cylinder() const {
    const Pose T =
        compose(rig.model[rig.solver.cylinder_joint], rig.solver.cylinder.T_chest_cylinder);
    return transform_point(inverse(T), rig.model[arm.hand].translation);
  }
};

float ellipse_level(const ChestCylinder& c, const Vec3& p) {
  return (p.x() / c.half_width) * (p.x() / c.half_width) +
         (p.z() / c.half_depth) * (p.z() / c.half_depth);
}

TEST(ChestCylinder, ProjectsInsidePointsRadiallyOntoTheBoundary) {
  ChestCylinder c;
  EXPECT_TRUE(inside(c, Vec3(0.05f, 0, 0.05f)));
  EXPECT_FALSE(inside(c, Vec3(0.05f, c.top + 0.01f, 0.05f)));
  EXPECT_FALSE(inside(c, Vec3(0.05f, c.bottom - 0.01f, 0.05f)));
  EXPECT_FALSE(inside(c, Vec3(0.0f, 0, 0.2f)));
  const Vec3 p(0.05f, 0.1f, -0.04f);
  const Vec3 q = project_out(c, p, 1.0f);
  EXPECT_NEAR(ellipse_level(c, q), 1.0f, 1e-5f);
  EXPECT_EQ(q.y(), p.y());
  EXPECT_NEAR(q.x() / q.z(), p.x() / p.z(), 1e-5f);  // along the ray from the axis
  EXPECT_EQ(project_out(c, Vec3(0.3f, 0, 0), 1.0f), Vec3(0.3f, 0, 0));
  EXPECT_EQ(project_out(c, Vec3(0, 0.05f, 0), -1.0f), Vec3(-c.half_width, 0.05f, 0));
  EXPECT_EQ(project_out(c, Vec3(0, 0.05f, 0), 1.0f), Vec3(c.half_width, 0.05f, 0));
}

TEST(OtherHandTarget, KeepsAzimuthElevationAndScaledDistance) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 100; ++i) {
    const Pose root{yaw_rotation(3 * u(rng)), Vec3(u(rng), 1.6f, u(rng))};
    const Pose head{testing::random_rotation(rng),
                    root.translation + 0.05f * Vec3(u(rng), u(rng), u(rng))};
    const Pose wrist{testing::random_rotation(rng),
                     head.translation + 0.6f * Vec3(u(rng), u(rng), u(rng))};
    const OtherHandTarget t = other_hand_target(root, head, wrist, 1.25f);
    const Vec3 back = head.translation +
                      root.rotation * (1.25f * t.distance * direction_of(t.azimuth, t.elevation));
    EXPECT_LT((back - wrist.translation).norm(), 1e-5f);
    EXPECT_TRUE((root.rotation * t.R_root_wrist).isApprox(wrist.rotation, 1e-5f));
  }
  // Positive azimuth is to the left (−X for a body facing −Z); positive elevation is up.
  EXPECT_TRUE(direction_of(deg(90), 0).isApprox(Vec3(-1, 0, 0), 1e-6f));
  EXPECT_TRUE(direction_of(0, deg(90)).isApprox(Vec3(0, 1, 0), 1e-6f));
  EXPECT_TRUE(direction_of(0, 0).isApprox(Vec3(0, 0, -1), 1e-6f));
}

TEST(OtherArmJob, ValidateRejectsEachBrokenRule) {
  OtherSetup s;
  const OtherHandTarget t;
  std::string_view why;
  ASSERT_TRUE(s.job(t).validate(&why)) << why;
  const auto expect_invalid = [&](const OtherArmJob& job, std::string_view expected) {
    std::string_view reason;
    EXPECT_FALSE(job.validate(&reason));
    EXPECT_EQ(reason, expected);
    EXPECT_FALSE(job.run());
  };
  OtherArmJob j = s.job(t);
  j.cylinder = nullptr;
  expect_invalid(j, "skeleton, arm, limits and cylinder must be set");
  j = s.job(t);
  j.local = {};
  expect_invalid(j, "local and model must hold one pose per skeleton joint");
  ArmRig broken = s.arm;
  broken.lower = broken.upper;
  j = s.job(t);
  j.arm = &broken;
  expect_invalid(j, "arm: upper, lower and hand must be joints, each below the previous");
  broken = s.arm;
  broken.index[2] = s.rig[Bone::kHead];
  j.arm = &broken;
  expect_invalid(j, "arm: index joints must hang below the hand");
  j = s.job(t);
  j.chest = 10000;
  expect_invalid(j, "chest is not a joint of the skeleton");
  ChestCylinder flat = s.rig.solver.cylinder;
  flat.half_depth = 0.0f;
  j = s.job(t);
  j.cylinder = &flat;
  expect_invalid(j, "cylinder needs positive semi-axes, bottom < top and a finite frame");
  flat = s.rig.solver.cylinder;
  flat.top = flat.bottom;
  expect_invalid(j, "cylinder needs positive semi-axes, bottom < top and a finite frame");
  j = s.job(t);
  j.soften = 2.0f;
  expect_invalid(j, "soften is not in (0, 1]");
  IkLimits bad;
  bad.elbow = {1.0f, 0.5f};
  j = s.job(t);
  j.limits = &bad;
  expect_invalid(j, "limits are not usable (see check(IkLimits))");
}

TEST(OtherArmJob, WristKeepsAzimuthElevationAndDistanceFromTheHead) {
  OtherSetup s(Hand::kLeft);
  // Gestures beside and in front of the body, all outside the chest and within reach.
  const std::array<std::array<float, 3>, 5> cases = {{{deg(20), deg(-40), 0.55f},
                                                      {deg(40), deg(-60), 0.6f},
                                                      {deg(70), deg(-30), 0.5f},
                                                      {deg(10), deg(-20), 0.4f},
                                                      {deg(90), deg(-80), 0.65f}}};
  for (const auto& [azimuth, elevation, distance] : cases) {
    s.rig.reset();
    OtherHandTarget t;
    t.azimuth = azimuth;
    t.elevation = elevation;
    t.distance = distance;
    ASSERT_TRUE(s.job(t).run());
    EXPECT_TRUE(s.result.reached);
    EXPECT_FALSE(s.result.projected);
    const Vec3 v = s.rig.model[s.arm.hand].translation - s.eye_midpoint();
    EXPECT_NEAR(v.norm(), distance, 1e-3f);
    EXPECT_NEAR(std::atan2(-v.x(), -v.z()), azimuth, deg(0.2f));
    EXPECT_NEAR(std::atan2(v.y(), std::hypot(v.x(), v.z())), elevation, deg(0.2f));
    EXPECT_EQ(testing::check_limits(s.rig.solver, s.rig.local, s.rig.model), "");
  }
}

TEST(OtherArmJob, HandStaysOutsideTheChestCylinder) {
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (const Hand hand : {Hand::kLeft, Hand::kRight}) {
    for (const bool bone_aligned : {false, true}) {
      OtherSetup s(hand, bone_aligned);
      int projected = 0;
      for (int i = 0; i < 2000; ++i) {
        s.rig.reset();
        OtherHandTarget t;
        t.azimuth = deg(180) * u(rng);
        t.elevation = deg(90) * u(rng);
        t.distance = 0.8f * std::abs(u(rng));
        t.R_root_wrist = testing::random_rotation(rng);
        ASSERT_TRUE(s.job(t).run());
        projected += s.result.projected;
        const Vec3 q = s.wrist_in_cylinder();
        const ChestCylinder& c = s.rig.solver.cylinder;
        // Inside the height range by more than round-off (a wrist can rest on the bottom face).
        if (q.y() > c.bottom + 1e-4f && q.y() < c.top - 1e-4f) {
          EXPECT_GE(ellipse_level(c, q), 1.0f - 1e-3f)
              << "wrist inside the chest at " << q.transpose();
        }
        ASSERT_EQ(testing::check_limits(s.rig.solver, s.rig.local, s.rig.model), "");
      }
      EXPECT_GT(projected, 100);  // the sweep did aim into the chest
    }
  }
}

TEST(OtherArmJob, NonFiniteTargetsLeaveThePose) {
  OtherSetup s;
  const std::vector<Pose> rest = s.rig.local;
  for (int k = 0; k < 4; ++k) {
    OtherHandTarget t;
    (k == 0 ? t.azimuth : k == 1 ? t.elevation : k == 2 ? t.distance : t.R_root_wrist(1, 1)) = NAN;
    ASSERT_TRUE(s.job(t).run());
    EXPECT_FALSE(s.result.reached);
    for (std::size_t i = 0; i < rest.size(); ++i) {
      EXPECT_TRUE(s.rig.local[i].rotation.isApprox(rest[i].rotation));
    }
  }
}

}  // namespace
}  // namespace deixis::ik
