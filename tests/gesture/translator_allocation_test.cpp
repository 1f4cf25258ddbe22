// A translator tick allocates nothing: features, MPNet, blend, UGNet, decode, missed tracking;
// nor does the sender's target selection.

#include <gtest/gtest.h>

#include "allocation_counter.h"
#include "gesture/target_selection.h"
#include "gesture/translator.h"
#include "test_support.h"
#include "tracking_frames.h"

namespace deixis {
namespace {

TEST(HotPath, TranslatorTicksAllocateNothing) {
  const auto weights = testing::reference_dir() / "weights/left";
  testing::StandingPerson person(Hand::kLeft, 1.62f);
  TranslatorConfig config;
  config.user = person.body;
  config.T_world_avatar_root = Pose{yaw_rotation(-0.3f), Vec3(1, 1.6f, 2)};
  for (const char* ugnet :
       {"UGNet(MoE)(AC)120.safetensors", "UGNet(Diffusion)(AC)120.safetensors"}) {
    Translator translator(nn::Mpnet::load(weights / "MPNet(MoE)(AC)80.safetensors"),
                          nn::Ugnet::load(weights / ugnet), config);
    TargetMap room;
    room.objects.push_back(
        {1, "Box", TargetKind::kBox, Vec3(0.4f, 1.0f, 1.4f), Vec3(0.3f, 0.3f, 0.3f)});
    const LocalTargets targets{&room, Vec3(1, 1.6f, 0)};
    TrackingFrame frame = person.frame;
    float sink = 0.0f;
    const auto tick = [&](int i) {
      frame.T_world_head.translation.x() = 0.01f * static_cast<float>(i % 7);
      const AvatarFrame a = translator.tick(i % 10 == 9 ? nullptr : &frame, targets);
      sink += a.deictic.index_tip.x();
    };
    for (int i = 0; i < 10; ++i) {
      tick(i);
    }
    const int ticks = std::string(ugnet).find("Diffusion") != std::string::npos ? 100 : 1000;
    testing::AllocationCounter counter;
    for (int i = 0; i < ticks; ++i) {
      tick(i);
    }
    EXPECT_EQ(counter.count(), 0u) << ugnet;
    EXPECT_TRUE(std::isfinite(sink));
  }
}

TEST(HotPath, TargetSelectionAllocatesNothing) {
  testing::StandingPerson person(Hand::kRight, 1.75f);
  TargetMap room;
  for (int i = 0; i < 8; ++i) {
    room.objects.push_back({i + 1, "Box", i % 2 == 0 ? TargetKind::kBox : TargetKind::kSphere,
                            Vec3(0.3f * static_cast<float>(i) - 1.0f, 1.0f, -1.5f),
                            Vec3(0.2f, 0.2f, 0.2f)});
  }
  TargetSelector selector;
  TrackingFrame frame = person.frame;
  int changes = 0;
  testing::AllocationCounter counter;
  for (int i = 0; i < 1000; ++i) {
    // Sweep the gaze and the fingertip across the objects.
    const float x = 0.003f * static_cast<float>(i % 800) - 1.2f;
    frame.gaze = (Vec3(x, 1.0f, -1.5f) - frame.T_world_head.translation).normalized();
    frame.index_tip[index(Hand::kRight)] = Vec3(-x, 1.2f, -0.5f);
    const TargetId before = selector.head_target;
    selector.select(frame, room, Vec3(1, 1.6f, 0));
    changes += selector.head_target != before ? 1 : 0;
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(changes, 4);  // the sweep really moved the selection
}

}  // namespace
}  // namespace deixis
