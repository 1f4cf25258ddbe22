// Each metric against hand-computed cases: a fingertip offset by a known angle gives
// that HE and VE to 0.01°, identical motion gives FMD 0, a known hold pattern gives the expected
// MPJPE and velocity error.

#include "eval/metrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/error.h"

namespace deixis::eval {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;
float radians(double degrees) {
  return static_cast<float>(degrees * std::numbers::pi / 180.0);
}

// Upright head at the root, identity hand frame, the fingertip `reach` straight ahead (+Z in the
// network frame).
EndEffectors pointing_pose(float reach = 0.54f) {
  EndEffectors x{};
  set_vec3(x, ee::kGaze, Vec3(0, 0, 1));
  set_vec3(x, ee::kHeadForward, Vec3(0, 0, 1));
  set_vec3(x, ee::kHeadUp, Vec3(0, 1, 0));
  set_vec3(x, ee::kHeadPosition, Vec3(0, 0, 0));
  set_vec3(x, ee::kHandForward, Vec3(0, 0, 1));
  set_vec3(x, ee::kHandUp, Vec3(0, 1, 0));
  set_vec3(x, ee::kHandPosition, Vec3(0, -0.05f, reach - 0.1f));
  set_vec3(x, ee::kFingertip, Vec3(0, 0.05f, 0.1f));
  return x;
}

TEST(ProgressionError, MeanAbsoluteErrorPerChannel) {
  const std::vector<nn::Progression> predicted = {{0.5f, 0.0f, 1.0f}, {1.0f, 0.25f, 0.0f}};
  const std::vector<nn::Progression> labels = {{0.0f, 0.0f, 1.0f}, {1.0f, 0.75f, 0.5f}};
  const ProgressionError e = progression_error(predicted, labels);
  EXPECT_DOUBLE_EQ(e.channel[0], 0.25);
  EXPECT_DOUBLE_EQ(e.channel[1], 0.25);
  EXPECT_DOUBLE_EQ(e.channel[2], 0.25);
  EXPECT_DOUBLE_EQ(e.total, 0.25);
  EXPECT_THROW(progression_error(predicted, std::span(labels).first(1)), deixis::Error);
}

TEST(DeicticChain, ComposesHeadHandAndFingertip) {
  EndEffectors x = pointing_pose();
  // Turn the head 90° to the left (network frame: +Z forward, left is −X) and lift it 2 cm.
  set_vec3(x, ee::kHeadForward, Vec3(-1, 0, 0));
  set_vec3(x, ee::kHeadPosition, Vec3(0, 0.02f, 0));
  const DeicticChain chain = deictic_chain(x);
  EXPECT_TRUE(chain.head.isApprox(Vec3(0, 0.02f, 0)));
  // The fingertip is 0.54 m ahead of the head in the head frame: (0, 0, 0.54) → (−0.54, 0, 0).
  EXPECT_TRUE(chain.fingertip.isApprox(Vec3(-0.54f, 0.02f, 0.0f), 1e-5f));
}

TEST(PointingError, AKnownHorizontalAndVerticalOffset) {
  const DeicticChain chain = deictic_chain(pointing_pose());  // EFR straight ahead
  for (const double yaw : {0.0, 1.0, 2.37, 10.0, 45.0}) {
    for (const double pitch : {0.0, 1.57, 5.0, 20.0}) {
      // A target `yaw` degrees to the side and `pitch` degrees up, seen from the head, 2 m away.
      const float h = radians(yaw), v = radians(pitch);
      const Vec3 target(2.0f * std::sin(h), 2.0f * std::tan(v), 2.0f * std::cos(h));
      const PointingError e = pointing_error(chain, target);
      EXPECT_NEAR(e.horizontal_deg, yaw, 0.01) << yaw << ", " << pitch;
      // The y–z projection sees the elevation as atan(y / z).
      EXPECT_NEAR(
          e.vertical_deg,
          static_cast<double>(std::atan2(std::tan(v), std::cos(h))) * 180.0 / std::numbers::pi,
          0.01);
    }
  }
  const PointingError straight = pointing_error(chain, Vec3(0, 0, 3));
  EXPECT_NEAR(straight.horizontal_deg, 0.0, 0.01);
  EXPECT_NEAR(straight.vertical_deg, 0.0, 0.01);
}

TEST(TouchingError, CentimetresFromTheFingertip) {
  const DeicticChain chain = deictic_chain(pointing_pose(0.4f));
  EXPECT_NEAR(touching_error_cm(chain, chain.fingertip + Vec3(0.03f, 0, 0)), 3.0, 1e-4);
  EXPECT_NEAR(touching_error_cm(chain, chain.fingertip + Vec3(0, 0.012f, -0.016f)), 2.0, 1e-4);
}

TEST(FrechetDistance, IdenticalSetsGiveZero) {
  std::mt19937 rng(4);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<std::vector<double>> set(200, std::vector<double>(16));
  for (auto& row : set) {
    for (double& v : row) {
      v = n(rng);
    }
  }
  EXPECT_NEAR(frechet_distance(set, set), 0.0, 1e-9);
}

// The motion encoder's 128-dimensional embeddings of a short sequence are fewer than their
// dimensions, so the covariances are singular; the trace of the square-root term then rounds a
// little above the traces, and before the floor every one of these 20 identical pairs came out
// below zero ("-0.00" in the tables, copy-paste's FMD). The distance is a squared distance:
// never below zero, and two different singular sets still a positive distance.
TEST(FrechetDistance, IdenticalSingularSetsGiveZeroNotBelow) {
  std::normal_distribution<double> n(0.0, 3.0);
  int below = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    std::mt19937 rng(seed);
    std::vector<std::vector<double>> set(40, std::vector<double>(128));
    for (auto& row : set) {
      for (double& v : row) {
        v = n(rng);
      }
    }
    const double d = frechet_distance(set, set);
    EXPECT_NEAR(d, 0.0, 1e-9) << "seed " << seed;
    below += d < 0.0 ? 1 : 0;
    std::vector<std::vector<double>> shifted = set;
    for (auto& row : shifted) {
      row[seed % 128] += 0.5;  // the means differ by 0.5 in one dimension: FMD ≈ 0.25
    }
    EXPECT_NEAR(frechet_distance(set, shifted), 0.25, 1e-4) << "seed " << seed;
  }
  EXPECT_EQ(below, 0);
}

