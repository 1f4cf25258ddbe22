// The tracking hot path allocates nothing: encoding and decoding a frame, sealing and opening it,
// the jitter buffer, and two sessions streaming to each other (sealed, with heartbeats, loss,
// jitter and duplicates) over the simulated network after warm-up. ENet's own packet allocation
// is outside this proof (enet_link.h says so).

#include <gtest/gtest.h>

#include "allocation_counter.h"
#include "net/jitter_buffer.h"
#include "net/sealing.h"
#include "net/tracking_codec.h"
#include "session_pair.h"

namespace deixis::net {
namespace {

TEST(NetHotPath, EncodeDecodeSealOpenAndTheJitterBufferAllocateNothing) {
  const Vec3 root(0.3f, 1.6f, -1.0f);
  std::vector<TrackingFrame> frames;
  for (std::uint32_t i = 0; i < 1000; ++i) {
    frames.push_back(testing::moving_frame(i, root));
  }
  Key key{};
  key.fill(std::byte{9});
  PacketSealer sealer(key);
  PacketOpener opener(key);
  JitterBuffer buffer;
  std::array<std::byte, kTrackingBytes> plain{};
  std::array<std::byte, kTrackingBytes + kSealOverheadBytes> sealed{};
  std::array<std::byte, kTrackingBytes> scratch{};
  TrackingMessage back;
  std::uint64_t played = 0;
  testing::AllocationCounter counter;
  for (std::uint32_t i = 0; i < 1000; ++i) {
    ASSERT_EQ(encode_tracking({i, frames[i]}, root, plain).bytes, kTrackingBytes);
    const std::size_t n = sealer.seal(Channel::kTracking, plain, sealed);
    std::span<const std::byte> opened;
    ASSERT_TRUE(opener.open(Channel::kTracking, std::span(sealed).first(n), scratch, opened).ok());
    ASSERT_TRUE(decode_tracking(opened, root, back).ok());
    buffer.push(back.sequence, back.frame, back.frame.time + 0.01);
    played += buffer.pop(back.frame.time + 0.01).kind == PlayoutKind::kFrame ? 1 : 0;
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_GT(played, 900u);
}

TEST(NetHotPath, StreamingSessionsAllocateNothing) {
  LinkConditions c;
  c.loss = 0.05;
  c.jitter = 0.005;
  c.duplicate = 0.05;
  testing::SessionPair pair(c, 42, "pw", "pw");
  ASSERT_TRUE(pair.connect());
  const Vec3 host_root = pair.host.config().hello.avatar.body.T_world_root.translation;
  const Vec3 joiner_root = pair.joiner.config().hello.avatar.body.T_world_root.translation;
  std::vector<TrackingFrame> host_frames, joiner_frames;
  for (std::uint32_t i = 0; i < 900; ++i) {
    host_frames.push_back(testing::moving_frame(i, host_root));
    joiner_frames.push_back(testing::moving_frame(i, joiner_root));
  }
  std::uint64_t played = 0;
  const auto tick = [&](std::uint32_t i) {
    pair.host.send_tracking(host_frames[i]);
    pair.joiner.send_tracking(joiner_frames[i]);
    for (int k = 0; k < 3; ++k) {
      pair.step(testing::kTick / 3);
    }
    for (Session* s : {&pair.host, &pair.joiner}) {
      for (Playout p = s->next_frame(pair.now);
           p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed;
           p = s->next_frame(pair.now)) {
        played += p.kind == PlayoutKind::kFrame ? 1 : 0;
      }
    }
  };
  for (std::uint32_t i = 0; i < 300; ++i) {
    tick(i);  // warm-up: the first target maps, log lines, and so on
  }
  const std::uint64_t heartbeats_before = pair.host.stats().packets_received;
  testing::AllocationCounter counter;
  for (std::uint32_t i = 300; i < 900; ++i) {
    tick(i);  // 20 s: 600 frames each way, 40 heartbeats, about 60 duplicates rejected
  }
  EXPECT_EQ(counter.count(), 0u);
  {
    // Positive control: the counter does see this binary's allocations (a new target map
    // allocates its encoding, and the peer its decoded copy).
    testing::AllocationCounter control;
    pair.host.set_target_map(testing::make_target_map("A", 4));
    pair.step();
    EXPECT_GT(control.count(), 0u);
  }
  EXPECT_TRUE(pair.both_streaming());
  EXPECT_GT(played, 1500u);
  EXPECT_GT(pair.host.stats().packets_received - heartbeats_before, 600u);
  EXPECT_GT(pair.host.drops()[DropReason::kReplayed], 0u) << "the drop path ran too";
}

}  // namespace
}  // namespace deixis::net
