// Person targets on the wire (docs/protocol.md §4.8): a tracking frame's head and hand targets may
// name a person of a room, 1,000,001–1,000,254 (core/target_map.h, person_target); the ids around
// that range stay refused.

#include <gtest/gtest.h>

#include "core/target_map.h"
#include "net/tracking_codec.h"
#include "net/wire.h"
#include "net_fixtures.h"

namespace deixis::net {
namespace {

TEST(PersonTargetsOnTheWire, RoundTripForEveryPersonId) {
  const Vec3 root(0.3f, 1.6f, -1.0f);
  std::array<std::byte, kTrackingBytes> bytes{};
  for (const PersonId p : {PersonId{1}, PersonId{2}, PersonId{77}, kMaxPersonId}) {
    TrackingMessage m{7, testing::moving_frame(7, root)};
    m.frame.head_target = person_target(p);
    m.frame.hand_target = person_target(static_cast<PersonId>(kMaxPersonId + 1 - p));
    ASSERT_EQ(encode_tracking(m, root, bytes).bytes, kTrackingBytes);
    TrackingMessage back;
    ASSERT_TRUE(decode_tracking(bytes, root, back).ok()) << int(p);
    EXPECT_EQ(back.frame.head_target, person_target(p));
    EXPECT_EQ(target_person(back.frame.hand_target), kMaxPersonId + 1 - p);
    EXPECT_LT((back.frame.head_target_position - m.frame.head_target_position).norm(), 2e-3f);
  }
}

TEST(PersonTargetsOnTheWire, IdsBeyondThePeopleAreNotSentAndRefused) {
  const Vec3 root(0.3f, 1.6f, -1.0f);
  std::array<std::byte, kTrackingBytes> bytes{};
  for (const TargetId id : {TargetId{1'000'255}, TargetId{2'000'000}, TargetId{-2}}) {
    TrackingMessage m{1, testing::moving_frame(1, root)};
    m.frame.head_target = id;
    ASSERT_EQ(encode_tracking(m, root, bytes).bytes, kTrackingBytes);
    TrackingMessage back;
    ASSERT_TRUE(decode_tracking(bytes, root, back).ok());
    EXPECT_EQ(back.frame.head_target, kNoTarget) << id;  // the sender sends no target
    // Written into the packet by hand, the receiver refuses it.
    WireWriter w{std::span<std::byte>(bytes).subspan(62, 4)};
    w.i32(id);
    EXPECT_EQ(decode_tracking(bytes, root, back).reason, DropReason::kOutOfRange) << id;
  }
  // The last object id and the first and last person ids are all accepted.
  for (const TargetId id : {TargetId{1'000'000}, person_target(1), person_target(kMaxPersonId)}) {
    TrackingMessage m{1, testing::moving_frame(1, root)};
    m.frame.hand_target = id;
    encode_tracking(m, root, bytes);
    TrackingMessage back;
    ASSERT_TRUE(decode_tracking(bytes, root, back).ok());
    EXPECT_EQ(back.frame.hand_target, id);
  }
}

}  // namespace
}  // namespace deixis::net
