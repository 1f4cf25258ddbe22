// The progression labels (paper §III.B): in [0, 1], monotone within each ramp, the default state
// (0, 0, 1) before the first movement, and idle = 1 only after 0.5 s back in the upright posture.

#include <gtest/gtest.h>

#include <cmath>

#include "capture/labelling.h"
#include "sequences.h"

namespace deixis::capture {
namespace {

using testing::sample_sequences;

TEST(Labels, LieInZeroToOne) {
  for (const Sequence& s : sample_sequences()) {
    for (std::size_t i = 0; i < s.size(); ++i) {
      for (int k = 0; k < 3; ++k) {
        ASSERT_GE(s.labels[i][k], 0.0f) << s.subject << " frame " << i;
        ASSERT_LE(s.labels[i][k], 1.0f) << s.subject << " frame " << i;
      }
    }
  }
}

TEST(Labels, AreMonotoneWithinEachRamp) {
  // A ramp is a run of frames strictly between 0 and 1 (plus its end points); along it the label
  // never turns back.
  for (const Sequence& s : sample_sequences()) {
    for (int k = 0; k < 3; ++k) {
      std::size_t i = 1;
      while (i < s.size()) {
        if (s.labels[i][k] <= 0.0f || s.labels[i][k] >= 1.0f) {
          ++i;
          continue;
        }
        const std::size_t start = i - 1;
        while (i < s.size() && s.labels[i][k] > 0.0f && s.labels[i][k] < 1.0f) {
          ++i;
        }
        const std::size_t end = std::min(i, s.size() - 1);
        const float direction = s.labels[end][k] - s.labels[start][k];
        for (std::size_t j = start + 1; j <= end; ++j) {
          const float step = s.labels[j][k] - s.labels[j - 1][k];
          ASSERT_GE(step * direction, -1e-6f) << s.subject << " " << category_name(s.category)
                                              << " channel " << k << " frame " << j;
        }
      }
    }
  }
}

TEST(Labels, StartInTheDefaultStateAndReachTheCompletionState) {
  for (const Sequence& s : sample_sequences()) {
    EXPECT_EQ(s.labels.front(), (Labels{0, 0, 1})) << s.subject;
    EXPECT_EQ(s.labels.back(), (Labels{0, 0, 1})) << s.subject;
    bool completed = false;
    for (const Labels& l : s.labels) {
      completed = completed || (l[1] == 1.0f && l[2] == 0.0f);
    }
    EXPECT_TRUE(completed) << s.subject << " " << category_name(s.category);
  }
}

// Upright: both wrists at their rest positions (within standing sway) and the head level and
// facing ahead.
bool upright(const Sequence& s, std::size_t i) {
  const Pose T_root_world = inverse(s.calibration.T_world_root);
  for (int h = 0; h < 2; ++h) {
    const Vec3 wrist = transform_point(T_root_world, s.frames[i].T_world_wrist[h].translation);
    if ((wrist - s.calibration.rest_wrist_in_root[h]).norm() > 0.03f) {
      return false;
    }
  }
  const Vec3 ahead = T_root_world.rotation * s.frames[i].T_world_head.rotation * Vec3(0, 0, -1);
  return ahead.dot(Vec3(0, 0, -1)) > std::cos(0.06f);
}

TEST(Labels, IdleIsOneOnlyAfterHalfASecondUpright) {
  const auto window = static_cast<std::size_t>(kIdleDelay * kFrameRate);
  int checked = 0;
  for (const Sequence& s : sample_sequences()) {
    bool moved = false;
    for (std::size_t i = 0; i < s.size(); ++i) {
      moved = moved || s.labels[i][2] < 1.0f;
      if (!moved || s.labels[i][2] < 1.0f) {
        ASSERT_TRUE(!moved || s.labels[i][2] < 1.0f || upright(s, i));
        continue;
      }
      ASSERT_GE(i, window);
      for (std::size_t j = i - window; j <= i; ++j) {
        ASSERT_TRUE(upright(s, j))
            << s.subject << " " << category_name(s.category) << " seed " << s.seed
            << ": idle = 1 at frame " << i << " but not upright at frame " << j;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 150 * testing::kPerCategory);
}

TEST(Labels, IdleFallsWhenThePersonLeavesTheUprightPosture) {
  for (const Sequence& s : sample_sequences()) {
    for (std::size_t i = 1; i < s.size(); ++i) {
      if (s.labels[i - 1][2] == 1.0f && s.labels[i][2] < 1.0f) {
        // Leaving starts here: the person was upright until now.
        EXPECT_TRUE(upright(s, i - 1)) << s.subject << " frame " << i;
      }
    }
  }
}

}  // namespace
}  // namespace deixis::capture
