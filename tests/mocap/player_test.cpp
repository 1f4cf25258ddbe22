// Playing a recording (mocap/player.h): the recorded frames at their times, interpolation
// between them, once (held at the ends) and looping (the last frame followed by the first).

#include "mocap/player.h"

#include <gtest/gtest.h>

#include "mocap/humanoid.h"

namespace deixis::mocap {
namespace {

TEST(BvhPlayer, FramesAtTheirTimesAndInterpolatedBetween) {
  const Bvh b = parse_bvh(testing::humanoid_bvh(testing::random_motion(4, 9, 20)), "p.bvh");
  BvhPlayer player(b, 0.01, Playback::kOnce);
  SkeletonTracking tracking(b, 0.01);
  std::array<TrackingFrame, 4> recorded;
  for (std::size_t i = 0; i < 4; ++i) {
    tracking.track(i, recorded[i]);
  }
  TrackingFrame f;
  for (std::size_t i = 0; i < 4; ++i) {
    player.at(static_cast<double>(i) * b.frame_time, f);
    EXPECT_LT((f.T_world_head.translation - recorded[i].T_world_head.translation).norm(), 1e-5f);
    EXPECT_LT((f.T_world_wrist[1].rotation - recorded[i].T_world_wrist[1].rotation).norm(), 1e-4f);
  }
  player.at(1.5 * b.frame_time, f);
  const Vec3 middle = 0.5f * (recorded[1].index_tip[0] + recorded[2].index_tip[0]);
  EXPECT_LT((f.index_tip[0] - middle).norm(), 1e-5f);
  EXPECT_NEAR(f.time, 1.5 * b.frame_time, 1e-12);
  // The rotation halfway: as far from each end.
  const float to_1 =
      Quat(f.T_world_head.rotation).angularDistance(Quat(recorded[1].T_world_head.rotation));
  const float to_2 =
      Quat(f.T_world_head.rotation).angularDistance(Quat(recorded[2].T_world_head.rotation));
  EXPECT_NEAR(to_1, to_2, 1e-4f);
  EXPECT_GT(to_1, 0.0f);
  // Once: held at the ends.
  player.at(-1.0, f);
  EXPECT_LT((f.T_world_head.translation - recorded[0].T_world_head.translation).norm(), 1e-5f);
  player.at(100.0, f);
  EXPECT_LT((f.T_world_head.translation - recorded[3].T_world_head.translation).norm(), 1e-5f);
  EXPECT_NEAR(player.duration(), 3 * b.frame_time, 1e-12);
}

TEST(BvhPlayer, LoopingRepeatsTheRecording) {
  const Bvh b = parse_bvh(testing::humanoid_bvh(testing::random_motion(4, 10, 20)), "l.bvh");
  BvhPlayer player(b, 0.01, Playback::kLoop);
  SkeletonTracking tracking(b, 0.01);
  TrackingFrame first;
  TrackingFrame last;
  tracking.track(0, first);
  tracking.track(3, last);
  TrackingFrame f;
  player.at(4 * b.frame_time * 3 + 2 * b.frame_time, f);  // three loops and two frames
  TrackingFrame two;
  tracking.track(2, two);
  EXPECT_LT((f.T_world_head.translation - two.T_world_head.translation).norm(), 1e-4f);
  player.at(3.5 * b.frame_time, f);  // between the last frame and the first
  EXPECT_LT((f.index_tip[1] - 0.5f * (first.index_tip[1] + last.index_tip[1])).norm(), 1e-5f);
}

}  // namespace
}  // namespace deixis::mocap