TEST(FrechetDistance, HandComputedOneDimensionalCases) {
  // real: mean 1, variance 2; generated: mean 2, variance 2 → 1 + 2 + 2 − 2·√4 = 1.
  const std::vector<std::vector<double>> real = {{0.0}, {2.0}};
  EXPECT_NEAR(frechet_distance(real, std::vector<std::vector<double>>{{1.0}, {3.0}}), 1.0, 1e-12);
  // generated: mean 2, variance 8 → 1 + 2 + 8 − 2·√16 = 3.
  EXPECT_NEAR(frechet_distance(real, std::vector<std::vector<double>>{{0.0}, {4.0}}), 3.0, 1e-12);
  // Shifting every generated embedding by m adds |m|².
  const std::vector<std::vector<double>> a = {{0, 0}, {1, 2}, {3, 1}, {2, 5}};
  std::vector<std::vector<double>> b = a;
  for (auto& row : b) {
    row[0] += 3.0;
    row[1] -= 4.0;
  }
  EXPECT_NEAR(frechet_distance(a, b), 25.0, 1e-9);
  EXPECT_THROW(frechet_distance(real, std::vector<std::vector<double>>{{1.0}}), deixis::Error);
}

TEST(AxisAngle, RecoversAxisTimesAngle) {
  const Vec3 axis = Vec3(1, 2, 3).normalized();
  for (const float angle : {0.0f, 1e-4f, 0.7f, 2.0f, kPi - 1e-3f}) {
    const Mat3 R = Eigen::AngleAxisf(angle, axis).toRotationMatrix();
    EXPECT_TRUE(axis_angle(R).isApprox(axis * angle, 1e-4f) || angle == 0.0f) << angle;
    EXPECT_LT(axis_angle(Mat3(Mat3::Identity())).norm(), 1e-7f);
  }
}

TEST(MotionDeviation, IdenticalRunsGiveZero) {
  std::vector<EndEffectors> run(10, pointing_pose());
  const MotionDeviation d = motion_deviation(run, run);
  EXPECT_DOUBLE_EQ(d.position_cm, 0.0);
  EXPECT_DOUBLE_EQ(d.rotation_deg, 0.0);
  EXPECT_DOUBLE_EQ(d.linear_velocity_cm_s, 0.0);
  EXPECT_DOUBLE_EQ(d.angular_velocity_deg_s, 0.0);
}

TEST(MotionDeviation, AKnownHoldPattern) {
  // The clean hand moves 1 cm per frame along x; the noisy run holds frame 2 for frames 3–5
  // (missed tracking) and then catches up.
  std::vector<EndEffectors> clean, noisy;
  for (int t = 0; t < 10; ++t) {
    EndEffectors x = pointing_pose();
    set_vec3(x, ee::kHandPosition, Vec3(0.01f * static_cast<float>(t), 0, 0.4f));
    clean.push_back(x);
    noisy.push_back(t >= 3 && t <= 5 ? noisy[2] : x);
  }
  const MotionDeviation d = motion_deviation(clean, noisy);
  // Hand errors 1, 2, 3 cm on three of ten frames, the head none: (6 / 10) / 2 = 0.3 cm.
  EXPECT_NEAR(d.position_cm, 0.3, 1e-4);
  // Velocities (cm/s): clean 30 everywhere; noisy 0, 0, 0 then 120 across the catch-up: errors
  // 30 + 30 + 30 + 90 = 180 over 9 intervals for the hand, none for the head → 10 cm/s.
  EXPECT_NEAR(d.linear_velocity_cm_s, 10.0, 1e-3);
  EXPECT_DOUBLE_EQ(d.rotation_deg, 0.0);
}

TEST(MotionDeviation, AHeadTurnHeldForOneFrame) {
  // The clean head turns 3° per frame about +Y; the noisy one misses frame 1 (holds frame 0).
  std::vector<EndEffectors> clean, noisy;
  for (int t = 0; t < 3; ++t) {
    EndEffectors x = pointing_pose();
    const float a = radians(3.0 * t);
    set_vec3(x, ee::kHeadForward, Vec3(std::sin(a), 0, std::cos(a)));
    clean.push_back(x);
    noisy.push_back(t == 1 ? clean[0] : x);
  }
  const MotionDeviation d = motion_deviation(clean, noisy);
  EXPECT_NEAR(d.rotation_deg, (3.0 / 2.0) / 3.0, 1e-3);  // 3° on one of 3 frames, head only
  // Angular speeds (°/s): clean 90, 90; noisy 0, 180 → errors 90, 90 → head mean 90 → 45.
  EXPECT_NEAR(d.angular_velocity_deg_s, 45.0, 1e-2);
}

}  // namespace
}  // namespace deixis::eval
