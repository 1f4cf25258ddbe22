// Tracking a frame allocates nothing once the tracker is built (mocap/skeleton_tracking.h).

#include <gtest/gtest.h>

#include "allocation_counter.h"
#include "mocap/humanoid.h"
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

}  // namespace
}  // namespace deixis::mocap
