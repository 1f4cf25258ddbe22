// Monotone cubic (PCHIP) interpolation, checked against hand-computed values (the capture's speed
// augmentation built on it: tests/capture/speed_test.cpp).

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "dataset/pchip.h"

namespace deixis::dataset {
namespace {

std::vector<double> iota(std::size_t n) {
  std::vector<double> x(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = static_cast<double>(i);
  }
  return x;
}

TEST(Pchip, HandComputedValuesOfASquare) {
  // y = x² at 0..3: secants 1, 3, 5; interior slopes by the harmonic mean 6/(3/1 + 3/3) = 1.5 and
  // 6/(3/3 + 3/5) = 3.75; end slopes by the three-point formula, (3·1 − 3)/2 = 0 and
  // (3·5 − 3)/2 = 6. Hermite midpoints: 0.5·y0 + h/8·d0 + 0.5·y1 − h/8·d1.
  const std::vector<double> x = iota(4);
  const std::vector<double> y = {0, 1, 4, 9};
  const Pchip f(x, y);
  EXPECT_NEAR(f(0.5), 0.5 - 0.125 * 1.5, 1e-12);
  EXPECT_NEAR(f(1.5), 0.5 + 0.125 * 1.5 + 2.0 - 0.125 * 3.75, 1e-12);
  EXPECT_NEAR(f(2.5), 2.0 + 0.125 * 3.75 + 4.5 - 0.125 * 6.0, 1e-12);
  for (std::size_t k = 0; k < 4; ++k) {
    EXPECT_DOUBLE_EQ(f(x[k]), y[k]);  // through the knots
  }
}

TEST(Pchip, StepsDoNotOvershoot) {
  // 0, 0, 1, 1: every slope is 0 (flat neighbours), so the rise is the smoothstep 3t² − 2t³.
  const std::vector<double> x = iota(4);
  const Pchip f(x, std::vector<double>{0, 0, 1, 1});
  EXPECT_NEAR(f(1.25), 3 * 0.0625 - 2 * 0.015625, 1e-12);
  EXPECT_NEAR(f(1.5), 0.5, 1e-12);
  double last = 0;
  for (double t = 0; t <= 3; t += 0.01) {
    const double v = f(t);
    EXPECT_GE(v, 0.0);
    EXPECT_LE(v, 1.0);
    EXPECT_GE(v, last - 1e-12);  // monotone data, monotone curve
    last = v;
  }
}

TEST(Pchip, LinearDataStaysLinearAndEndsAreKept) {
  const std::vector<double> y = {2, 3, 4, 5, 6};
  const std::vector<double> out = pchip_resample(y, 9);
  ASSERT_EQ(out.size(), 9u);
  for (std::size_t j = 0; j < out.size(); ++j) {
    EXPECT_NEAR(out[j], 2.0 + 0.5 * static_cast<double>(j), 1e-12);
  }
}

TEST(Pchip, RejectsBadKnots) {
  EXPECT_THROW(Pchip(std::vector<double>{0, 1, 1}, std::vector<double>{0, 1, 2}), Error);
  EXPECT_THROW(Pchip(std::vector<double>{}, std::vector<double>{}), Error);
  EXPECT_THROW(Pchip(std::vector<double>{0, 1}, std::vector<double>{0}), Error);
}

}  // namespace
}  // namespace deixis::dataset
