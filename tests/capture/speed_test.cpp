// The ×0.5 / ×2 speed augmentation (capture/speed.h), built on PCHIP (dataset/pchip.h): labels stay
// in [0, 1], hands stay rigid, the motion keeps its shape in time.

#include <gtest/gtest.h>

#include <cmath>

#include "capture/body.h"
#include "capture/speed.h"
#include "core/error.h"
#include "sequences.h"

namespace deixis::capture {
namespace {

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
