// How the motion model moves: rigid bones, eyes within their range, bell-shaped reaches with
// human peak speeds, and eye–head coordination (eyes lead; the head's share grows with the
// amplitude).

#include <gtest/gtest.h>

#include <cmath>

#include "capture/actor.h"
#include "capture/body.h"
#include "gesture/features.h"
#include "sequences.h"

namespace deixis::capture {
namespace {

using testing::sample_sequences;

float angle(const Vec3& a, const Vec3& b) {
  return unsigned_angle(a, b);  // atan2: exact near 0, unlike acos
}

TEST(Motion, BoneLengthsNeverChange) {
  for (const Sequence& s : sample_sequences()) {
    const Body body = make_body(find_subject(s.subject));
    const Joints& first = s.joints.front();
    const float spine = (first.neck - first.hip).norm();
    const float shoulders = (first.shoulder[0] - first.shoulder[1]).norm();
    for (std::size_t i = 0; i < s.size(); ++i) {
      const Joints& j = s.joints[i];
      ASSERT_NEAR((j.neck - j.hip).norm(), spine, 1e-4f) << s.subject << " frame " << i;
      ASSERT_NEAR((j.shoulder[0] - j.shoulder[1]).norm(), shoulders, 1e-4f);
      ASSERT_NEAR((j.head - j.neck).norm(), body.eyes_in_head.norm(), 1e-4f);
      ASSERT_NEAR((j.eye[0] - j.eye[1]).norm(), body.eye_separation, 1e-4f);
      for (int h = 0; h < 2; ++h) {
        ASSERT_NEAR((j.elbow[h] - j.shoulder[h]).norm(), body.upper_arm, 1e-4f)
            << s.subject << " " << category_name(s.category) << " seed " << s.seed << " frame " << i
            << " hand " << h;
        ASSERT_NEAR((j.wrist[h] - j.elbow[h]).norm(), body.forearm, 1e-4f)
            << s.subject << " " << category_name(s.category) << " seed " << s.seed << " frame " << i
            << " hand " << h;
        ASSERT_NEAR((j.tip[h] - j.wrist[h]).norm(), body.tip_in_wrist[h].norm(), 1e-4f);
      }
    }
  }
}

TEST(Motion, EyesStayWithinTheirRangeOfMotion) {
  for (const Sequence& s : sample_sequences()) {
    for (const TrackingFrame& f : s.frames) {
      const Vec3 ahead = f.T_world_head.rotation * Vec3(0, 0, -1);
      ASSERT_LE(angle(f.gaze, ahead), kEyeRange + 1e-3f) << s.subject << " t " << f.time;
    }
  }
}

// Every reach toward a completion state: the deictic label's rise, from the hand's onset to the
// completion state, is exactly the movement. Short corrections (under 20 cm, e.g. from the
// gesture space to a nearby touch target) are not reaches and move slower.
struct ReachWindow {
  std::size_t onset;
  std::size_t complete;
};
std::vector<ReachWindow> reaches(const Sequence& s) {
  std::vector<ReachWindow> out;
  for (std::size_t i = 1; i < s.size(); ++i) {
    if (s.labels[i][1] > 0.0f && s.labels[i - 1][1] == 0.0f) {
      std::size_t k = i;
      while (k < s.size() && s.labels[k][1] < 1.0f) {
        ++k;
      }
      if (k < s.size()) {
        out.push_back({i - 1, k});
      }
    }
  }
  return out;
}

TEST(Motion, ReachesHaveBellShapedSpeedWithHumanPeaks) {
  int checked = 0;
  for (const Sequence& s : sample_sequences()) {
    const int hand = index(s.calibration.deictic_hand);
    for (const ReachWindow& r : reaches(s)) {
      std::vector<float> speed;
      for (std::size_t i = r.onset + 1; i <= r.complete; ++i) {
        speed.push_back(static_cast<float>(kFrameRate) *
                        (s.frames[i].T_world_wrist[hand].translation -
                         s.frames[i - 1].T_world_wrist[hand].translation)
                            .norm());
      }
      ASSERT_GE(speed.size(), 6u);
      const float distance = (s.frames[r.complete].T_world_wrist[hand].translation -
                              s.frames[r.onset].T_world_wrist[hand].translation)
                                 .norm();
      if (distance < 0.2f) {
        continue;
      }
      const auto peak = std::max_element(speed.begin(), speed.end());
      EXPECT_GE(*peak, 0.5f) << s.subject << " " << category_name(s.category) << " seed " << s.seed;
      EXPECT_LE(*peak, 2.5f) << s.subject << " " << category_name(s.category) << " seed " << s.seed;
      // One hump: rising to the peak, falling after it (standing sway allows 3 cm/s).
      constexpr float kSlack = 0.03f;
      for (auto it = speed.begin() + 1; it <= peak; ++it) {
        ASSERT_GE(*it, *(it - 1) - kSlack) << s.subject << " seed " << s.seed;
      }
      for (auto it = peak + 1; it != speed.end(); ++it) {
        ASSERT_LE(*it, *(it - 1) + kSlack) << s.subject << " seed " << s.seed;
      }
      // Near rest at both ends, as a minimum-jerk movement is.
      EXPECT_LT(speed.front(), 0.25f * *peak);
      EXPECT_LT(speed.back(), 0.25f * *peak);
      ++checked;
    }
  }
  EXPECT_GT(checked, 20 * testing::kPerCategory);
}

TEST(Motion, LongerReachesTakeLonger) {
  // Fitts-like: pooled over reaches, duration grows with distance.
  std::vector<std::pair<float, double>> samples;
  for (const Sequence& s : sample_sequences()) {
    if (s.subject != "170") {
      continue;
    }
    const int hand = index(s.calibration.deictic_hand);
    for (const ReachWindow& r : reaches(s)) {
      const float distance = (s.frames[r.complete].T_world_wrist[hand].translation -
                              s.frames[r.onset].T_world_wrist[hand].translation)
                                 .norm();
      samples.emplace_back(distance, s.frames[r.complete].time - s.frames[r.onset].time);
    }
  }
  std::sort(samples.begin(), samples.end());
  const std::size_t third = samples.size() / 3;
  ASSERT_GE(third, 4u);
  double short_mean = 0;
  double long_mean = 0;
  for (std::size_t i = 0; i < third; ++i) {
    short_mean += samples[i].second / static_cast<double>(third);
    long_mean += samples[samples.size() - 1 - i].second / static_cast<double>(third);
  }
  EXPECT_GT(long_mean, short_mean + 0.05);
}

// A person standing at the origin looks at points at growing angles to the side.
struct GazeProbe {
  Body body = make_body(find_subject("170"));
  Random rng{5};
  Motion motion{body, Pose{}, rng};
  Labelling labels;
  Actor actor{motion, labels, rng};

