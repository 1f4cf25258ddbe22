// EyeJob: both eyes look along the gaze within their range, clamped at its edge beyond it.

#include "ik/eye_job.h"

#include <gtest/gtest.h>

#include "rig_pose.h"

namespace deixis::ik {
namespace {

using testing::angle_between;
using testing::RigPose;

struct EyeSetup {
  explicit EyeSetup(bool bone_aligned = false)
      : rig(testing::TestRigOptions{.bone_aligned = bone_aligned}),
        eyes{rig[Bone::kLeftEye], rig[Bone::kRightEye]} {}
  RigPose rig;
  std::array<int, 2> eyes;
  bool reached = false;

  EyeJob job(const Vec3& gaze) {
    EyeJob j;
    j.skeleton = &rig.skeleton();
    j.rest_model = rig.solver.rest_model;
    j.head = rig[Bone::kHead];
    j.eyes = eyes;
    j.gaze = gaze;
    j.local = rig.local;
    j.model = rig.model;
    j.reached = &reached;
    return j;
  }
  // An eye's line of sight: its rest forward (−Z in the model) carried by its rotation.
  Vec3 sight(int eye) const {
    return rig.model[eye].rotation * rig.solver.rest_model[eye].rotation.transpose() *
           Vec3(0, 0, -1);
  }
};

TEST(EyeJob, ValidateRejectsEachBrokenRule) {
  EyeSetup s;
  std::string_view why;
  ASSERT_TRUE(s.job(Vec3(0, 0, -1)).validate(&why)) << why;
  const auto expect_invalid = [&](const EyeJob& job, std::string_view expected) {
    std::string_view reason;
    EXPECT_FALSE(job.validate(&reason));
    EXPECT_EQ(reason, expected);
    EXPECT_FALSE(job.run());
  };
  EyeJob j = s.job(Vec3(0, 0, -1));
  j.skeleton = nullptr;
  expect_invalid(j, "skeleton is not set");
  j = s.job(Vec3(0, 0, -1));
  j.rest_model = {};
  expect_invalid(j, "rest_model, local and model must hold one pose per skeleton joint");
  j = s.job(Vec3(0, 0, -1));
  j.head = -2;
  expect_invalid(j, "head is not a joint of the skeleton");
  j = s.job(Vec3(0, 0, -1));
  j.eyes = {};
  expect_invalid(j, "eyes must hold 1 or 2 joints");
  const std::array<int, 3> three = {s.eyes[0], s.eyes[1], s.eyes[0]};
  j.eyes = three;
  expect_invalid(j, "eyes must hold 1 or 2 joints");
  const std::array<int, 1> not_below = {s.rig[Bone::kRightHand]};
  j.eyes = not_below;
  expect_invalid(j, "eyes must be joints below the head");
  const std::array<int, 1> the_head = {s.rig[Bone::kHead]};
  j.eyes = the_head;
  expect_invalid(j, "eyes must be joints below the head");
  j = s.job(Vec3(0, 0, -1));
  j.range.up = deg(95);
  expect_invalid(j, "range: yaw must lie in [0, π], up and down in [0, π/2)");
  j = s.job(Vec3(0, 0, -1));
  j.range.yaw = -0.1f;
  expect_invalid(j, "range: yaw must lie in [0, π], up and down in [0, π/2)");
}

TEST(EyeJob, EyesPointAlongTheGazeWithinTheirRange) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (const bool bone_aligned : {false, true}) {
    EyeSetup s(bone_aligned);
    for (int i = 0; i < 300; ++i) {
      s.rig.reset();
      // Turn the head first: the range is the face's, not the room's.
      const int head = s.rig[Bone::kHead];
      s.rig.local[head].rotation =
          s.rig.local[head].rotation * testing::random_rotation(rng, deg(40));
      local_to_model(s.rig.skeleton(), s.rig.local, s.rig.model);
      const Mat3 face =
          s.rig.model[head].rotation * s.rig.solver.rest_model[head].rotation.transpose();
      const float yaw = deg(34) * u(rng);
      const float pitch =
          u(rng) > 0 ? deg(24) * 0.5f * (u(rng) + 1) : -deg(34) * 0.5f * (u(rng) + 1);
      const Vec3 gaze = face * Vec3(-std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                                    -std::cos(yaw) * std::cos(pitch));
      ASSERT_TRUE(s.job(gaze).run());
      EXPECT_TRUE(s.reached);
      for (const int eye : s.eyes) {
        EXPECT_LT(angle_between(s.sight(eye), gaze), deg(0.01f));
        // The eye turned in place.
        EXPECT_LT((s.rig.model[eye].translation -
                   transform_point(s.rig.model[head], s.rig.skeleton().rest_local[eye].translation))
                      .norm(),
                  1e-6f);
      }
    }
  }
}

TEST(EyeJob, GazeBeyondTheRangeStopsAtItsEdge) {
  EyeSetup s;
  // 60° to the right (−yaw) and 50° up: clamped to 35° and 25°.
  const float yaw = -deg(60), pitch = deg(50);
  const Vec3 gaze(-std::sin(yaw) * std::cos(pitch), std::sin(pitch),
                  -std::cos(yaw) * std::cos(pitch));
  ASSERT_TRUE(s.job(gaze).run());
  EXPECT_FALSE(s.reached);
  const Vec3 edge(-std::sin(-deg(35)) * std::cos(deg(25)), std::sin(deg(25)),
                  -std::cos(-deg(35)) * std::cos(deg(25)));
  for (const int eye : s.eyes) {
    EXPECT_LT(angle_between(s.sight(eye), edge), deg(0.01f));
  }
  // Straight behind: the yaw clamps to one side, nothing is NaN.
  ASSERT_TRUE(s.job(Vec3(0, 0, 1)).run());
  EXPECT_FALSE(s.reached);
  EXPECT_NEAR(angle_between(s.sight(s.eyes[0]), Vec3(0, 0, -1)), deg(35), deg(0.01f));
}

TEST(EyeJob, NoGazeLooksStraightAhead) {
  EyeSetup s;
  for (const Vec3& gaze : {Vec3(0, 0, 0), Vec3(NAN, 0, -1), Vec3(0, INFINITY, 0)}) {
    ASSERT_TRUE(s.job(gaze).run());
    for (const int eye : s.eyes) {
      EXPECT_LT(angle_between(s.sight(eye), Vec3(0, 0, -1)), deg(0.01f));
    }
  }
}

}  // namespace
}  // namespace deixis::ik
