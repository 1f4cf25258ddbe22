// A site tick of many remote people (presence::tick_people: networks batched across people, then
// touch contact and IK per person) against ticking each RemoteAvatar alone: a crowd of right- and
// left-handed people, arriving at different ticks, with missed and broken frames, over 300 ticks.
// Every joint of every avatar agrees bit for bit at every tick (the requirement is 1e-5; the IK
// amplifies the networks' last-bit differences about fifty times, so anything less than bit
// equality of the networks would not meet it; nn/batch.h).

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "avatar/avatar_loader.h"
#include "gesture/batch_people.h"
#include "presence/people_tick.h"
#include "test_support.h"

namespace deixis::presence {
namespace {

namespace fs = std::filesystem;

constexpr int kTicks = 300;

using Networks = testing::CrowdNetworks;

float largest_difference(const RemoteAvatar& a, const RemoteAvatar& b) {
  float worst = 0.0f;
  for (std::size_t j = 0; j < a.model_pose().size(); ++j) {
    const Pose& x = a.model_pose()[j];
    const Pose& y = b.model_pose()[j];
    worst = std::max(worst, (x.translation - y.translation).cwiseAbs().maxCoeff());
    worst = std::max(worst, (x.rotation - y.rotation).cwiseAbs().maxCoeff());
  }
  worst = std::max(worst, (a.eye_midpoint() - b.eye_midpoint()).cwiseAbs().maxCoeff());
  worst = std::max(worst, (a.index_fingertip() - b.index_fingertip()).cwiseAbs().maxCoeff());
  return worst;
}

class PeopleTick : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    solver_ = new ik::AvatarSolver(ik::AvatarSolver::build(
        avatar::load_avatar(testing::source_dir() / "assets/avatars/default.glb").rig));
  }
  static void TearDownTestSuite() {
    delete solver_;
    solver_ = nullptr;
  }
  static ik::AvatarSolver* solver_;
};
ik::AvatarSolver* PeopleTick::solver_ = nullptr;

TEST_F(PeopleTick, CrowdEqualsEachAvatarAlone) {
  const Networks right = testing::load_networks(testing::reference_dir() / "weights/right");
  const Networks left = testing::load_networks(testing::reference_dir() / "weights/left");
  const TargetMap room = testing::receiving_room();
  const LocalTargets targets{&room, Vec3(0, 1.6f, 0.5f)};
  for (const int people : {1, 4, 9, 34}) {  // 34: each hand's sixteen in lanes, one as a row
    std::vector<testing::CrowdPerson> crowd;
    std::vector<std::unique_ptr<RemoteAvatar>> alone, together;
    for (int k = 0; k < people; ++k) {
      crowd.emplace_back(k);
      RemoteAvatarConfig config;
      config.user = crowd.back().standing.body;
      config.T_world_floor = Pose{yaw_rotation(testing::crowd_yaw(k)), testing::crowd_floor(k)};
      const Networks& n = crowd.back().hand() == Hand::kLeft ? left : right;
      alone.push_back(std::make_unique<RemoteAvatar>(n.mpnet, n.ugnet, *solver_, config));
      together.push_back(std::make_unique<RemoteAvatar>(n.mpnet, n.ugnet, *solver_, config));
    }
    PeopleTickBuffers buffers;
    std::vector<TrackingFrame> storage(static_cast<std::size_t>(people));
    std::vector<PersonTick> tick(static_cast<std::size_t>(people));
    float worst = 0.0f;
    int visible = 0;
    for (int t = 0; t < kTicks; ++t) {
      for (int k = 0; k < people; ++k) {
        const auto i = static_cast<std::size_t>(k);
        tick[i] = {together[i].get(), crowd[i].received(t, storage[i])};
      }
      tick_people(tick, targets, buffers);
      for (int k = 0; k < people; ++k) {
        const auto i = static_cast<std::size_t>(k);
        const bool shown = alone[i]->tick(tick[i].frame, targets);
        ASSERT_EQ(together[i]->visible(), shown) << "person " << k << " tick " << t;
        ASSERT_EQ(together[i]->frame().held, alone[i]->frame().held);
        if (shown) {
          worst = std::max(worst, largest_difference(*together[i], *alone[i]));
          ++visible;
        }
      }
    }
    std::cout << "[ measured ] " << people << " people, " << kTicks
              << " ticks: max |together - alone| over every joint " << worst << "\n";
    EXPECT_EQ(worst, 0.0f) << people << " people";
    EXPECT_GT(visible, people * kTicks * 3 / 4);
    for (int k = 0; k < people; ++k) {
      const auto i = static_cast<std::size_t>(k);
      EXPECT_EQ(together[i]->stats().held, alone[i]->stats().held);
      EXPECT_EQ(together[i]->stats().rejected_frames, alone[i]->stats().rejected_frames);
    }
  }
}

// Null entries are skipped, and one person missing a frame only holds that person's avatar.
TEST_F(PeopleTick, NullAvatarsAreSkippedAndAMissHoldsOnlyItsPerson) {
  const Networks right = testing::load_networks(testing::reference_dir() / "weights/right");
  testing::CrowdPerson a(0), b(1);
  RemoteAvatarConfig config;
  config.user = a.standing.body;
  RemoteAvatar first(right.mpnet, right.ugnet, *solver_, config);
  config.user = b.standing.body;
  config.T_world_floor = Pose{Mat3::Identity(), Vec3(1.5f, 0, 0)};
  RemoteAvatar second(right.mpnet, right.ugnet, *solver_, config);
  const TargetMap room = testing::receiving_room();
  const LocalTargets targets{&room, Vec3(0, 1.6f, 0.5f)};
  PeopleTickBuffers buffers;
  const TrackingFrame fa = a.frame(1), fb = b.frame(1);
  std::vector<PersonTick> tick = {{&first, &fa}, {nullptr, &fb}, {&second, &fb}};
  tick_people(tick, targets, buffers);
  EXPECT_TRUE(first.visible());
  EXPECT_TRUE(second.visible());
  tick = {{&first, nullptr}, {&second, &fb}};
  tick_people(tick, targets, buffers);
  EXPECT_TRUE(first.frame().held);
  EXPECT_FALSE(second.frame().held);
  EXPECT_EQ(first.stats().held, 1u);
  EXPECT_EQ(second.stats().held, 0u);
}

}  // namespace
}  // namespace deixis::presence
