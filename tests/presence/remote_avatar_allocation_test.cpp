// A remote avatar's tick (translator + whole-avatar IK) allocates nothing once constructed: 1,000
// ticks over moving tracking and missed frames make zero heap allocations. Not built under ASan
// (tests/CMakeLists.txt).

#include <gtest/gtest.h>

#include "allocation_counter.h"
#include "avatar/avatar_loader.h"
#include "gesture/tracking_frames.h"
#include "presence/remote_avatar.h"
#include "test_support.h"

namespace deixis::presence {
namespace {

namespace fs = std::filesystem;

TEST(RemoteAvatarHotPath, TicksAllocateNothing) {
  const fs::path weights = testing::reference_dir() / "weights/right";
  const ik::AvatarSolver solver = ik::AvatarSolver::build(
      avatar::load_avatar(fs::path(DEIXIS_SOURCE_DIR) / "assets/avatars/default.glb").rig);
  testing::StandingPerson person;
  RemoteAvatarConfig config;
  config.user = person.body;
  config.T_world_floor = Pose{yaw_rotation(3.14159f), Vec3(0, 0, -2.2f)};
  RemoteAvatar avatar(nn::Mpnet::load(weights / "MPNet(MoE)(AC)80.safetensors"),
                      nn::Ugnet::load(weights / "UGNet(MoE)(AC)120.safetensors"), solver, config);
  TargetMap room;
  room.objects.push_back(
      {1, "Jupiter", TargetKind::kSphere, Vec3(1.5f, 1.5f, -2.5f), Vec3(0.3f, 0.3f, 0.3f)});
  const LocalTargets targets{&room, Vec3(0, 1.6f, 0)};
  avatar.tick(&person.frame, targets);  // warm-up

  deixis::testing::AllocationCounter counter;
  TrackingFrame frame = person.frame;
  for (int i = 0; i < 1000; ++i) {
    const float t = static_cast<float>(i) / 30.0f;
    frame.T_world_wrist[index(Hand::kRight)].translation.z() = -0.3f * std::sin(t);
    frame.index_tip[index(Hand::kRight)].z() = -0.45f * std::sin(t);
    avatar.tick(i % 50 == 7 ? nullptr : &frame, targets);
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_TRUE(avatar.visible());
}

}  // namespace
}  // namespace deixis::presence
