#include "core/math/rotation_6d.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

namespace deixis {
namespace {

bool is_proper_rotation(const Mat3& R, float tolerance = 1e-5f) {
  return (R.transpose() * R).isIdentity(tolerance) && std::abs(R.determinant() - 1.0f) < tolerance;
}

TEST(Rotation6D, EncodeTakesForwardAndUpColumns) {
  // A 90° turn about +Y: columns are (0,0,−1), (0,1,0), (1,0,0).
  const Mat3 R = Eigen::AngleAxisf(1.5707963f, Vec3::UnitY()).toRotationMatrix();
  const Rotation6D r = encode_6d(R);
  EXPECT_TRUE(r.forward.isApprox(Vec3(1, 0, 0), 1e-6f));
  EXPECT_TRUE(r.up.isApprox(Vec3(0, 1, 0), 1e-6f));
}

TEST(Rotation6D, RoundTripOfRandomRotations) {
  std::mt19937 rng(11);
  std::normal_distribution<float> n(0.0f, 1.0f);
  for (int i = 0; i < 1000; ++i) {
    const Mat3 R = Quat(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
    EXPECT_TRUE(decode_6d(encode_6d(R)).isApprox(R, 1e-5f));
    EXPECT_TRUE(decode_6d_unorthogonalised(R.col(2), R.col(1)).isApprox(R, 1e-5f));
  }
}

TEST(Rotation6D, GramSchmidtKeepsForwardExact) {
  // Forward along +Z scaled, up tilted 30° toward forward: forward must stay +Z, up becomes +Y.
  const Mat3 R = decode_6d(Vec3(0, 0, 2), Vec3(0, std::cos(0.5236f), std::sin(0.5236f)));
  EXPECT_TRUE(R.col(2).isApprox(Vec3(0, 0, 1), 1e-6f));
  EXPECT_TRUE(R.col(1).isApprox(Vec3(0, 1, 0), 1e-6f));
  EXPECT_TRUE(R.col(0).isApprox(Vec3(1, 0, 0), 1e-6f));  // right = up × forward
  EXPECT_TRUE(is_proper_rotation(R));
}

TEST(Rotation6D, AuthorsRecipeIsNotOrthogonalised) {
  // The same tilted input through the authors' recipe keeps the tilted up column
  // (docs/conventions.md#6d-rotations).
  const Vec3 up(0, std::cos(0.5236f), std::sin(0.5236f));
  const Mat3 R = decode_6d_unorthogonalised(Vec3(0, 0, 2), up);
  EXPECT_TRUE(R.col(1).isApprox(up, 1e-6f));
  EXPECT_GT(std::abs(R.col(1).dot(R.col(2))), 0.4f);
}

TEST(Rotation6D, DegenerateInputStillGivesProperRotation) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const Vec3 cases[][2] = {
      {Vec3(0, 0, 0), Vec3(0, 1, 0)},         // zero forward
      {Vec3(0, 0, 1), Vec3(0, 0, 0)},         // zero up
      {Vec3(0, 0, 1), Vec3(0, 0, 5)},         // up parallel to forward
      {Vec3(0, 1, 0), Vec3(0, 1, 0)},         // forward vertical and up parallel
      {Vec3(nan, 0, 1), Vec3(0, 1, 0)},       // NaN
      {Vec3(0, 0, 1), Vec3(inf, 1, 0)},       // Inf
      {Vec3(1e-9f, 0, 0), Vec3(0, 1e-9f, 0)}  // vanishingly small
  };
  for (const auto& c : cases) {
    const Mat3 R = decode_6d(c[0], c[1]);
    EXPECT_TRUE(R.allFinite());
    EXPECT_TRUE(is_proper_rotation(R)) << c[0].transpose() << " / " << c[1].transpose();
  }
  // A zero forward falls back to +Z, keeping the given up.
  EXPECT_TRUE(decode_6d(Vec3::Zero(), Vec3::UnitY()).isIdentity(1e-6f));
}

TEST(Rotation6D, NoisyNetworkOutputsDecodeToProperRotations) {
  std::mt19937 rng(3);
  std::normal_distribution<float> n(0.0f, 1.0f);
  for (int i = 0; i < 1000; ++i) {
    EXPECT_TRUE(
        is_proper_rotation(decode_6d(Vec3(n(rng), n(rng), n(rng)), Vec3(n(rng), n(rng), n(rng)))));
  }
}

}  // namespace
}  // namespace deixis
