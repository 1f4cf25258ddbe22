// A stable room allocates nothing per tick: three sealed members streaming to each other through
// the in-process relay (tests/net/room_fixture.h, whose slots are reused), with heartbeats, loss
// on one link and jitter on another, after warm-up — sending (sealed once for everyone), the
// relay callbacks, opening, the jitter buffers and playouts.

#include <gtest/gtest.h>

#include "allocation_counter.h"
#include "room_fixture.h"

namespace deixis::net {
namespace {

TEST(RoomHotPath, AStableSealedRoomAllocatesNothingPerTick) {
  testing::RoomHarness room;
  for (const char* site : {"A", "B", "C"}) {
    room.add(testing::room_config(site, "pw"));
    room.run_until([] { return false; }, 0.1);
  }
  ASSERT_TRUE(room.run_until([&] { return room.everyone_sees({0, 1, 2}, 2); }, 2.0));
  room.endpoints[1]->uplink.tracking_loss = 0.05;
  room.endpoints[2]->uplink.jitter = 0.010;
  std::vector<std::vector<TrackingFrame>> frames(3);
  for (std::size_t i = 0; i < 3; ++i) {
    const Vec3 root = room.members[i]->config().hello.avatar.body.T_world_root.translation;
    for (std::uint32_t t = 0; t < 600; ++t) {
      frames[i].push_back(testing::moving_frame(t, root));
    }
  }
  std::uint64_t played = 0;
  const auto tick = [&](std::uint32_t t) {
    for (std::size_t i = 0; i < 3; ++i) {
      room.members[i]->send_tracking(frames[i][t], t * testing::kTick);
    }
    for (int k = 0; k < 3; ++k) {
      room.step(testing::kTick / 3);
    }
    for (auto& m : room.members) {
      for (const MemberId person : m->people()) {
        for (Playout p = m->next_playout(person, room.now);
             p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed;
             p = m->next_playout(person, room.now)) {
          played += p.kind == PlayoutKind::kFrame ? 1 : 0;
        }
      }
    }
    RoomEvent e;
    while (room.members[0]->next_event(e)) {
    }
  };
  for (std::uint32_t t = 0; t < 300; ++t) {
    tick(t);  // warm-up: target maps, the relay's slots, log lines
  }
  const std::uint64_t heartbeats =
      room.members[0]->person_stats(room.members[1]->self())->heartbeats;
  testing::AllocationCounter counter;
  for (std::uint32_t t = 300; t < 600; ++t) {
    tick(t);
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(played, 6u * 280u);
  EXPECT_GT(room.members[0]->person_stats(room.members[1]->self())->heartbeats, heartbeats + 15);
  EXPECT_EQ(room.members[0]->people().size(), 2u);
}

}  // namespace
}  // namespace deixis::net