  Vec3 head_forward(double t) const { return motion.posture_at(t).R_world_head * Vec3(0, 0, -1); }
};

TEST(Motion, EyesLeadAndTheHeadTakesAGrowingShare) {
  float last_share = -1.0f;
  for (const float degrees : {8.0f, 25.0f, 45.0f, 70.0f, 95.0f}) {
    GazeProbe p;
    const float a = degrees * 0.017453292f;
    const Vec3 point(-3.0f * std::sin(a), p.body.eye_height(), -3.0f * std::cos(a));
    const TargetObject target{1, "probe", TargetKind::kSphere, point, Vec3::Constant(0.1f)};
    const GazeShift shift = p.actor.look_at(1.0, target);
    const Vec3 start = p.head_forward(0.99);
    const Vec3 end = p.head_forward(shift.settled + 0.01);
    const Posture settled = p.motion.posture_at(shift.settled + 0.01);
    const Vec3 to_target =
        point - head_position(p.body, settled.T_world_torso, settled.R_world_head);
    // Gaze lands on the target, the eyes within a comfortable range of centre.
    EXPECT_LT(angle(settled.gaze, to_target), 0.01f) << degrees;
    EXPECT_LT(angle(settled.gaze, end), 0.47f) << degrees;
    const float share = angle(start, end) / a;
    EXPECT_GE(share, last_share - 0.02f) << degrees;
    last_share = share;
    if (degrees < 10.0f) {
      EXPECT_LT(share, 0.1f);  // small shifts: eyes only
    }
    if (degrees > 60.0f) {
      EXPECT_GT(share, 0.6f);
      // The eyes lead: shortly after onset gaze has turned further than the head.
      const Posture early = p.motion.posture_at(1.0 + 0.08);
      const Vec3 head_early = early.R_world_head * Vec3(0, 0, -1);
      EXPECT_GT(angle(start, early.gaze), angle(start, head_early) + 0.1f);
    }
  }
}

}  // namespace
}  // namespace deixis::capture
