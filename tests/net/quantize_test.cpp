// The quantisation error bounds that docs/protocol.md states, measured over many random values,
// and the edges: range limits, non-finite input, bit patterns no encoder produces.

#include <gtest/gtest.h>

#include <random>

#include "angles.h"
#include "net/quantize.h"

namespace deixis::net {
namespace {

Mat3 random_rotation(std::mt19937& rng) {
  std::normal_distribution<float> n(0.0f, 1.0f);
  return Quat(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

TEST(Quantize, PositionErrorIsAtMostHalfAMillimetrePerAxis) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-kPositionLimit, kPositionLimit);
  float worst = 0.0f;
  for (int i = 0; i < 100000; ++i) {
    const Vec3 p(u(rng), u(rng), u(rng));
    const auto q = quantize_position(p);
    ASSERT_TRUE(q.has_value());
    worst = std::max(worst, (dequantize_position(*q) - p).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(worst, 0.0005f + 4e-6f);  // plus float rounding of metres near 32 m
  EXPECT_GT(worst, 0.0004f) << "the bound is tight, not loose";
}

TEST(Quantize, PositionOutsideTheRangeOrNotFiniteIsRefused) {
  EXPECT_FALSE(quantize_position(Vec3(32.768f, 0, 0)).has_value());
  EXPECT_FALSE(quantize_position(Vec3(0, -40.0f, 0)).has_value());
  EXPECT_FALSE(quantize_position(Vec3(0, 0, std::nanf(""))).has_value());
  EXPECT_FALSE(quantize_position(Vec3(INFINITY, 0, 0)).has_value());
  EXPECT_TRUE(quantize_position(Vec3(32.767f, -32.767f, 0)).has_value());
}

TEST(Quantize, FarDirectionIsShortenedAlongItself) {
  const Vec3 far(300.0f, -40.0f, 12.0f);
  const auto q = quantize_direction_preserving(far);
  ASSERT_TRUE(q.has_value());
  const Vec3 back = dequantize_position(*q);
  EXPECT_LT(angle_deg(back, far), 0.01);
  EXPECT_NEAR(back.cwiseAbs().maxCoeff(), kPositionLimit, 0.001f);
  EXPECT_FALSE(quantize_direction_preserving(Vec3(std::nanf(""), 0, 0)).has_value());
}

TEST(Quantize, RotationErrorIsWithinTheStatedBound) {
  std::mt19937 rng(4);
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const Mat3 R = random_rotation(rng);
    const auto packed = quantize_rotation(R);
    ASSERT_TRUE(packed.has_value());
    const auto back = dequantize_rotation(*packed);
    ASSERT_TRUE(back.has_value());
    worst = std::max(worst, angle_deg(*back, R));
  }
  EXPECT_LE(worst, kRotationErrorBoundDeg);
  EXPECT_GT(worst, 0.5 * static_cast<double>(kRotationErrorBoundDeg))
      << "the bound is tight, not loose";
  std::printf("rotation: worst error %.4f deg over 200000 random rotations\n", worst);
}

TEST(Quantize, RotationDecodesEveryBitPatternToARotationOrRefusesIt) {
  // A grid over the three 15-bit components and every index: nothing non-finite, nothing that is
  // not a rotation; patterns with |v|² > 1, and any with the reserved bit set, refused.
  int refused = 0;
  int decoded = 0;
  for (std::uint64_t index = 0; index < 4; ++index) {
    for (std::uint64_t a = 0; a < 32768; a += 1111) {
      for (std::uint64_t b = 0; b < 32768; b += 1234) {
        for (std::uint64_t c = 0; c < 32768; c += 999) {
          const std::uint64_t packed = (index << 45) | (a << 30) | (b << 15) | c;
          EXPECT_FALSE(dequantize_rotation(packed | (std::uint64_t{1} << 47)).has_value());
          const auto R = dequantize_rotation(packed);
          if (!R) {
            ++refused;
            continue;
          }
          ++decoded;
          ASSERT_TRUE(R->allFinite());
          EXPECT_LT((R->transpose() * *R - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-5f);
          EXPECT_NEAR(R->determinant(), 1.0f, 1e-5f);
        }
      }
    }
  }
  EXPECT_GT(refused, 0) << "some patterns cannot be a unit quaternion";
  EXPECT_GT(decoded, refused);
  EXPECT_FALSE(quantize_rotation(Mat3::Constant(std::nanf(""))).has_value());
  EXPECT_EQ(*quantize_rotation(Mat3::Identity()) >> 45, 3u) << "w is the largest";
  EXPECT_EQ(*dequantize_rotation(*quantize_rotation(Mat3::Identity())), Mat3::Identity())
      << "zero components are exact";
  EXPECT_FALSE(dequantize_rotation((std::uint64_t{3} << 45) | 32767u).has_value())
      << "a component of 32767 is never sent";
}

TEST(Quantize, DirectionErrorIsWithinTheStatedBound) {
  std::mt19937 rng(5);
  std::normal_distribution<float> n(0.0f, 1.0f);
  double worst = 0.0;
  for (int i = 0; i < 200000; ++i) {
    const Vec3 d = Vec3(n(rng), n(rng), n(rng)).normalized();
    const auto q = quantize_unit_vector(d);
    ASSERT_TRUE(q.has_value());
    const Vec3 back = dequantize_unit_vector(*q);
    EXPECT_NEAR(back.norm(), 1.0f, 1e-6f);
    worst = std::max(worst, angle_deg(back, d));
  }
  EXPECT_LE(worst, kDirectionErrorBoundDeg);
  std::printf("direction: worst error %.5f deg over 200000 random directions\n", worst);
  for (const Vec3& axis : {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(1, 0, 0), Vec3(0, -1, 0)}) {
    EXPECT_LT(angle_deg(dequantize_unit_vector(*quantize_unit_vector(axis)), axis), 1e-3);
  }
  EXPECT_FALSE(quantize_unit_vector(Vec3::Zero()).has_value());
  EXPECT_FALSE(quantize_unit_vector(Vec3(std::nanf(""), 0, 1)).has_value());
  // Every int16 pair decodes to a unit vector, including −32768 (no encoder writes it).
  for (const std::int16_t a : {std::int16_t{-32768}, std::int16_t{0}, std::int16_t{32767}}) {
    for (const std::int16_t b : {std::int16_t{-32768}, std::int16_t{-1}, std::int16_t{32767}}) {
      EXPECT_NEAR(dequantize_unit_vector({a, b}).norm(), 1.0f, 1e-6f);
    }
  }
}

}  // namespace
}  // namespace deixis::net
