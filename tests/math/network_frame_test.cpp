#include "core/math/network_frame.h"

#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "core/math/rotation_6d.h"

namespace deixis {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

TEST(NetworkFrame, FlipsZOfVectors) {
  EXPECT_TRUE(to_network_frame(Vec3(1, 2, 3)).isApprox(Vec3(1, 2, -3)));
  EXPECT_TRUE(from_network_frame(to_network_frame(Vec3(1, 2, 3))).isApprox(Vec3(1, 2, 3)));
}

TEST(NetworkFrame, WorldForwardIsTheNetworkForwardColumn) {
  // Looking straight ahead in OpenXR (−Z) is looking along +Z in the network frame.
  EXPECT_TRUE(encode_6d(to_network_frame(Mat3(Mat3::Identity()))).forward.isApprox(Vec3(0, 0, 1)));
  const Mat3 R_world = yaw_rotation(0.6f);  // turned 0.6 rad to the left
  const Rotation6D r = encode_6d(to_network_frame(R_world));
  EXPECT_TRUE(r.forward.isApprox(to_network_frame(Vec3(R_world * Vec3(0, 0, -1))), 1e-6f));
  EXPECT_TRUE(r.up.isApprox(to_network_frame(Vec3(R_world * Vec3::UnitY())), 1e-6f));
  // A target along that gaze is to the left, so its θ is positive and equals the turn.
  const Vec3 target_world = R_world * Vec3(0, 0, -2);
  EXPECT_NEAR(target_angles(to_network_frame(target_world)).theta, 0.6f, 1e-6f);
}

TEST(NetworkFrame, RotationMapIsSRS) {
  std::mt19937 rng(5);
  std::normal_distribution<float> n(0.0f, 1.0f);
  const Mat3 S = Vec3(1, 1, -1).asDiagonal();
  for (int i = 0; i < 100; ++i) {
    const Mat3 R = Quat(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
    EXPECT_TRUE(to_network_frame(R).isApprox(S * R * S, 1e-6f));
    EXPECT_NEAR(to_network_frame(R).determinant(), 1.0f, 1e-5f);
    // Rotating a vector then converting equals converting both then rotating.
    const Vec3 v(n(rng), n(rng), n(rng));
    EXPECT_TRUE(
        to_network_frame(Vec3(R * v)).isApprox(to_network_frame(R) * to_network_frame(v), 1e-5f));
  }
}

TEST(NetworkFrame, PosesComposeTheSameInBothFrames) {
  const Pose T_root_head{yaw_rotation(0.3f), Vec3(0.02f, -0.01f, -0.05f)};
  const Pose T_head_hand{Eigen::AngleAxisf(0.8f, Vec3(1, 2, 3).normalized()).toRotationMatrix(),
                         Vec3(0.2f, -0.3f, -0.4f)};
  const Pose world = compose(T_root_head, T_head_hand);
  const Pose network = compose(to_network_frame(T_root_head), to_network_frame(T_head_hand));
  EXPECT_TRUE(to_network_frame(world).rotation.isApprox(network.rotation, 1e-6f));
  EXPECT_TRUE(to_network_frame(world).translation.isApprox(network.translation, 1e-6f));
}

TEST(TargetFeature, HandComputedAngles) {
  // Straight ahead (network +Z), at eye height: θ = 0, φ = atan2(z, y) = π/2.
  TargetAngles a = target_angles(Vec3(0, 0, 2));
  EXPECT_NEAR(a.theta, 0.0f, 1e-6f);
  EXPECT_NEAR(a.phi, kPi / 2, 1e-6f);
  EXPECT_NEAR(a.distance, 1.0f, 1e-6f);  // clamped at 1 m
  // 45° to the left (−x in the network frame is left): θ = atan2(−x, z) = +π/4.
  a = target_angles(Vec3(-0.5f, 0, 0.5f));
  EXPECT_NEAR(a.theta, kPi / 4, 1e-6f);
  EXPECT_NEAR(a.distance, std::sqrt(0.5f), 1e-6f);
  // Below and in front: y = −0.3, z = 0.3 → φ = atan2(0.3, −0.3) = 3π/4.
  a = target_angles(Vec3(0, -0.3f, 0.3f));
  EXPECT_NEAR(a.phi, 3 * kPi / 4, 1e-6f);
  // φ ignores x (docs/conventions.md#target-feature): moving sideways does not change it.
  EXPECT_NEAR(target_angles(Vec3(0.7f, -0.3f, 0.3f)).phi, 3 * kPi / 4, 1e-6f);
}

TEST(TargetFeature, LayoutIsHeadThenHand) {
  const TargetFeature t = target_feature(Vec3(-1, 0, 1), Vec3(0, -0.3f, 0.3f));
  EXPECT_NEAR(t[tf::kHeadTheta], kPi / 4, 1e-6f);
  EXPECT_NEAR(t[tf::kHeadPhi], kPi / 2, 1e-6f);
  EXPECT_NEAR(t[tf::kHandTheta], 0.0f, 1e-6f);
  EXPECT_NEAR(t[tf::kHandPhi], 3 * kPi / 4, 1e-6f);
  EXPECT_NEAR(t[tf::kHandDistance], std::sqrt(0.18f), 1e-6f);
}

TEST(Mirroring, NegatesXOfAllEightVectorsAndBothThetas) {
  EndEffectors x;
  for (int i = 0; i < kEndEffectorSize; ++i) {
    x[i] = static_cast<float>(i + 1);
  }
  EndEffectors mirrored = x;
  mirror_end_effectors(mirrored);
  for (int i = 0; i < kEndEffectorSize; ++i) {
    const bool is_x_component = i % 3 == 0;
    EXPECT_EQ(mirrored[i], is_x_component ? -x[i] : x[i]) << "index " << i;
  }
  mirror_end_effectors(mirrored);
  EXPECT_EQ(mirrored, x);  // its own inverse

  TargetFeature t = {0.5f, 1.2f, -0.4f, 2.0f, 0.8f};
  mirror_target_feature(t);
  EXPECT_EQ(t, (TargetFeature{-0.5f, 1.2f, 0.4f, 2.0f, 0.8f}));
}

TEST(Mirroring, MirroredTargetFeatureIsTheFeatureOfTheMirroredTarget) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u(-2.0f, 2.0f);
  for (int i = 0; i < 100; ++i) {
    const Vec3 head(u(rng), u(rng), std::abs(u(rng)) + 0.1f);
    const Vec3 hand(u(rng), u(rng), std::abs(u(rng)) + 0.1f);
    TargetFeature t = target_feature(head, hand);
    mirror_target_feature(t);
    const Vec3 mirror(-1, 1, 1);
    const TargetFeature expected =
        target_feature(head.cwiseProduct(mirror), hand.cwiseProduct(mirror));
    for (int k = 0; k < kTargetFeatureSize; ++k) {
      EXPECT_NEAR(t[k], expected[k], 1e-5f);
    }
  }
}

}  // namespace
}  // namespace deixis
