// The translator's handling of the stream: readiness, missed tracking, bad numbers, unknown
// targets. (Whether it points the avatar at the right object is checked end to end with the
// synthetic capture.)

#include "gesture/translator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "test_support.h"
#include "tracking_frames.h"

namespace deixis {
namespace {

namespace fs = std::filesystem;

bool all_finite(const AvatarFrame& a) {
  return a.deictic.gaze.allFinite() && is_finite(a.deictic.T_world_head) &&
         is_finite(a.deictic.T_world_wrist) && a.deictic.index_tip.allFinite() &&
         is_finite(a.other_wrist_from_head);
}

class TranslatorTest : public ::testing::Test {
 protected:
  TranslatorTest()
      : person(Hand::kRight),
        translator(nn::Mpnet::load(weights() / "MPNet(MoE)(AC)80.safetensors"),
                   nn::Ugnet::load(weights() / "UGNet(MoE)(AC)120.safetensors"), config()) {
    room.site.assign(1, 'B');  // not = "B": GCC 12 -O3 reports a false -Wrestrict there
    room.objects.push_back(
        {1, "Jupiter", TargetKind::kSphere, Vec3(1.5f, 1.5f, -2.5f), Vec3(0.3f, 0.3f, 0.3f)});
    targets.map = &room;
    targets.partner_head = Vec3(0, 1.6f, -2.0f);
  }
  static fs::path weights() { return testing::reference_dir() / "weights/right"; }
  TranslatorConfig config() const {
    TranslatorConfig c;
    c.user = person.body;
    c.T_world_avatar_root = Pose{yaw_rotation(0.5f), Vec3(3, 1.55f, 1)};
    c.avatar_height = 1.65f;
    return c;
  }

