// The FMD autoencoder's reconstruction errors (train/reconstruction.h) on hand-computed
// cases: identical motion is 0 cm and 0°; a head moved by 1 cm is 0.5 cm averaged over head and
// hand; a hand turned by 30° about any axis is 15°; 6D vectors that are not unit or not
// orthogonal are orthonormalised first, so they measure the rotation they stand for.

#include "train/reconstruction.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <cmath>

namespace deixis::train {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Segments [n, 30, 18] of a still pose: head and hand facing −z, up +y, at fixed positions.
torch::Tensor still_segments(int n) {
  torch::Tensor row = torch::tensor({0.f, 0.f, -1.f, 0.f, 1.f, 0.f,  // head forward, up
                                     0.02f, -0.01f, 0.03f,           // head position (m)
                                     0.f, 0.f, -1.f, 0.f, 1.f, 0.f,  // hand forward, up
                                     0.25f, -0.35f, -0.30f});        // hand position (m)
  return row.repeat({n, 30, 1});
}

// Rodrigues: `v` [.., 3] turned by `angle` about the unit `axis`.
torch::Tensor turned(const torch::Tensor& v, const torch::Tensor& axis, double angle) {
  return v * std::cos(angle) + torch::cross(axis.expand_as(v), v, -1) * std::sin(angle) +
         axis * (v * axis).sum(-1, true) * (1 - std::cos(angle));
}

TEST(Reconstruction, IdenticalMotionHasNoError) {
  const torch::Tensor real = still_segments(4) + 0.01 * torch::randn({4, 30, 18});
  const ReconstructionError e = motion_errors(real, real.clone());
  EXPECT_NEAR(e.position_cm, 0.0, 1e-9);
  EXPECT_NEAR(e.rotation_deg, 0.0, 1e-3);  // acos near 1: float rounding of the frames
  EXPECT_EQ(e.segments, 4u);
}

TEST(Reconstruction, AHeadOneCentimetreOffIsHalfACentimetreOverHeadAndHand) {
  const torch::Tensor real = still_segments(3);
  torch::Tensor moved = real.clone();
  moved.select(2, 6) += 0.006f;  // (0.6, 0.8, 0) cm: 1 cm
  moved.select(2, 7) += 0.008f;
  const ReconstructionError e = motion_errors(real, moved);
  EXPECT_NEAR(e.position_cm, 0.5, 1e-4);
  EXPECT_NEAR(e.rotation_deg, 0.0, 1e-3);
}

TEST(Reconstruction, AHandTurnedThirtyDegreesIsFifteenOverHeadAndHand) {
  const torch::Tensor real = still_segments(2);
  const torch::Tensor axis = torch::nn::functional::normalize(
      torch::tensor({1.f, 2.f, -0.5f}), torch::nn::functional::NormalizeFuncOptions().dim(0));
  torch::Tensor turned_hand = real.clone();
  turned_hand.slice(2, 9, 12).copy_(turned(real.slice(2, 9, 12), axis, kPi / 6));
  turned_hand.slice(2, 12, 15).copy_(turned(real.slice(2, 12, 15), axis, kPi / 6));
  const ReconstructionError e = motion_errors(real, turned_hand);
  EXPECT_NEAR(e.rotation_deg, 15.0, 1e-3);
  EXPECT_NEAR(e.position_cm, 0.0, 1e-9);
}

TEST(Reconstruction, SixDIsOrthonormalisedBeforeTheAngle) {
  const torch::Tensor real = still_segments(2);
  torch::Tensor scaled = real.clone();
  scaled.slice(2, 0, 3) *= 3.0;  // a long forward vector
  scaled.select(2, 3) += 0.5f;   // up leaning along x (a real turn about forward) and along
  scaled.select(2, 5) += 0.4f;   // forward itself (no turn: orthonormalisation removes it)
  // Orthonormalised, up becomes (0.5, 1, 0)/|.|: a turn of atan(0.5) about the forward axis.
  const double expected = std::atan(0.5) * 180.0 / kPi / 2.0;  // head only; the hand is exact
  EXPECT_NEAR(motion_errors(real, scaled).rotation_deg, expected, 1e-3);
}

}  // namespace
}  // namespace deixis::train
