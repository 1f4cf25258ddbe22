// The rotation helpers and the skeleton path update the jobs are built on.

#include "ik/rotations.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "ik/joint_limits.h"
#include "ik/skeleton.h"
#include "rig_pose.h"

namespace deixis::ik {
namespace {

bool is_rotation(const Mat3& R) {
  return R.allFinite() && (R.transpose() * R).isIdentity(1e-5f) &&
         std::abs(R.determinant() - 1) < 1e-5f;
}

TEST(Rotations, RotationBetweenCarriesFromOntoTo) {
  std::mt19937 rng(1);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 a = testing::random_unit(rng);
    const Vec3 b = i % 10 == 0 ? Vec3(-a) : i % 10 == 1 ? a : testing::random_unit(rng);
    const Mat3 R = rotation_between(a, b);
    EXPECT_TRUE(is_rotation(R));
    EXPECT_LT((R * a - b).norm(), 1e-5f);
    // The smallest such rotation: its angle is the angle between them.
    EXPECT_NEAR(rotation_angle(R), testing::angle_between(a, b), 1e-3f);
  }
}

TEST(Rotations, SwingTwistRecomposesAndSplitsAtTheAxis) {
  std::mt19937 rng(2);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 axis = testing::random_unit(rng);
    const float twist = deg(170) * (2.0f * std::uniform_real_distribution<float>(0, 1)(rng) - 1);
    const Vec3 swing_axis = frame_from(axis, testing::random_unit(rng)).col(1);
    const Mat3 swing =
        axis_angle(swing_axis, deg(120) * std::uniform_real_distribution<float>(0, 1)(rng));
    const Mat3 R = swing * axis_angle(axis, twist);
    const SwingTwist st = swing_twist(R, axis);
    EXPECT_NEAR(st.twist, twist, 1e-4f);
    EXPECT_TRUE((st.swing * axis_angle(axis, st.twist)).isApprox(R, 1e-5f));
    // The swing turns about an axis perpendicular to the twist axis.
    const Eigen::AngleAxisf aa(st.swing);
    EXPECT_LT(std::abs(aa.axis().dot(axis)) * std::sin(aa.angle() / 2), 1e-4f);
  }
  // A swing by π has no twist to split off.
  const SwingTwist flip = swing_twist(axis_angle(Vec3::UnitX(), kPi), Vec3::UnitY());
  EXPECT_EQ(flip.twist, 0.0f);
  EXPECT_TRUE(is_rotation(flip.swing));
}

TEST(Rotations, ScaleAndClampKeepTheAxis) {
  const Mat3 R = axis_angle(Vec3(1, 2, 2) / 3.0f, deg(80));
  EXPECT_TRUE(scale_rotation(R, 0.25f).isApprox(axis_angle(Vec3(1, 2, 2) / 3.0f, deg(20)), 1e-5f));
  EXPECT_TRUE(scale_rotation(R, 0.0f).isIdentity(1e-6f));
  EXPECT_TRUE(
      clamp_rotation(R, deg(30)).isApprox(axis_angle(Vec3(1, 2, 2) / 3.0f, deg(30)), 1e-5f));
  EXPECT_TRUE(clamp_rotation(R, deg(90)).isApprox(R));
  EXPECT_NEAR(rotation_angle(axis_angle(Vec3::UnitZ(), deg(179.9f))), deg(179.9f), 1e-4f);
  EXPECT_NEAR(rotation_angle(axis_angle(Vec3::UnitZ(), 1e-4f)), 1e-4f, 1e-7f);
}

// clamp_rotation as it was before its shortcut: the angle computed every time. The shortcut must
// decide exactly as this does, so that the IK's results keep their bits.
Mat3 clamp_by_angle(const Mat3& R, float max_angle) {
  Quat q(R);
  if (q.w() < 0.0f) {
    q.coeffs() = -q.coeffs();
  }
  const float s = q.vec().norm();
  const float angle = 2.0f * std::atan2(s, q.w());
  if (angle <= max_angle || s < 1e-7f) {
    return R;
  }
  return axis_angle(q.vec() / s, max_angle);
}