  testing::StandingPerson person;
  Translator translator;
  TargetMap room;
  LocalTargets targets;
};

TEST_F(TranslatorTest, HiddenUntilTheFirstValidFrame) {
  EXPECT_FALSE(translator.tick(nullptr, targets).ready);
  TrackingFrame no_head = person.frame;
  no_head.valid &= static_cast<std::uint8_t>(~tracked::kHead);
  EXPECT_FALSE(translator.tick(&no_head, targets).ready);
  const AvatarFrame first = translator.tick(&person.frame, targets);
  EXPECT_TRUE(first.ready);
  EXPECT_FALSE(first.held);
  EXPECT_TRUE(all_finite(first));
  EXPECT_EQ(translator.stats().rejected_frames, 1u);
  EXPECT_EQ(translator.stats().held, 0u);
}

TEST_F(TranslatorTest, MissedTrackingHoldsTheLastValidFrameAndIsCounted) {
  translator.tick(&person.frame, targets);
  TrackingFrame bad = person.frame;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<TrackingFrame> broken;
  bad.T_world_head.translation.x() = nan;
  broken.push_back(bad);
  bad = person.frame;
  bad.gaze = Vec3(inf, 0, 0);
  broken.push_back(bad);
  bad = person.frame;
  bad.T_world_wrist[index(Hand::kRight)].rotation(1, 1) = nan;
  broken.push_back(bad);
  bad = person.frame;
  bad.index_tip[index(Hand::kRight)].z() = -inf;
  broken.push_back(bad);
  bad = person.frame;
  bad.hand_target_position.y() = nan;
  broken.push_back(bad);
  bad = person.frame;
  bad.valid &= static_cast<std::uint8_t>(~tracked::kRightHand);
  broken.push_back(bad);
  bad = person.frame;
  bad.gaze = Vec3::Zero();
  broken.push_back(bad);
  bad = person.frame;
  bad.time = std::numeric_limits<double>::quiet_NaN();
  broken.push_back(bad);
  for (const TrackingFrame& frame : broken) {
    const AvatarFrame a = translator.tick(&frame, targets);
    EXPECT_TRUE(a.ready);
    EXPECT_TRUE(a.held);
    EXPECT_TRUE(all_finite(a));
  }
  for (int i = 0; i < 20; ++i) {  // a gap of 20 ticks: no frames at all
    const AvatarFrame a = translator.tick(nullptr, targets);
    EXPECT_TRUE(a.held);
    EXPECT_TRUE(all_finite(a));
  }
  EXPECT_EQ(translator.stats().rejected_frames, broken.size());
  EXPECT_EQ(translator.stats().held, broken.size() + 20);
  const AvatarFrame resumed = translator.tick(&person.frame, targets);
  EXPECT_FALSE(resumed.held);
}

TEST_F(TranslatorTest, TheNonDeicticHandSurvivesItsOwnLoss) {
  translator.tick(&person.frame, targets);
  const Pose before = translator.tick(&person.frame, targets).other_wrist_from_head;
  TrackingFrame left_lost = person.frame;
  left_lost.valid &= static_cast<std::uint8_t>(~tracked::kLeftHand);
  left_lost.T_world_wrist[index(Hand::kLeft)].translation = Vec3(9, 9, 9);  // garbage
  const AvatarFrame a = translator.tick(&left_lost, targets);
  EXPECT_FALSE(a.held);  // the deictic side is fine
  EXPECT_TRUE(a.other_wrist_from_head.translation.isApprox(before.translation, 1e-6f));
}

TEST_F(TranslatorTest, TheNonDeicticHandIsRelativeToTheBodyNotTheHeadsTurn) {
  const Pose still = translator.tick(&person.frame, targets).other_wrist_from_head;
  TrackingFrame turned = person.frame;
  turned.T_world_head.rotation = turned.T_world_head.rotation * yaw_rotation(0.5f);
  const Pose after = translator.tick(&turned, targets).other_wrist_from_head;
  EXPECT_TRUE(after.translation.isApprox(still.translation, 1e-5f));
  EXPECT_TRUE(after.rotation.isApprox(still.rotation, 1e-5f));
  // Scaled to the avatar: the user (1.70 m) is taller than the avatar (1.65 m).
  const Pose& wrist = person.frame.T_world_wrist[index(Hand::kLeft)];
  const Vec3 offset = config().user.T_world_root.rotation.transpose() *
                      (wrist.translation - person.frame.T_world_head.translation);
  EXPECT_TRUE(still.translation.isApprox(offset * (1.65f / 1.70f), 1e-5f));
}

TEST_F(TranslatorTest, AnObjectThisRoomLacksIsCopiedAndCounted) {
  TrackingFrame frame = person.frame;
  frame.hand_target = 42;  // not in room B
  translator.tick(&frame, targets);
  EXPECT_EQ(translator.stats().unknown_targets, 1u);
  EXPECT_EQ(translator.stats().held, 0u);
}

// Nothing designated (kNoTarget, e.g. a headset user in a room looking at nothing) is translated,
// not held: its point is ahead of the person's head (core/target_map.h), computed here, whatever
// position the frame carries (the wire carries none), and copied into this room like an object
// this room lacks, without counting it as unknown.
TEST_F(TranslatorTest, NothingDesignatedIsTranslatedAsThePointAheadOfTheHead) {
  Translator copied(translator.mpnet(), translator.ugnet(), config());
  for (int i = 0; i < 40; ++i) {
    TrackingFrame nothing = person.frame;
    nothing.T_world_head.rotation = yaw_rotation(0.02f * static_cast<float>(i));
    nothing.head_target = nothing.hand_target = kNoTarget;
    nothing.head_target_position = nothing.hand_target_position = Vec3::Zero();
    TrackingFrame ahead = nothing;
    ahead.head_target = ahead.hand_target = 42;  // not in room B: copied
    ahead.head_target_position = ahead.hand_target_position =
        nothing_designated_point(nothing.T_world_head);
    const AvatarFrame a = translator.tick(&nothing, targets);
    const AvatarFrame b = copied.tick(&ahead, targets);
    ASSERT_TRUE(a.ready);
    EXPECT_FALSE(a.held);
    EXPECT_EQ(a.head_target, kNoTarget);
    EXPECT_LT((a.deictic.gaze - b.deictic.gaze).norm(), 1e-6f) << i;
    EXPECT_LT((a.deictic.index_tip - b.deictic.index_tip).norm(), 1e-6f) << i;
  }
  EXPECT_EQ(translator.stats().held, 0u);
  EXPECT_EQ(translator.stats().rejected_frames, 0u);
  EXPECT_EQ(translator.stats().unknown_targets, 0u);
  EXPECT_GT(copied.stats().unknown_targets, 0u);
}

TEST_F(TranslatorTest, ScaleIsTheRatioOfHeights) {
  EXPECT_NEAR(translator.scale(), 1.70f / 1.65f, 1e-6f);
}

TEST_F(TranslatorTest, TheAvatarStandsAtItsOwnRoot) {
  // Idle, upright, both hands down: after a second the avatar's head is near its own root (not
  // the user's), and its non-deictic hand hangs below the head.
  AvatarFrame a;
  for (int i = 0; i < 30; ++i) {
    a = translator.tick(&person.frame, targets);
  }
  const Vec3 avatar_root = config().T_world_avatar_root.translation;
  EXPECT_LT((a.deictic.T_world_head.translation - avatar_root).norm(), 0.15f);
  EXPECT_LT(a.other_wrist_from_head.translation.y(), -0.5f);
}

// A mirrored translator (a left-handed person through the right-hand weights,
// docs/decisions.md §68) fed the mirror image of a right-handed person, in the mirror image of a
// room, moves the avatar as the mirror image of an unmirrored translator's: the networks see the
// same numbers, and what comes back is mirrored once, through the person's sagittal plane.
TEST(MirroredTranslator, IsTheMirrorImageOfTheRightHandedTranslation) {
  const auto mirror = [](const Vec3& v) { return Vec3(-v.x(), v.y(), v.z()); };
  const fs::path weights = testing::reference_dir() / "weights/right";
  const auto translator = [&](Hand hand, bool mirrored, float side) {
    TranslatorConfig c;
    c.user = testing::StandingPerson(hand).body;
    c.T_world_avatar_root = Pose{yaw_rotation(0.5f * side), Vec3(3 * side, 1.55f, 1)};
    c.avatar_height = 1.65f;
    c.mirrored = mirrored;
    return Translator(nn::Mpnet::load(weights / "MPNet(MoE)(AC)80.safetensors"),
                      nn::Ugnet::load(weights / "UGNet(MoE)(AC)120.safetensors"), c);
  };
  Translator right = translator(Hand::kRight, false, 1.0f);
  Translator left = translator(Hand::kLeft, true, -1.0f);
  TargetMap room, mirror_room;
  room.objects.push_back(
      {1, "Jupiter", TargetKind::kSphere, Vec3(1.5f, 1.5f, -2.5f), Vec3(0.3f, 0.3f, 0.3f)});
  mirror_room.objects = room.objects;
  mirror_room.objects[0].position = mirror(room.objects[0].position);
  const LocalTargets targets{&room, Vec3(0, 1.6f, -2.0f)};
  const LocalTargets mirror_targets{&mirror_room, Vec3(0, 1.6f, -2.0f)};
  // Each looks and points at a target to their deictic side.
  testing::StandingPerson r(Hand::kRight), l(Hand::kLeft);
  for (testing::StandingPerson* p : {&r, &l}) {
    const float side = p == &r ? 1.0f : -1.0f;
    TrackingFrame& f = p->frame;
    f.head_target_position = f.hand_target_position = Vec3(0.8f * side, 1.4f, -2.0f);
    f.gaze = (f.head_target_position - f.T_world_head.translation).normalized();
  }
  float worst = 0.0f;
  for (int i = 0; i < 40; ++i) {
    const AvatarFrame a = right.tick(&r.frame, targets);
    const AvatarFrame b = left.tick(&l.frame, mirror_targets);
    ASSERT_EQ(b.deictic_hand, Hand::kLeft);
    worst = std::max(
        {worst, (mirror(a.deictic.gaze) - b.deictic.gaze).norm(),
         (mirror(a.deictic.T_world_head.translation) - b.deictic.T_world_head.translation).norm(),
         (mirror(a.deictic.T_world_wrist.translation) - b.deictic.T_world_wrist.translation).norm(),
         (mirror(a.deictic.index_tip) - b.deictic.index_tip).norm()});
  }
  EXPECT_LT(worst, 1e-3f);
  // Not trivially so: the avatar looks to its side, not straight ahead.
  EXPECT_GT(std::abs(right.tick(&r.frame, targets).deictic.gaze.x()), 0.1f);
}

}  // namespace
}  // namespace deixis
