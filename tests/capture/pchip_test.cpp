// Monotone cubic (PCHIP) interpolation, checked against hand-computed values, and the ×0.5 / ×2
// speed augmentation built on it.

#include <gtest/gtest.h>

#include <cmath>

#include "capture/pchip.h"
#include "capture/speed.h"
#include "core/error.h"
#include "sequences.h"

namespace deixis::capture {
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

TEST(SpeedAugmentation, HalvesOrDoublesTheFramesAndKeepsLabelsAndHandsHonest) {
  const Sequence& s = testing::sample_sequences().front();
  const Body body = make_body(find_subject(s.subject));
  for (const float speed : {0.5f, 2.0f}) {
    const Sequence r = resample_speed(s, speed);
    EXPECT_EQ(r.size(), static_cast<std::size_t>(std::floor(static_cast<double>(s.size()) /
                                                            static_cast<double>(speed))));
    EXPECT_FLOAT_EQ(r.speed, speed);
    EXPECT_TRUE(r.joints.empty());
    EXPECT_EQ(r.labels.front(), s.labels.front());
    EXPECT_EQ(r.labels.back(), s.labels.back());
    EXPECT_NEAR(r.frames.back().time, static_cast<double>(r.size() - 1) / kFrameRate, 1e-9);
    for (std::size_t i = 0; i < r.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        ASSERT_GE(r.labels[i][k], 0.0f);
        ASSERT_LE(r.labels[i][k], 1.0f);
      }
      for (int h = 0; h < 2; ++h) {
        // Rigid hand: the fingertip keeps its distance from the wrist.
        ASSERT_NEAR((r.frames[i].index_tip[h] - r.frames[i].T_world_wrist[h].translation).norm(),
                    body.tip_in_wrist[h].norm(), 1e-4f);
        ASSERT_NEAR(r.frames[i].T_world_wrist[h].rotation.determinant(), 1.0f, 1e-4f);
      }
      ASSERT_NEAR(r.frames[i].gaze.norm(), 1.0f, 1e-5f);
    }
    // The same motion: twice as fast reaches the completion state in about half the time.
    auto first_complete = [](const Sequence& q) {
      for (std::size_t i = 0; i < q.size(); ++i) {
        if (q.labels[i][1] >= 0.999f) {
          return q.frames[i].time;
        }
      }
      return -1.0;
    };
    const double factor = static_cast<double>(speed);
    EXPECT_NEAR(first_complete(r), first_complete(s) / factor, 2.0 / (factor * kFrameRate));
  }
  EXPECT_THROW(resample_speed(s, 0.0f), Error);
  EXPECT_THROW(resample_speed(s, -1.0f), Error);
}

}  // namespace
}  // namespace deixis::capture
