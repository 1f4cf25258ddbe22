// The receiving site's completion-state detector (eval/deictic_observer.h) on hand-made streams: a
// person reaches towards an object at 1 m/s, holds still, then lowers the hand. Exactly one
// completion state is found, on the last frame of the hold, wherever the frames' local play times
// fall; frames that arrive late and play in a burst at one local time (a loaded machine, a
// network hiccup) are not a hand standing still. The errors there are the angles to the object.

#include "eval/deictic_observer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/math/angles.h"
#include "eval/metrics.h"

namespace deixis::eval {
namespace {

constexpr double kPeriod = 1.0 / 30.0;  // s between the sender's frames
constexpr TargetId kCup = 1;

struct Scene {
  BodyCalibration user;  // root O at the world origin, facing −Z, right-handed pointer
  presence::PoseCopy copy{user, Pose(), 1.70f};
  TargetMap room{"B",
                 {TargetObject{kCup, "cup", TargetKind::kSphere, Vec3(0.4f, 0.0f, -1.5f),
                               Vec3::Constant(0.1f)}}};
};

// The sender's frame `k` with the fingertip at depth `z`, the wrist behind it well away from its
// rest position.
TrackingFrame frame_at(int k, float z, TargetId target = kCup) {
  TrackingFrame f;
  f.time = 10.0 + k * kPeriod;  // the sender's clock has its own origin
  f.hand_target = target;
  f.T_world_wrist[index(Hand::kRight)].translation = Vec3(0.3f, -0.1f, z + 0.15f);
  f.index_tip[index(Hand::kRight)] = Vec3(0.3f, -0.1f, z);
  return f;
}

// The avatar points exactly at the cup: its fingertip on the line from the eyes to the cup.
eval::AvatarChain pointing_at(const Scene& s) {
  const Vec3 eyes = Vec3::Zero();
  return {eyes, eyes + 0.6f * (s.room.objects[0].position - eyes).normalized(), Pose()};
}

// A receiving site's observer watching the scene's person, the avatar pointing at the cup.
struct Watch {
  Scene scene;
  eval::AvatarChain chain = pointing_at(scene);
  eval::DeicticObserver observer;

  explicit Watch(std::size_t capacity) : observer(capacity) {}

