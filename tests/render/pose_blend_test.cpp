// Interpolation between two ticks: slerp along the shorter arc, lerp of translations, clamped.

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/error.h"
#include "render/pose_blend.h"

namespace deixis::render {
namespace {

Mat3 about(const Vec3& axis, float angle) {
  return Eigen::AngleAxisf(angle, axis.normalized()).toRotationMatrix();
}

float angle_between(const Mat3& a, const Mat3& b) {
  return Eigen::AngleAxisf(a.transpose() * b).angle();
}

TEST(PoseBlendTest, EndsAreTheTwoPoses) {
  const Pose a{about(Vec3(1, 0, 0), 0.3f), Vec3(1, 2, 3)};
  const Pose b{about(Vec3(0, 1, 1), 1.1f), Vec3(-1, 0, 2)};
  EXPECT_TRUE(blend(a, b, 0.0f).rotation.isApprox(a.rotation, 1e-5f));
  EXPECT_TRUE(blend(a, b, 0.0f).translation.isApprox(a.translation, 1e-6f));
  EXPECT_TRUE(blend(a, b, 1.0f).rotation.isApprox(b.rotation, 1e-5f));
  EXPECT_TRUE(blend(a, b, 1.0f).translation.isApprox(b.translation, 1e-6f));
}

TEST(PoseBlendTest, MidwayIsHalfTheRotationAndTheMidpoint) {
  const Pose a{Mat3::Identity(), Vec3(0, 0, 0)};
  const Pose b{about(Vec3::UnitY(), 1.2f), Vec3(2, 4, -6)};
  const Pose m = blend(a, b, 0.25f);
  EXPECT_TRUE(m.rotation.isApprox(about(Vec3::UnitY(), 0.3f), 1e-5f));
  EXPECT_TRUE(m.translation.isApprox(Vec3(0.5f, 1, -1.5f), 1e-6f));
  EXPECT_NEAR(m.rotation.determinant(), 1.0f, 1e-5f);
}

TEST(PoseBlendTest, TakesTheShorterArc) {
  // 350° about +Z is −10°: halfway is −5°, not 175°.
  const Pose a{Mat3::Identity(), Vec3::Zero()};
  const Pose b{about(Vec3::UnitZ(), 6.1086524f), Vec3::Zero()};
  const Pose m = blend(a, b, 0.5f);
  EXPECT_NEAR(angle_between(m.rotation, Mat3::Identity()), 0.0872665f, 1e-4f);
}

TEST(PoseBlendTest, FactorIsClamped) {
  const Pose a{Mat3::Identity(), Vec3(0, 0, 0)};
  const Pose b{about(Vec3::UnitX(), 0.5f), Vec3(1, 0, 0)};
  EXPECT_TRUE(blend(a, b, 1.7f).translation.isApprox(b.translation));
  EXPECT_TRUE(blend(a, b, -0.3f).translation.isApprox(a.translation));
}

TEST(PoseBlendTest, BlendsEveryJointAndChecksSizes) {
  const std::vector<Pose> from = {Pose{Mat3::Identity(), Vec3(0, 0, 0)},
                                  Pose{about(Vec3::UnitX(), 0.2f), Vec3(0, 1, 0)}};
  const std::vector<Pose> to = {Pose{about(Vec3::UnitY(), 0.4f), Vec3(2, 0, 0)},
                                Pose{about(Vec3::UnitX(), 0.6f), Vec3(0, 3, 0)}};
  std::vector<Pose> out(2);
  blend_poses(from, to, 0.5f, out);
  EXPECT_TRUE(out[0].translation.isApprox(Vec3(1, 0, 0)));
  EXPECT_TRUE(out[1].rotation.isApprox(about(Vec3::UnitX(), 0.4f), 1e-5f));
  EXPECT_TRUE(out[1].translation.isApprox(Vec3(0, 2, 0)));
  std::vector<Pose> wrong(1);
  EXPECT_THROW(blend_poses(from, to, 0.5f, wrong), Error);
}

}  // namespace
}  // namespace deixis::render
