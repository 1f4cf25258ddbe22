// A site tick of many remote people (presence::tick_people) allocates nothing once its buffers
// are sized: 64 people of both hands, with missed and broken frames, over 100 ticks. Not built
// under ASan (tests/CMakeLists.txt).

#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "allocation_counter.h"
#include "avatar/avatar_loader.h"
#include "gesture/batch_people.h"
#include "presence/people_tick.h"
#include "test_support.h"

namespace deixis::presence {
namespace {

namespace fs = std::filesystem;

TEST(PeopleTickHotPath, TicksAllocateNothingOnceSized) {
  constexpr int kPeople = 64;
  const ik::AvatarSolver solver = ik::AvatarSolver::build(
      avatar::load_avatar(testing::source_dir() / "assets/avatars/default.glb").rig);
  const fs::path w = testing::reference_dir() / "weights";
  const nn::Mpnet right_mpnet = nn::Mpnet::load(w / "right/MPNet(MoE)(AC)80.safetensors");
  const nn::Ugnet right_ugnet = nn::Ugnet::load(w / "right/UGNet(MoE)(AC)120.safetensors");
  const nn::Mpnet left_mpnet = nn::Mpnet::load(w / "left/MPNet(MoE)(AC)80.safetensors");
  const nn::Ugnet left_ugnet = nn::Ugnet::load(w / "left/UGNet(MoE)(AC)120.safetensors");
  std::vector<testing::CrowdPerson> crowd;
  std::vector<std::unique_ptr<RemoteAvatar>> avatars;
  for (int k = 0; k < kPeople; ++k) {
    crowd.emplace_back(k);
    RemoteAvatarConfig config;
    config.user = crowd.back().standing.body;
    config.T_world_floor = Pose{yaw_rotation(testing::crowd_yaw(k)), testing::crowd_floor(k)};
    const bool left = crowd.back().hand() == Hand::kLeft;
    avatars.push_back(std::make_unique<RemoteAvatar>(
        left ? left_mpnet : right_mpnet, left ? left_ugnet : right_ugnet, solver, config));
  }
  const TargetMap room = testing::receiving_room();
  const LocalTargets targets{&room, Vec3(0, 1.6f, 0.5f)};
  std::vector<TrackingFrame> storage(kPeople);
  std::vector<PersonTick> tick(kPeople);
  PeopleTickBuffers buffers;
  buffers.reserve(kPeople, right_mpnet, right_ugnet);

  testing::AllocationCounter counter;
  int visible = 0;
  for (int t = 0; t < 100; ++t) {
    for (std::size_t i = 0; i < kPeople; ++i) {
      tick[i] = {avatars[i].get(), crowd[i].received(t, storage[i])};
    }
    tick_people(tick, targets, buffers);
    for (const auto& avatar : avatars) {
      visible += avatar->visible() ? 1 : 0;
    }
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(visible, kPeople * 100 * 3 / 4);
}

}  // namespace
}  // namespace deixis::presence
