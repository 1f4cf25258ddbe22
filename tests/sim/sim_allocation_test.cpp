// The simulator's tick adds no allocation to the translator's and IK's: sampling the live user,
// and the panel's rings, allocate nothing once the user's command is planned.

#include <gtest/gtest.h>

#include "allocation_counter.h"
#include "capture/subject.h"
#include "sim/sim_history.h"
#include "sim/sim_user.h"

namespace deixis::sim {
namespace {

TEST(SimAllocationTest, SamplingTheUserAndRecordingATickAllocateNothing) {
  SimUserScene scene;
  scene.T_world_floor = Pose{Mat3::Identity(), Vec3::Zero()};
  scene.objects = {{1, "Lamp", TargetKind::kSphere, Vec3(1.5f, 1.8f, -2.5f), Vec3::Constant(0.3f)}};
  scene.partner_head = Vec3(0, 1.6f, -2.2f);
  SimUser user(capture::find_subject("172"), scene, 5);
  ASSERT_EQ(user.point(0.5, 1), "");
  SimHistory history;
  AvatarFrame frame;
  const deixis::testing::AllocationCounter counter;
  float sum = 0.0f;
  for (int k = 0; k < 300; ++k) {
    const double t = k / 30.0;
    const TrackingFrame f = user.sample(t);
    sum += f.index_tip[1].x() + user.deictic(t);
    frame.progression[1] = user.deictic(t);
    history.push_tick(frame, 0.1);
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_TRUE(std::isfinite(sum));
}

}  // namespace
}  // namespace deixis::sim
