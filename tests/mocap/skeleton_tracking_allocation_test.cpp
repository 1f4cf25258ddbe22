// Tracking a frame and playing a recording allocate nothing once built (mocap/skeleton_tracking.h,
// mocap/player.h).

#include <gtest/gtest.h>

#include "allocation_counter.h"
#include "mocap/humanoid.h"
#include "mocap/player.h"
#include "mocap/skeleton_tracking.h"

namespace deixis::mocap {
namespace {

TEST(SkeletonTrackingAllocation, TrackingAFrameAllocatesNothing) {
  const Bvh b = parse_bvh(testing::humanoid_bvh(testing::random_motion(50, 2)), "a.bvh");
  SkeletonTracking s(b, 0.01);
  TrackingFrame f;
  s.track(0, f);
  deixis::testing::AllocationCounter counter;
  for (std::size_t i = 0; i < b.frames(); ++i) {
    s.track(i, f);
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_EQ(f.valid, tracked::kAll);
}

TEST(SkeletonTrackingAllocation, PlayingAllocatesNothing) {
  const Bvh b = parse_bvh(testing::humanoid_bvh(testing::random_motion(50, 3)), "p.bvh");
  BvhPlayer player(b, 0.01, Playback::kLoop);
  TrackingFrame f;
  player.at(0.0, f);
  deixis::testing::AllocationCounter counter;
  for (int i = 0; i < 300; ++i) {
    player.at(i / 30.0, f);
  }
  EXPECT_EQ(counter.count(), 0u);
}

}  // namespace
}  // namespace deixis::mocap
