// Many translators ticked with their networks batched (gesture/translator_batch.h) against the
// same translators ticked one by one: a crowd of right- and left-handed people (two weight sets,
// so two batches per tick), arriving at different ticks, with missed and broken frames, over 300
// ticks. Every output of every tick agrees bit for bit (the requirement is 1e-5; the networks give
// a person the same bits alone or in a batch, nn/batch.h).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "batch_people.h"
#include "gesture/translator_batch.h"
#include "test_support.h"

namespace deixis {
namespace {

namespace fs = std::filesystem;

constexpr int kTicks = 300;

using Networks = testing::CrowdNetworks;

TranslatorConfig config_of(const testing::CrowdPerson& person, int k) {
  TranslatorConfig config;
  config.user = person.standing.body;
  config.T_world_avatar_root =
      Pose{yaw_rotation(testing::crowd_yaw(k)), testing::crowd_floor(k) + Vec3(0, 1.55f, 0)};
  config.avatar_height = 1.62f + 0.05f * static_cast<float>(k % 3);
  config.noise_seed = static_cast<std::uint32_t>(k + 1);
  return config;
}

float largest_difference(const AvatarFrame& a, const AvatarFrame& b) {
  float worst = 0.0f;
  const auto vec = [&](const Vec3& x, const Vec3& y) {
    worst = std::max(worst, (x - y).cwiseAbs().maxCoeff());
  };
  const auto pose = [&](const Pose& x, const Pose& y) {
    vec(x.translation, y.translation);
    worst = std::max(worst, (x.rotation - y.rotation).cwiseAbs().maxCoeff());
  };
  vec(a.deictic.gaze, b.deictic.gaze);
  pose(a.deictic.T_world_head, b.deictic.T_world_head);
  pose(a.deictic.T_world_wrist, b.deictic.T_world_wrist);
  vec(a.deictic.index_tip, b.deictic.index_tip);
  pose(a.other_wrist_from_head, b.other_wrist_from_head);
  for (int i = 0; i < nn::kProgressionSize; ++i) {
    worst = std::max(worst, std::abs(a.progression[i] - b.progression[i]));
  }
  return worst;
}

// Ticks `people` translators alone and batched side by side; returns the largest difference.
float crowd_difference(int people, const Networks& right, const Networks& left) {
  std::vector<testing::CrowdPerson> crowd;
  std::vector<std::unique_ptr<Translator>> alone, batched;
  std::vector<Translator*> batched_ptrs;
  for (int k = 0; k < people; ++k) {
    crowd.emplace_back(k);
    const Networks& n = crowd.back().hand() == Hand::kLeft ? left : right;
    alone.push_back(std::make_unique<Translator>(n.mpnet, n.ugnet, config_of(crowd.back(), k)));
    batched.push_back(std::make_unique<Translator>(n.mpnet, n.ugnet, config_of(crowd.back(), k)));
    batched_ptrs.push_back(batched.back().get());
  }
  const TargetMap room = testing::receiving_room();
  const LocalTargets targets{&room, Vec3(0, 1.6f, 0.5f)};
  TranslatorBatch batch;
  std::vector<TrackingFrame> storage(static_cast<std::size_t>(people));
  std::vector<const TrackingFrame*> frames(static_cast<std::size_t>(people));
  float worst = 0.0f;
  int compared = 0;
  for (int t = 0; t < kTicks; ++t) {
    for (int k = 0; k < people; ++k) {
      const auto i = static_cast<std::size_t>(k);
      frames[i] = crowd[i].received(t, storage[i]);
    }
    tick_translators(batched_ptrs, frames, targets, batch);
    for (int k = 0; k < people; ++k) {
      const auto i = static_cast<std::size_t>(k);
      const AvatarFrame expected = alone[i]->tick(frames[i], targets);
      const AvatarFrame& actual = batched[i]->tick_result();
      EXPECT_EQ(actual.ready, expected.ready) << "person " << k << " tick " << t;
      EXPECT_EQ(actual.held, expected.held) << "person " << k << " tick " << t;
      EXPECT_EQ(actual.hand_target, expected.hand_target);
      EXPECT_EQ(actual.head_weight, expected.head_weight) << "person " << k << " tick " << t;
      EXPECT_EQ(actual.hand_weight, expected.hand_weight) << "person " << k << " tick " << t;
      if (expected.ready && actual.ready) {
        worst = std::max(worst, largest_difference(actual, expected));
        ++compared;
      }
    }
  }
  for (int k = 0; k < people; ++k) {
    const auto i = static_cast<std::size_t>(k);
    EXPECT_EQ(batched[i]->stats().held, alone[i]->stats().held);
    EXPECT_EQ(batched[i]->stats().rejected_frames, alone[i]->stats().rejected_frames);
  }
  EXPECT_GT(compared, people * kTicks * 3 / 4);
  return worst;
}

TEST(TranslatorBatch, CrowdEqualsOneByOne) {
  const Networks right = testing::load_networks(testing::reference_dir() / "weights/right");
  const Networks left = testing::load_networks(testing::reference_dir() / "weights/left");
  for (const int people : {1, 3, 16, 37}) {  // 37: each hand's sixteen in lanes, the rest as rows
    const float worst = crowd_difference(people, right, left);
    std::cout << "[ measured ] " << people << " people, " << kTicks
              << " ticks: max |batched - alone| " << worst << "\n";
    EXPECT_EQ(worst, 0.0f) << people << " people";
  }
}

TEST(TranslatorBatch, ShippedWeightsEqualOneByOne) {
  const Networks right = testing::load_networks(testing::source_dir() / "assets/weights/right");
  const Networks left = testing::load_networks(testing::source_dir() / "assets/weights/left");
  const float worst = crowd_difference(5, right, left);
  std::cout << "[ measured ] shipped weights, 5 people: max |batched - alone| " << worst << "\n";
  EXPECT_EQ(worst, 0.0f);
}

// A diffusion UGNet has no batched path: through the batch each person still gets their own
// draws (mixed up, the poses would differ by centimetres).
TEST(TranslatorBatch, DiffusionPeopleKeepTheirOwnDraws) {
  const fs::path w = testing::reference_dir() / "weights";
  const Networks right = testing::load_networks(w / "right", "UGNet(Diffusion)(AC)120.safetensors");
  const Networks left = testing::load_networks(w / "left", "UGNet(Diffusion)(AC)120.safetensors");
  EXPECT_EQ(crowd_difference(3, right, left), 0.0f);
}

}  // namespace
}  // namespace deixis
