// The lane-wise expm1 (gesture/nn/lanewise_math.h) and the ELU made of it
// (gesture/nn/activations.h): accurate against the double-precision C library, saturating
// sensibly outside its range, NaN kept, and, what they exist for, a value's result the same
// bits whatever its neighbours and wherever it sits in the library's vectorised loop, 8 or 16
// floats wide (against the same function called one value at a time).

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <vector>

#include "gesture/nn/activations.h"
#include "gesture/nn/lanewise_math.h"

namespace deixis::nn {
namespace {

using Function = float (*)(float);

// Evenly spaced points of [lo, hi] plus a logarithmic sweep of small magnitudes of both signs,
// where expm1 switches between its series and e^x.
std::vector<float> sweep(float lo, float hi) {
  std::vector<float> xs;
  constexpr int kSteps = 400'000;
  for (int i = 0; i <= kSteps; ++i) {
    xs.push_back(lo + (hi - lo) * static_cast<float>(i) / kSteps);
  }
  for (float m = 1e-30f; m < 2.0f; m *= 1.001f) {
    xs.push_back(m);
    xs.push_back(-m);
  }
  return xs;
}

TEST(LanewiseMath, AccurateAgainstDoublePrecision) {
  double worst = 0.0;  // |expm1 − exact| / |exact|
  float worst_x = 0.0f;
  for (const float x : sweep(-87.0f, 88.0f)) {
    const double exact = std::expm1(static_cast<double>(x));
    if (exact == 0.0) {
      continue;  // x = ±0, given back as it is (below)
    }
    const double relative =
        std::fabs(static_cast<double>(lanewise::expm1(x)) - exact) / std::fabs(exact);
    if (relative > worst) {
      worst = relative;
      worst_x = x;
    }
  }
  EXPECT_LE(worst, 2e-7) << "expm1 at x = " << worst_x;
  std::ostringstream figure;
  figure << worst << " at " << worst_x;
  RecordProperty("expm1", figure.str());
}

TEST(LanewiseMath, SaturatesOutsideAndKeepsNaN) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(lanewise::expm1(-kInf), -1.0f);
  EXPECT_EQ(lanewise::expm1(-200.0f), -1.0f);
  EXPECT_GT(lanewise::expm1(kInf), 1e38f);  // e^88 − 1, the clamp: finite
  EXPECT_TRUE(std::isfinite(lanewise::expm1(kInf)));
  EXPECT_EQ(std::bit_cast<std::uint32_t>(lanewise::expm1(0.0f)), 0u);
  EXPECT_EQ(std::bit_cast<std::uint32_t>(lanewise::expm1(-0.0f)),
            std::bit_cast<std::uint32_t>(-0.0f));  // as std::expm1 and torch's ELU
  EXPECT_EQ(std::bit_cast<std::uint32_t>(elu(-0.0f)), std::bit_cast<std::uint32_t>(-0.0f));
  EXPECT_EQ(lanewise::expm1(200.0f), lanewise::expm1(88.0f));  // the clamp
  EXPECT_TRUE(std::isnan(lanewise::expm1(nan)));
}

// Called through a volatile pointer, so the compiler cannot inline it into a vector loop: scalar
// code, one value at a time.
float one_at_a_time(Function f, float x) {
  volatile Function call = f;
  return call(x);
}

TEST(LanewiseMath, AValueGetsTheSameBitsWhateverItsNeighbours) {
  std::mt19937 rng(88);
  std::uniform_real_distribution<float> wide(-100.0f, 20.0f);
  std::uniform_real_distribution<float> narrow(-0.5f, 0.5f);
  // 1,001 values (a vectorised loop's remainder too), a third of them near 0 where expm1 switches
  // formulas, some below −87 where exp clamps.
  std::vector<float> values(1001);
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = i % 3 == 0 ? narrow(rng) : wide(rng);
  }
  // The library's loop (vector code, built with its own flags in another translation unit; with
  // 16-float vectors too where the CPU has AVX-512)...
  for (const ProductKernel kernel : {ProductKernel::kBuild, ProductKernel::kAvx512}) {
    if (!product_kernel_available(kernel)) {
      continue;
    }
    SCOPED_TRACE(kernel == ProductKernel::kBuild ? "the build's vectors" : "AVX-512");
    std::vector<float> vectorised = values;
    elu_inplace(kernel, vectorised.data(), vectorised.size());
    // ... on the same values shifted by one place (each in another lane), with other
    // neighbours...
    std::vector<float> shifted(values.size() + 1, -15.0f);
    std::copy(values.begin(), values.end(), shifted.begin() + 1);
    elu_inplace(kernel, shifted.data(), shifted.size());
    // ... and one value at a time, here.
    for (std::size_t i = 0; i < values.size(); ++i) {
      const float alone = one_at_a_time(elu, values[i]);
      ASSERT_EQ(std::bit_cast<std::uint32_t>(vectorised[i]), std::bit_cast<std::uint32_t>(alone))
          << "elu(" << values[i] << ") at " << i;
      ASSERT_EQ(std::bit_cast<std::uint32_t>(shifted[i + 1]), std::bit_cast<std::uint32_t>(alone))
          << "elu(" << values[i] << ") shifted from " << i;
    }
  }
}

TEST(LanewiseMath, EluIsTheIdentityAboveZeroAndExpm1Below) {
  std::vector<float> x = {-3.0f, -0.2f, 0.0f, 1e-8f, 0.5f, 7.0f};
  const std::vector<float> before = x;
  elu_inplace(x.data(), x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const float expected = before[i] > 0.0f ? before[i] : lanewise::expm1(before[i]);
    EXPECT_EQ(x[i], expected) << before[i];
  }
  EXPECT_NEAR(x[0], std::expm1(-3.0), 1e-7);
  // A strided block takes the element-by-element path and gives the same values.
  Eigen::Matrix<float, 4, 3> m;
  m << -1, 2, -3, 4, -5, 6, -0.1f, 0.2f, -0.3f, 9, -9, 0;
  Eigen::Matrix<float, 4, 3> contiguous = m;
  elu_inplace(contiguous);
  auto block = m.block<3, 2>(1, 1);
  elu_inplace(block);
  const bool same = m.block<3, 2>(1, 1) == contiguous.block<3, 2>(1, 1);
  EXPECT_TRUE(same) << m << "\n\n" << contiguous;
}

}  // namespace
}  // namespace deixis::nn
