#include "core/math/pose.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace deixis {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  return Quat(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

TEST(Pose, ComposeAppliesChildThenParent) {
  // Head 1.6 m up, turned 90° left (about +Y); a hand 0.3 m in front of the head (−Z forward).
  const Pose T_root_head{yaw_rotation(kPi / 2), Vec3(0, 1.6f, 0)};
  const Pose T_head_hand{Mat3::Identity(), Vec3(0, 0, -0.3f)};
  const Pose T_root_hand = compose(T_root_head, T_head_hand);
  // Turning left by 90° carries −Z (forward) onto −X.
  EXPECT_NEAR(T_root_hand.translation.x(), -0.3f, 1e-6f);
  EXPECT_NEAR(T_root_hand.translation.y(), 1.6f, 1e-6f);
  EXPECT_NEAR(T_root_hand.translation.z(), 0.0f, 1e-6f);
  EXPECT_TRUE(transform_point(T_root_head, Vec3(0, 0, -0.3f)).isApprox(T_root_hand.translation));
}

TEST(Pose, InverseUndoesCompose) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  for (int i = 0; i < 100; ++i) {
    const Pose T_a_b{random_rotation(rng), Vec3(u(rng), u(rng), u(rng))};
    const Pose identity = compose(T_a_b, inverse(T_a_b));
    EXPECT_TRUE(identity.rotation.isIdentity(1e-5f));
    EXPECT_LT(identity.translation.norm(), 1e-5f);
    const Vec3 p(u(rng), u(rng), u(rng));
    EXPECT_TRUE(transform_point(inverse(T_a_b), transform_point(T_a_b, p)).isApprox(p, 1e-5f));
  }
}

TEST(Pose, DirectionsIgnoreTranslation) {
  const Pose T{yaw_rotation(kPi), Vec3(5, 6, 7)};
  EXPECT_TRUE(transform_direction(T, Vec3(0, 0, -1)).isApprox(Vec3(0, 0, 1), 1e-6f));
}

TEST(Pose, YawOfRecoversTheYawAngle) {
  for (const float angle : {-3.0f, -1.2f, 0.0f, 0.4f, 2.9f}) {
    EXPECT_NEAR(yaw_of(yaw_rotation(angle), Vec3(0, 0, -1)), angle, 1e-5f) << angle;
    EXPECT_NEAR(yaw_of(yaw_rotation(angle), Vec3(0, 0, 1)), angle, 1e-5f) << angle;
  }
  // Pitch does not change the yaw of the facing direction.
  const Mat3 pitched =
      yaw_rotation(0.7f) * Eigen::AngleAxisf(0.5f, Vec3::UnitX()).toRotationMatrix();
  EXPECT_NEAR(yaw_of(pitched, Vec3(0, 0, -1)), 0.7f, 1e-5f);
}

TEST(Pose, IsFiniteDetectsNaN) {
  Pose T;
  EXPECT_TRUE(is_finite(T));
  T.translation.y() = std::nanf("");
  EXPECT_FALSE(is_finite(T));
}

}  // namespace
}  // namespace deixis