TEST(Rotations, ClampDecidesAsTheAngleWouldEvenAtTheLimit) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  std::uniform_real_distribution<float> limit(0.0f, kPi);
  // Rotations at the limit give or take a few ulp, within 2e-4 of it, and anywhere.
  std::uniform_real_distribution<float> near(-2e-4f, 2e-4f);
  std::uniform_real_distribution<float> anywhere(0.0f, kPi);
  int clamped = 0;
  int inside = 0;
  for (int i = 0; i < 200000; ++i) {
    const Vec3 axis = normalized_or(Vec3(unit(rng), unit(rng), unit(rng)), Vec3::UnitX());
    const float max_angle = i % 50 == 0 ? 0.0f : limit(rng);
    float angle = max_angle;
    if (i % 3 == 1) {
      angle = std::clamp(max_angle * (1.0f + near(rng)), 0.0f, kPi);
    } else if (i % 3 == 2) {
      angle = anywhere(rng);
    } else {
      for (int ulps = static_cast<int>(rng() % 9) - 4; ulps != 0; ulps += ulps > 0 ? -1 : 1) {
        angle = std::nextafter(angle, ulps > 0 ? kPi : 0.0f);
      }
    }
    const Mat3 R = axis_angle(axis, angle);
    const Mat3 expected = clamp_by_angle(R, max_angle);
    const Mat3 got = clamp_rotation(R, max_angle);
    ASSERT_EQ(std::memcmp(expected.data(), got.data(), sizeof(Mat3)), 0)
        << "angle " << angle << " limit " << max_angle;
    (expected == R ? inside : clamped) += 1;
  }
  // Both decisions were exercised, many times.
  EXPECT_GT(clamped, 20000);
  EXPECT_GT(inside, 20000);
}

TEST(Rotations, DegenerateInputHasFallbacksNotNaN) {
  EXPECT_TRUE(orthonormalized(Mat3::Zero()).isIdentity());
  Mat3 nan = Mat3::Identity();
  nan(0, 1) = NAN;
  EXPECT_TRUE(orthonormalized(nan).isIdentity());
  Mat3 garbage;
  garbage << 1, 2, 3, 4, 5, 6, 7, 8, 10;
  EXPECT_TRUE(is_rotation(orthonormalized(garbage)));
  EXPECT_TRUE(is_rotation(orthonormalized(3.0f * axis_angle(Vec3::UnitX(), 1.0f))));
  EXPECT_EQ(normalized_or(Vec3::Zero(), Vec3::UnitY()), Vec3::UnitY());
  EXPECT_EQ(normalized_or(Vec3(INFINITY, 0, 0), Vec3::UnitY()), Vec3::UnitY());
  for (const Vec3& v :
       {Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(Vec3(1, 1, 1).normalized())}) {
    EXPECT_NEAR(any_perpendicular(v).dot(v), 0.0f, 1e-6f);
    EXPECT_NEAR(any_perpendicular(v).norm(), 1.0f, 1e-6f);
    EXPECT_TRUE(is_rotation(frame_from(v, v)));
  }
}

TEST(JointLimits, ClampToRestBoundsTheDeviation) {
  std::mt19937 rng(3);
  for (int i = 0; i < 200; ++i) {
    const Mat3 rest = testing::random_rotation(rng);
    const Mat3 local = rest * testing::random_rotation(rng);
    const Mat3 clamped = clamp_to_rest(local, rest, deg(30));
    EXPECT_LE(rotation_angle(rest_deviation(clamped, rest)), deg(30) + 1e-4f);
    if (rotation_angle(rest_deviation(local, rest)) <= deg(30)) {
      EXPECT_TRUE(clamped.isApprox(local, 1e-5f));
    }
  }
}

TEST(Skeleton, UpdateModelPathMatchesLocalToModel) {
  std::mt19937 rng(4);
  testing::RigPose rig(testing::TestRigOptions{.bone_aligned = true});
  const Skeleton& sk = rig.skeleton();
  for (int i = 0; i < 50; ++i) {
    rig.reset();
    // Change every joint on the chest → right index tip path, then update only the path.
    const int from = rig[Bone::kChest];
    const int to = rig[Bone::kRightIndexDistal];
    for (int j = to; j != sk.parents[from]; j = sk.parents[j]) {
      rig.local[j].rotation = rig.local[j].rotation * testing::random_rotation(rng, 1.0f);
    }
    update_model_path(sk, rig.local, rig.model, from, to);
    std::vector<Pose> full(rig.model.size());
    local_to_model(sk, rig.local, full);
    for (int j = to; j != sk.parents[from]; j = sk.parents[j]) {
      EXPECT_TRUE(rig.model[j].rotation.isApprox(full[j].rotation, 1e-5f));
      EXPECT_LT((rig.model[j].translation - full[j].translation).norm(), 1e-5f);
    }
  }
  EXPECT_TRUE(is_ancestor(sk, rig[Bone::kHips], rig[Bone::kLeftEye]));
  EXPECT_TRUE(is_ancestor(sk, rig[Bone::kHead], rig[Bone::kHead]));
  EXPECT_FALSE(is_ancestor(sk, rig[Bone::kLeftHand], rig[Bone::kRightHand]));
}

}  // namespace
}  // namespace deixis::ik