  void play(int k, float z, double local_time, TargetId target = kCup) {
    observer.observe(frame_at(k, z, target), static_cast<std::uint32_t>(k), local_time, chain,
                     scene.copy, scene.room, &scene.room);
  }
};

// The fingertip's depth in frame `k` of a reach at 1 m/s (frames 0..12), a hold (13..21) and a
// lowering at 1 m/s (22..27).
float reach_hold_lower_z(int k) {
  const float step = static_cast<float>(kPeriod);
  const float reached = -0.2f - 12 * step;
  if (k <= 12) {
    return -0.2f - static_cast<float>(k) * step;
  }
  return k <= 21 ? reached : reached + static_cast<float>(k - 21) * step;
}

// The reach, hold and lowering, then the target dropped (frame 28); each frame's local play time
// from `local_time(k)`.
template <typename LocalTime>
std::vector<eval::DeicticSample> observe_reach_hold_lower(LocalTime local_time) {
  Watch watch(8);
  for (int k = 0; k <= 28; ++k) {
    watch.play(k, reach_hold_lower_z(k), local_time(k), k < 28 ? kCup : kNoTarget);
  }
  const auto samples = watch.observer.samples();
  return {samples.begin(), samples.end()};
}

TEST(DeicticObserver, OneCompletionStateOnTheLastFrameOfTheHold) {
  const auto samples = observe_reach_hold_lower([](int k) { return k * kPeriod; });
  ASSERT_EQ(samples.size(), 1u);
  // Frame 13 is the first still one; frame 22 moves off, which ends the hold on frame 21.
  EXPECT_EQ(samples[0].sequence, 21u);
  EXPECT_EQ(samples[0].target, kCup);
  EXPECT_FALSE(samples[0].touching);
  EXPECT_NEAR(samples[0].avatar.horizontal_deg, 0.0, 0.01);
  EXPECT_NEAR(samples[0].avatar.vertical_deg, 0.0, 0.01);
  EXPECT_GT(samples[0].copy.horizontal_deg, 1.0);  // the copied pose points elsewhere
}

TEST(DeicticObserver, FramesPlayedInABurstAtOneLocalTimeAreNotAHold) {
  // Every three frames arrive together and play at the same local time: the local clock sees the
  // reaching hand not move at all between frames of a burst.
  const auto samples = observe_reach_hold_lower([](int k) { return (k / 3) * 3 * kPeriod; });
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples[0].sequence, 21u);
}

TEST(DeicticObserver, ALateGapInLocalPlayTimeIsNotAHold) {
  // A 0.5 s stall mid-reach: the local clock would read the hand as crawling (0.06 m/s).
  const auto samples =
      observe_reach_hold_lower([](int k) { return k * kPeriod + (k >= 5 ? 0.5 : 0.0); });
  ASSERT_EQ(samples.size(), 1u);
  EXPECT_EQ(samples[0].sequence, 21u);
}

TEST(DeicticObserver, AFrameNoLaterThanTheLastOnTheSendersClockIsNotAHold) {
  // Frame 6 of the reach comes twice (same sender time, same place): no speed, so no hold. A NaN
  // sender time takes the same path.
  Watch watch(8);
  for (int k = 0; k <= 28; ++k) {
    const TargetId target = k < 28 ? kCup : kNoTarget;
    watch.play(k, reach_hold_lower_z(k), k * kPeriod, target);
    if (k == 6) {
      watch.play(k, reach_hold_lower_z(k), k * kPeriod, target);
    }
  }
  ASSERT_EQ(watch.observer.samples().size(), 1u);
  EXPECT_EQ(watch.observer.samples()[0].sequence, 21u);
}

TEST(DeicticObserver, AStoppedStreamEndsTheHoldInProgress) {
  Watch watch(8);
  for (int k = 0; k < 18; ++k) {  // the reach and five frames of the hold
    watch.play(k, reach_hold_lower_z(k), k * kPeriod);
  }
  EXPECT_TRUE(watch.observer.samples().empty());  // still holding
  watch.observer.interrupt();
  ASSERT_EQ(watch.observer.samples().size(), 1u);
  EXPECT_EQ(watch.observer.samples()[0].sequence, 17u);
}

TEST(DeicticObserver, SamplesBeyondItsCapacityAreCountedAndDropped) {
  Watch watch(1);
  int k = 0;
  for (int hold = 0; hold < 3; ++hold) {
    for (int i = 0; i < 17; ++i, ++k) {  // the reach and four frames of the hold
      watch.play(k, reach_hold_lower_z(i), k * kPeriod);
    }
    watch.observer.interrupt();
  }
  EXPECT_EQ(watch.observer.samples().size(), 1u);
  EXPECT_EQ(watch.observer.dropped(), 2u);
}

// Where the error comes from: the networks' end-effectors (given with the chain) measured the
// same way as the avatar's, how far IK moved the fingertip, the person's own gesture in their
// room, and how long the hold lasted; without the networks' chain those are unmeasured.
TEST(DeicticObserver, TheStagesOfTheChainAreMeasuredAtTheCompletion) {
  Watch watch(8);
  // The networks' fingertip 10° to the side of the cup, which IK then put on the line.
  const Vec3 eyes = watch.chain.eye_midpoint;
  const Vec3 to_cup = watch.scene.room.objects[0].position - eyes;
  const Eigen::AngleAxisf turn(10.0f * kRadPerDeg, Vec3::UnitY());
  watch.chain.has_network = true;
  watch.chain.network_head = eyes;
  watch.chain.network_fingertip = eyes + 0.6f * (turn * to_cup).normalized();
  for (int k = 0; k <= 28; ++k) {
    watch.play(k, reach_hold_lower_z(k), k * kPeriod, k < 28 ? kCup : kNoTarget);
  }
  ASSERT_EQ(watch.observer.samples().size(), 1u);
  const DeicticSample& s = watch.observer.samples()[0];
  EXPECT_NEAR(s.avatar.horizontal_deg, 0.0, 0.01);
  EXPECT_NEAR(s.network.horizontal_deg, 10.0, 0.05);
  EXPECT_NEAR(s.network.vertical_deg, 0.0, 0.05);
  EXPECT_NEAR(
      s.ik_fingertip_cm,
      100.0 * static_cast<double>((watch.chain.fingertip - watch.chain.network_fingertip).norm()),
      1e-4);
  // The person's own gesture: their eyes (the frame's head, at their root) through their
  // fingertip at frame 21, against their room's cup.
  const TrackingFrame last = frame_at(21, reach_hold_lower_z(21));
  const PointingError own =
      pointing_error({last.T_world_head.translation, last.index_tip[index(Hand::kRight)]},
                     watch.scene.room.objects[0].position);
  EXPECT_NEAR(s.person.horizontal_deg, own.horizontal_deg, 1e-4);
  EXPECT_NEAR(s.person.vertical_deg, own.vertical_deg, 1e-4);
  EXPECT_GT(s.person.horizontal_deg, 1.0);
  // Still from frame 13 to frame 21.
  EXPECT_NEAR(s.hold_s, 8 * kPeriod, 1e-9);

  Watch plain(8);  // no networks' chain given
  for (int k = 0; k <= 28; ++k) {
    plain.play(k, reach_hold_lower_z(k), k * kPeriod, k < 28 ? kCup : kNoTarget);
  }
  ASSERT_EQ(plain.observer.samples().size(), 1u);
  EXPECT_TRUE(std::isnan(plain.observer.samples()[0].network.horizontal_deg));
  EXPECT_TRUE(std::isnan(plain.observer.samples()[0].ik_fingertip_cm));
}

// A direction from the eyes: azimuth (degrees, + to the right of −Z) and elevation.
Vec3 direction(float azimuth_deg, float elevation_deg) {
  const float a = azimuth_deg * kRadPerDeg;
  const float e = elevation_deg * kRadPerDeg;
  return {std::sin(a) * std::cos(e), std::sin(e), -std::cos(a) * std::cos(e)};
}

// An avatar that turned its body toward a cup 80° to its right (presence/body_turn.h) points 3°
// short of it and 2.8° high: its errors are measured in its turned root, where the vertical error
// stays what it looks like; in the spot's unturned frame the same pointing reads 16° vertically
// (docs/decisions.md §81). The copy of the person is measured in its own, unturned root.
TEST(DeicticObserver, AnAvatarsErrorsAreMeasuredInItsTurnedRoot) {
  Watch watch(8);
  const Vec3 eyes = Vec3::Zero();
  watch.scene.room.objects[0].position = eyes + 2.5f * direction(80.0f, -12.4f);
  const Pose T_world_turned{yaw_rotation(-36.0f * kRadPerDeg), Vec3::Zero()};  // to its right
  watch.chain = {eyes, eyes + 0.6f * direction(77.0f, -9.6f), T_world_turned};
  for (int k = 0; k <= 28; ++k) {
    watch.play(k, reach_hold_lower_z(k), k * kPeriod, k < 28 ? kCup : kNoTarget);
  }
  ASSERT_EQ(watch.observer.samples().size(), 1u);
  const DeicticSample& s = watch.observer.samples()[0];
  const Vec3& cup = watch.scene.room.objects[0].position;
  const auto in = [](const Pose& T_world_root, const Vec3& p) {
    return transform_point(inverse(T_world_root), p);
  };
  const PointingError turned =
      pointing_error({in(T_world_turned, eyes), in(T_world_turned, watch.chain.fingertip)},
                     in(T_world_turned, cup));
  const PointingError spot = pointing_error({eyes, watch.chain.fingertip}, cup);
  EXPECT_NEAR(s.avatar.horizontal_deg, turned.horizontal_deg, 1e-3);
  EXPECT_NEAR(s.avatar.vertical_deg, turned.vertical_deg, 1e-3);
  EXPECT_NEAR(s.avatar.horizontal_deg, spot.horizontal_deg, 1e-3);  // a yaw leaves HE alone
  EXPECT_LT(s.avatar.vertical_deg, 5.0);
  EXPECT_GT(spot.vertical_deg, 12.0);
  // The copy stands on the spot unturned: its root is the copy's, identity here.
  const TrackingFrame last = frame_at(21, reach_hold_lower_z(21));
  const PointingError copy =
      pointing_error({watch.scene.copy.point(last.T_world_head.translation),
                      watch.scene.copy.point(last.index_tip[index(Hand::kRight)])},
                     cup);
  EXPECT_NEAR(s.copy.vertical_deg, copy.vertical_deg, 1e-3);
  EXPECT_NEAR(s.copy.horizontal_deg, copy.horizontal_deg, 1e-3);
}

}  // namespace
}  // namespace deixis::eval
