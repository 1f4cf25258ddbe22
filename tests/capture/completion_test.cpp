// Completion states (paper §III.A): pointing ends with the dominant eye → fingertip ray through
// the target; touching ends with the fingertip on the target's surface. Checked at every frame
// of every completion state in sequences of all categories and three subjects.

#include <gtest/gtest.h>

#include <cmath>

#include "capture/completion.h"
#include "gesture/features.h"
#include "sequences.h"

namespace deixis::capture {
namespace {

using testing::sample_sequences;
using testing::target_of;

constexpr float kDegree = 0.017453292f;

float angle(const Vec3& a, const Vec3& b) {
  return unsigned_angle(a, b);  // atan2: exact near 0, unlike acos
}

// A pointing completion state: the deictic progression is complete while eyes and head are on
// the same target as the hand.
bool pointing_complete(const Sequence& s, std::size_t i) {
  return !is_touching(s.category) && s.labels[i][1] >= 1.0f && s.labels[i][0] >= 1.0f &&
         s.frames[i].head_target == s.frames[i].hand_target;
}

TEST(Completion, DominantEyeRayThroughFingertipHitsThePointingTarget) {
  int checked = 0;
  for (const Sequence& s : sample_sequences()) {
    const int hand = index(s.calibration.deictic_hand);
    const int eye = static_cast<int>(s.dominant_eye);
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (!pointing_complete(s, i)) {
        continue;
      }
      const Vec3 e = s.joints[i].eye[eye];
      const Vec3 target = target_of(s, s.frames[i].hand_target).position;
      const float error = angle(s.frames[i].index_tip[hand] - e, target - e);
      ASSERT_LT(error, 1.0f * kDegree)
          << s.subject << " " << category_name(s.category) << " seed " << s.seed << " frame " << i;
      ++checked;
    }
  }
  EXPECT_GT(checked, 150 * testing::kPerCategory);
}

TEST(Completion, EyeDominanceChangesThePointingPose) {
  // The same script with the other eye dominant: the non-dominant eye's ray misses targets
  // beyond arm's reach by degrees, so the pose must differ.
  Subject left_eyed = find_subject("170");
  left_eyed.name = "170-left-eye";
  left_eyed.dominant_eye = Eye::kLeft;
  int far_targets = 0;
  for (int i = 0; i < 6; ++i) {
    const std::uint64_t seed = sequence_seed(3, "test", "x", Category::kPointingSingle, i);
    const Sequence right = perform(find_subject("170"), Category::kPointingSingle, seed);
    const Sequence left = perform(left_eyed, Category::kPointingSingle, seed);
    ASSERT_EQ(right.size(), left.size());
    for (std::size_t k = 0; k < right.size(); ++k) {
      if (!pointing_complete(right, k)) {
        continue;
      }
      const Vec3 target = target_of(right, right.frames[k].hand_target).position;
      const Vec3 e_left = right.joints[k].eye[static_cast<int>(Eye::kLeft)];
      if ((target - e_left).norm() < 1.5f) {
        continue;
      }
      const Vec3 tip = right.frames[k].index_tip[index(Hand::kRight)];
      EXPECT_GT(angle(tip - e_left, target - e_left), 2.0f * kDegree);
      EXPECT_GT((tip - left.frames[k].index_tip[index(Hand::kRight)]).norm(), 0.01f);
      ++far_targets;
      break;
    }
  }
  EXPECT_GE(far_targets, 3);
}

TEST(Completion, FingertipIsOnTheSurfaceOfTheTouchedTarget) {
  int checked = 0;
  for (const Sequence& s : sample_sequences()) {
    if (!is_touching(s.category)) {
      continue;
    }
    const int hand = index(s.calibration.deictic_hand);
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (s.labels[i][1] < 1.0f) {
        continue;
      }
      const TargetObject& target = target_of(s, s.frames[i].hand_target);
      const Vec3 tip = s.frames[i].index_tip[hand];
      const float gap = (tip - closest_surface_point(target, tip)).norm();
      ASSERT_LT(gap, 0.01f) << s.subject << " " << category_name(s.category) << " seed " << s.seed
                            << " frame " << i;
      ++checked;
    }
  }
  EXPECT_GT(checked, 150 * testing::kPerCategory);
}

TEST(Completion, PointingPoseKeepsTheWristWithinReach) {
  // Targets all around and at all distances: the solver always returns a reachable wrist on the
  // dominant eye's ray.
  for (const char* name : {"170", "161", "174"}) {
    const Body body = make_body(find_subject(name));
    const Pose torso{Mat3::Identity(), body.hip_in_stance};
    const Vec3 eye_pos = eye_position(body, torso, Mat3::Identity(), body.subject.dominant_eye);
    for (float azimuth = -1.3f; azimuth <= 1.3f; azimuth += 0.2f) {
      for (float elevation = -0.5f; elevation <= 0.6f; elevation += 0.2f) {
        for (const float distance : {0.3f, 0.6f, 1.0f, 2.0f, 5.0f}) {
          const Vec3 direction(-std::sin(azimuth) * std::cos(elevation), std::sin(elevation),
                               -std::cos(azimuth) * std::cos(elevation));
          const Vec3 target = eye_pos + distance * direction;
          const Hand hand = body.subject.handedness;
          const CompletionPose p = pointing_pose(body, hand, torso, Mat3::Identity(), target);
          const Vec3 shoulder = shoulder_position(body, torso, hand);
          EXPECT_LE((p.wrist.translation - shoulder).norm(), comfortable_reach(body) + 1e-4f);
          EXPECT_LT(angle(p.tip - eye_pos, target - eye_pos), 0.01f * kDegree);
          EXPECT_LT((fingertip(body, hand, p.wrist) - p.tip).norm(), 1e-5f);
          EXPECT_LT(p.ray_distance, distance);  // stops short of near targets
        }
      }
    }
  }
}

}  // namespace
}  // namespace deixis::capture
