// Target selection for tracked users (gesture/target_selection.h): the gaze picks the head
// target, the eye–fingertip ray or a touch picks the hand target, the hand follows the eyes while
// it designates nothing, hysteresis keeps close objects from flickering, and untracked parts keep
// their targets.

#include "gesture/target_selection.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace deixis {
namespace {

constexpr float kDeg = 3.14159265f / 180.0f;
const Vec3 kHead(0.0f, 1.6f, 0.0f);

// A direction `azimuth` degrees to the left of −Z and `elevation` up.
Vec3 direction(float azimuth, float elevation) {
  return Vec3(-std::sin(azimuth * kDeg) * std::cos(elevation * kDeg), std::sin(elevation * kDeg),
              -std::cos(azimuth * kDeg) * std::cos(elevation * kDeg));
}

TargetObject sphere(TargetId id, const Vec3& position) {
  TargetObject o;
  o.id = id;
  o.name = std::to_string(id);
  o.position = position;
  o.size = Vec3::Constant(0.1f);
  return o;
}

// Three objects 2 m from the head at 30° to the left, straight ahead and 30° to the right,
// all 10° below eye level; the other person 60° to the right.
struct Room {
  TargetMap map;
  Vec3 partner = kHead + 2.0f * direction(-60, 0);
  Room() {
    map.site.assign(1, 'A');  // not = "A": GCC 12 -O3 reports a false -Wrestrict there
    map.objects = {sphere(1, kHead + 2.0f * direction(30, -10)),
                   sphere(2, kHead + 2.0f * direction(0, -10)),
                   sphere(3, kHead + 2.0f * direction(-30, -10))};
  }
};

// The user looking along `gaze`, the right index fingertip at `tip`, hand at rest when null.
TrackingFrame user(const Vec3& gaze, const Vec3* tip = nullptr) {
  TrackingFrame f;
  f.T_world_head = Pose{Mat3::Identity(), kHead};
  f.gaze = gaze.normalized();
  f.index_tip[index(Hand::kRight)] = tip != nullptr ? *tip : Vec3(0.2f, 0.85f, 0.0f);
  f.valid = tracked::kAll;
  return f;
}

// Selects the same frame `ticks` times, as a held pose is over that many ticks.
TrackingFrame held(TargetSelector& selector, const TrackingFrame& frame, const Room& room,
                   int ticks) {
  TrackingFrame f = frame;
  for (int i = 0; i < ticks; ++i) {
    f = frame;
    selector.select(f, room.map, room.partner);
  }
  return f;
}

TEST(TargetSelection, GazePicksTheHeadTargetAndTheRestingHandFollowsIt) {
  const Room room;
  TargetSelector selector;
  TrackingFrame f = user(direction(29, -9));
  selector.select(f, room.map, room.partner);
  EXPECT_EQ(f.head_target, 1);
  EXPECT_EQ(f.hand_target, 1);  // the hand hangs down: it designates nothing yet
  EXPECT_TRUE(f.head_target_position.isApprox(room.map.objects[0].position));
  EXPECT_TRUE(f.hand_target_position.isApprox(room.map.objects[0].position));
}

TEST(TargetSelection, TheEyeFingertipRayPicksTheHandTarget) {
  const Room room;
  TargetSelector selector;
  const Vec3 tip = kHead + 0.6f * direction(-31, -11);  // arm out toward object 3
  const TrackingFrame pointing = user(direction(0, -10), &tip);
  // The eyes are on object 2: pointing at 3 counts once held for the dwell, not on the way.
  TrackingFrame f = held(selector, pointing, room, selector.config.dwell_ticks - 1);
  EXPECT_EQ(f.hand_target, 2);
  f = held(selector, pointing, room, 1);
  EXPECT_EQ(f.head_target, 2);
  EXPECT_EQ(f.hand_target, 3);
  EXPECT_TRUE(f.hand_target_position.isApprox(room.map.objects[2].position));
}

TEST(TargetSelection, ATouchPicksTheTouchedObjectWhateverTheRay) {
  Room room;
  room.map.objects.push_back(sphere(4, Vec3(0.35f, 1.0f, -0.3f)));  // low, beside the body
  TargetSelector selector;
  const Vec3 tip = Vec3(0.35f, 1.0f, -0.3f) + Vec3(0.0f, 0.08f, 0.0f);  // 3 cm above its surface
  const TrackingFrame f = held(selector, user(direction(0, -10), &tip), room, 6);
  EXPECT_EQ(f.hand_target, 4);
  // Brushing past it (0.1 s) while looking elsewhere is not touching it.
  TargetSelector passing;
  EXPECT_EQ(held(passing, user(direction(0, -10), &tip), room, 3).hand_target, 2);
}

TEST(TargetSelection, AHandNearTheBodyDoesNotPointWhateverItsRay) {
  const Room room;
  TargetSelector selector;
  // Gesturing in front of the chest, the eye–fingertip ray happens to cross object 3.
  const Vec3 tip = kHead + 0.3f * direction(-30, -10);
  const TrackingFrame f = held(selector, user(direction(0, -10), &tip), room, 10);
  EXPECT_EQ(f.hand_target, 2);  // it follows the eyes
}

TEST(TargetSelection, LookingAtTheOtherPersonSelectsThem) {
  const Room room;
  TargetSelector selector;
  selector.head_target = 2;
  TrackingFrame f = user(direction(-60, 0));
  selector.select(f, room.map, room.partner);
  EXPECT_EQ(f.head_target, kPartnerTarget);
  EXPECT_TRUE(f.head_target_position.isApprox(room.partner));
}

TEST(TargetSelection, NothingNearTheGazeKeepsTheHeadTarget) {
  const Room room;
  TargetSelector selector;
  TrackingFrame f = user(direction(0, -10));
  selector.select(f, room.map, room.partner);
  ASSERT_EQ(f.head_target, 2);
  TrackingFrame up = user(direction(15, 40));  // at the ceiling
  selector.select(up, room.map, room.partner);
  EXPECT_EQ(up.head_target, 2);
}

TEST(TargetSelection, CloseObjectsDoNotFlickerButAClearMoveSwitches) {
  Room room;
  room.map.objects = {sphere(1, kHead + 2.0f * direction(0, 0)),
                      sphere(2, kHead + 2.0f * direction(3, 0))};
  TargetSelector selector;
  TrackingFrame f = user(direction(0, 0));
  selector.select(f, room.map, room.partner);
  ASSERT_EQ(f.head_target, 1);
  // Gaze drifts to 1.9°: object 2 is now nearer (1.1° vs 1.9°) but not by the 2° margin.
  TrackingFrame drift = user(direction(1.9f, 0));
  selector.select(drift, room.map, room.partner);
  EXPECT_EQ(drift.head_target, 1);
  // Gaze on object 2: 0° vs 3°, a clear move.
  TrackingFrame moved = user(direction(3, 0));
  selector.select(moved, room.map, room.partner);
  EXPECT_EQ(moved.head_target, 2);
}

TEST(TargetSelection, WithoutEyeTrackingTheHeadForwardIsTheGaze) {
  const Room room;
  TargetSelector selector;
  TrackingFrame f = user(direction(0, 0));
  f.valid = tracked::kHead | tracked::kRightHand;
  f.gaze = direction(30, -10);  // not tracked: must not be read
  f.T_world_head.rotation =
      (Eigen::AngleAxisf(-30 * kDeg, Vec3::UnitY()) * Eigen::AngleAxisf(-10 * kDeg, Vec3::UnitX()))
          .toRotationMatrix();
  selector.select(f, room.map, room.partner);
  EXPECT_EQ(f.head_target, 3);
}

TEST(TargetSelection, AnUntrackedHandKeepsItsTarget) {
  const Room room;
  TargetSelector selector;
  const Vec3 tip = kHead + 0.6f * direction(30, -10);
  const TrackingFrame f = held(selector, user(direction(0, -10), &tip), room, 6);
  ASSERT_EQ(f.hand_target, 1);
  TrackingFrame lost = user(direction(-30, -10));
  lost.valid = tracked::kHead | tracked::kGaze;
  selector.select(lost, room.map, room.partner);
  EXPECT_EQ(lost.head_target, 3);
  EXPECT_EQ(lost.hand_target, 1);
}

TEST(TargetSelection, TheLeftHandWhenItIsTheDeicticOne) {
  const Room room;
  TargetSelector selector;
  selector.config.deictic_hand = Hand::kLeft;
  TrackingFrame f = user(direction(0, -10));
  f.index_tip[index(Hand::kLeft)] = kHead + 0.6f * direction(30, -10);
  f.index_tip[index(Hand::kRight)] = kHead + 0.6f * direction(-30, -10);  // not the deictic hand
  EXPECT_EQ(held(selector, f, room, 6).hand_target, 1);
}

// A room of several people: person 7's avatar 45° to the left, person 9's 45° to the right, the
// user (person 3) among them; no "other person" (kPartnerTarget) is a candidate.
struct Gathering {
  Room room;
  std::array<PersonTarget, 3> people = {PersonTarget{7, kHead + 2.0f * direction(45, 0)},
                                        PersonTarget{9, kHead + 2.0f * direction(-45, 0)},
                                        PersonTarget{3, kHead}};
  SelectionCandidates candidates() const { return {&room.map, nullptr, people, 3}; }
};

TEST(TargetSelection, LookingAtAnAvatarSelectsThatPerson) {
  const Gathering g;
  TargetSelector selector;
  TrackingFrame f = user(direction(44, 1));
  selector.select(f, g.candidates());
  EXPECT_EQ(f.head_target, person_target(7));
  EXPECT_EQ(f.hand_target, person_target(7));  // the resting hand follows the eyes
  EXPECT_TRUE(f.head_target_position.isApprox(g.people[0].head));
  TrackingFrame other = user(direction(-46, 0));
  selector.select(other, g.candidates());
  EXPECT_EQ(other.head_target, person_target(9));
  EXPECT_TRUE(other.head_target_position.isApprox(g.people[1].head));
}

TEST(TargetSelection, PointingAtAnAvatarSelectsThatPerson) {
  const Gathering g;
  TargetSelector selector;
  const Vec3 tip = kHead + 0.6f * direction(-45, 0);
  const TrackingFrame pointing = user(direction(-45, 0), &tip);
  TrackingFrame f = pointing;
  selector.select(f, g.candidates());
  EXPECT_EQ(f.hand_target, person_target(9));  // at once: the eyes are on them
  // Objects stay candidates beside people.
  TrackingFrame object = user(direction(0, -10));
  selector.select(object, g.candidates());
  EXPECT_EQ(object.head_target, 2);
}

TEST(TargetSelection, TheUserIsNeverTheirOwnTargetAndAPersonWhoLeftIsDropped) {
  Gathering g;
  // The own user's head is a PersonTarget of the room (for the avatars), never a candidate: a gaze
  // that passes near nothing designates nothing (a room has no "other person"), its point ahead
  // of the head.
  TargetSelector selector;
  TrackingFrame f = user(direction(0, 60));
  selector.select(f, g.candidates());
  EXPECT_EQ(f.head_target, kNoTarget);
  EXPECT_EQ(f.hand_target, kNoTarget);
  EXPECT_LT((f.head_target_position - nothing_designated_point(f.T_world_head)).norm(), 1e-6f);
  TrackingFrame at7 = user(direction(45, 0));
  selector.select(at7, g.candidates());
  ASSERT_EQ(at7.head_target, person_target(7));
  // Person 7 leaves: the target is no candidate any more (angle ∞), so the next gaze on anything
  // takes over without the hysteresis margin.
  g.people[0].id = 8;
  TrackingFrame near_old = user(direction(0, -10));
  selector.select(near_old, g.candidates());
  EXPECT_EQ(near_old.head_target, 2);
  // Whoever the eyes were on leaves while they rest on nothing: nothing is designated, not a
  // person who is gone (whose id other rooms might still place).
  TrackingFrame at8 = user(direction(45, 0));
  selector.select(at8, g.candidates());
  ASSERT_EQ(at8.head_target, person_target(8));
  g.people[0].id = 11;
  TrackingFrame away = user(direction(0, 60));
  selector.select(away, g.candidates());
  EXPECT_EQ(away.head_target, kNoTarget);
}

}  // namespace
}  // namespace deixis
