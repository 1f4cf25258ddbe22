// The AdamW step on flat buffers: torch's formula (checked against a double-precision restatement
// of torch.optim.AdamW 1.13), gradients cleared, and denormal moments flushed to exactly zero
// without leaking the flush mode to the caller.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/error.h"
#include "train/adamw.h"
#include "train/network_kind.h"
#include "train/schedule.h"

namespace deixis::train {
namespace {

struct Buffers {
  std::vector<float> p, g, m, v;
  explicit Buffers(std::size_t n) : p(n), g(n), m(n), v(n) {}
  AdamWBuffers spans() { return {p, g, m, v}; }
};

Schedule adamw_schedule() {
  Schedule s = default_schedule(Family::kUgnet);
  s.weight_decay = 0.01;
  return s;
}

TEST(AdamW, MatchesTorchsFormula) {
  const Schedule s = adamw_schedule();
  const std::size_t n = 3000;  // more than two blocks, and a partial one
  Buffers b(n);
  std::mt19937 rng(7);
  std::normal_distribution<float> normal(0.0f, 1.0f);
  for (std::size_t i = 0; i < n; ++i) {
    b.p[i] = normal(rng);
    b.g[i] = 0.1f * normal(rng);
    b.m[i] = 0.01f * normal(rng);
    b.v[i] = 1e-4f * std::abs(normal(rng));
  }
  const Buffers before = b;
  const double lr = 3e-4;
  const std::int64_t step = 5;
  adamw_step(b.spans(), s, lr, step);
  for (std::size_t i = 0; i < n; ++i) {
    // torch/optim/adamw.py, _single_tensor_adamw.
    const double p0 = before.p[i], g = before.g[i], m0 = before.m[i], v0 = before.v[i];
    const double p = p0 * (1.0 - lr * s.weight_decay);
    const double m = s.beta1 * m0 + (1.0 - s.beta1) * g;
    const double v = s.beta2 * v0 + (1.0 - s.beta2) * g * g;
    const double correction1 = 1.0 - std::pow(s.beta1, static_cast<double>(step));
    const double correction2 = 1.0 - std::pow(s.beta2, static_cast<double>(step));
    const double denominator = std::sqrt(v) / std::sqrt(correction2) + s.epsilon;
    const double expected = p - lr / correction1 * m / denominator;
    // Float arithmetic: within a few ulps of the terms (which may cancel), not of the result.
    const double m_terms = s.beta1 * std::abs(m0) + (1.0 - s.beta1) * std::abs(g);
    const double update = lr / correction1 * std::abs(m) / denominator;
    ASSERT_NEAR(b.m[i], m, 1e-6 * m_terms) << i;
    ASSERT_NEAR(b.v[i], v, 1e-6 * v) << i;
    ASSERT_NEAR(b.p[i], expected, 1e-6 * (std::abs(p) + update)) << i;
    ASSERT_EQ(b.g[i], 0.0f) << i;
  }
}

// A parameter without gradient: its moments decay by beta1 and beta2 each step. Once they are
// denormal (slow on the CPU) the step makes them exactly zero, and the parameter moves only by
// its weight decay.
TEST(AdamW, DenormalMomentsOfAParameterWithoutGradientBecomeZero) {
  const Schedule s = adamw_schedule();
  const float denormal = std::numeric_limits<float>::denorm_min() * 1000.0f;
  ASSERT_EQ(std::fpclassify(denormal), FP_SUBNORMAL);
  Buffers b(100);
  for (std::size_t i = 0; i < 100; ++i) {
    b.p[i] = 0.5f;
    b.m[i] = denormal;
    b.v[i] = denormal;
  }
  const double lr = 1e-3;
  adamw_step(b.spans(), s, lr, 1000);
  for (std::size_t i = 0; i < 100; ++i) {
    EXPECT_EQ(b.m[i], 0.0f) << i;
    EXPECT_EQ(b.v[i], 0.0f) << i;
    EXPECT_FLOAT_EQ(b.p[i], static_cast<float>(0.5 * (1.0 - lr * s.weight_decay))) << i;
  }
  // The caller's mode is back: arithmetic here still produces denormals.
  volatile float tiny = std::numeric_limits<float>::min();
  volatile float half = tiny * 0.5f;
  EXPECT_EQ(std::fpclassify(half), FP_SUBNORMAL);
}

TEST(AdamW, MismatchedBuffersAreAnError) {
  Buffers b(10);
  b.m.resize(9);
  EXPECT_THROW(adamw_step(b.spans(), adamw_schedule(), 1e-3, 1), Error);
  Buffers c(10);
  EXPECT_THROW(adamw_step(c.spans(), adamw_schedule(), 1e-3, 0), Error);
}

}  // namespace
}  // namespace deixis::train
