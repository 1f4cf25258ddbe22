// The relay's forwarding allocates nothing once its rooms are stable (net/relay_server.h): a room
// of eight members, each sending tracking-sized forwards to everyone at 30 Hz with keepalives and
// a unicast now and then, over an in-process link with fixed storage. ENet's own per-packet
// allocation is outside this proof (enet_link.h says so).

#include <gtest/gtest.h>

#include <array>

#include "allocation_counter.h"
#include "net/relay_server.h"
#include "net/relay_wire.h"

namespace deixis::net {
namespace {

// A many-peer link whose events the test queues and whose sends it counts: fixed storage only.
class FakeLink : public Link {
 public:
  static constexpr std::size_t kQueue = 512;
  static constexpr std::size_t kBytes = 256;

  PeerId connect() override { return kNoPeer; }
  void disconnect(PeerId, std::uint32_t) override { ++disconnects; }
  bool send(PeerId peer, Channel channel, std::span<const std::byte> packet) override {
    if (peer == full_peer && channel == Channel::kReliable) {
      return false;  // its queue is full
    }
    ++sent[static_cast<std::size_t>(channel)];
    sent_bytes += packet.size();
    return true;
  }
  LinkEvent next_event(std::uint32_t) override {
    if (head_ == tail_) {
      return {};
    }
    const Item& it = queue_[head_++ % kQueue];
    switch (it.kind) {
      case LinkEvent::Kind::kConnected:
        return LinkEvent::connected(it.peer);
      case LinkEvent::Kind::kDisconnected:
        return LinkEvent::disconnected(it.peer, 0);
      default:
        return LinkEvent::received(it.peer, it.channel, std::span(it.bytes).first(it.size));
    }
  }
  std::string_view peer_name(PeerId) const override { return "fake"; }
  std::uint32_t peer_address(PeerId peer) const override { return peer; }
  std::uint32_t round_trip_ms(PeerId) const override { return 1; }

  void push_connected(PeerId peer) {
    push(LinkEvent::Kind::kConnected, peer, Channel::kReliable, {});
  }
  void push_packet(PeerId peer, Channel channel, std::span<const std::byte> bytes) {
    push(LinkEvent::Kind::kReceived, peer, channel, bytes);
  }

  PeerId full_peer = kNoPeer;  // a peer whose reliable sends are refused
  std::array<std::uint64_t, 2> sent{};
  std::uint64_t sent_bytes = 0;
  std::uint64_t disconnects = 0;

 private:
  struct Item {
    LinkEvent::Kind kind = LinkEvent::Kind::kNone;
    PeerId peer = kNoPeer;
    Channel channel = Channel::kReliable;
    std::array<std::byte, kBytes> bytes{};
    std::size_t size = 0;
  };
  void push(LinkEvent::Kind kind, PeerId peer, Channel channel, std::span<const std::byte> bytes) {
    Item& it = queue_[tail_++ % kQueue];
    it.kind = kind;
    it.peer = peer;
    it.channel = channel;
    it.size = std::min(bytes.size(), kBytes);
    std::copy_n(bytes.begin(), it.size, it.bytes.begin());
  }
  std::array<Item, kQueue> queue_{};
  std::size_t head_ = 0;
  std::size_t tail_ = 0;
};

// Peers 1 … people connect and enter the room `name`.
void fill_room(FakeLink& link, RelayServer& relay, PeerId people, const char* name) {
  for (PeerId p = 1; p <= people; ++p) {
    link.push_connected(p);
  }
  relay.service(0.0);
  const std::array<std::uint8_t, 16> announce{};
  RelayEnter enter;
  enter.room = room_token(name);
  enter.announce = announce;
  std::array<std::byte, FakeLink::kBytes> enter_bytes{};
  const std::size_t enter_size = encode(enter, enter_bytes);
  for (PeerId p = 1; p <= people; ++p) {
    link.push_packet(p, Channel::kReliable, std::span(enter_bytes).first(enter_size));
  }
  relay.service(0.0);
}

TEST(RelayHotPath, ForwardingInAStableRoomAllocatesNothing) {
  FakeLink link;
  RelayServer relay(link, RelayServerConfig{});
  constexpr PeerId kPeople = 8;
  double now = 0.0;
  fill_room(link, relay, kPeople, "allocation");
  ASSERT_EQ(relay.members_in(room_token("allocation")), kPeople);

  std::array<std::byte, 100> payload{};  // a sealed tracking packet is about this size
  std::array<std::byte, kRelayForwardHeaderBytes + 100> to_all{};
  std::array<std::byte, kRelayForwardHeaderBytes + 100> to_one{};
  encode_forward(kAllMembers, payload, to_all);
  encode_forward(3, payload, to_one);
  std::array<std::byte, kRelayKeepaliveBytes> keepalive{};
  encode_keepalive(keepalive);
  const auto tick = [&](int i) {
    now += 1.0 / 30.0;
    for (PeerId p = 1; p <= kPeople; ++p) {
      link.push_packet(p, Channel::kTracking, to_all);
      if (i % 15 == 0) {
        link.push_packet(p, Channel::kReliable, keepalive);
        link.push_packet(p, Channel::kReliable, to_one);
      }
    }
    relay.service(now);
  };
  for (int i = 0; i < 60; ++i) {
    tick(i);  // warm-up
  }
  const std::uint64_t sent_before = link.sent[1];
  testing::AllocationCounter counter;
  for (int i = 0; i < 600; ++i) {
    tick(i);
  }
  EXPECT_EQ(counter.count(), 0u);
  EXPECT_EQ(link.sent[1] - sent_before, 600u * kPeople * (kPeople - 1)) << "every forward went out";
  EXPECT_EQ(relay.drops().total, 0u);
  EXPECT_EQ(relay.stats().floods_cut, 0u);
  EXPECT_EQ(link.disconnects, 0u);
  EXPECT_GT(relay.stats().keepalives_sent + relay.stats().forwards_out, 0u);
}

// Not a hot-path test, but it needs this link: a member whose reliable queue is full when a
// reliable copy is due is let go (and the others told), rather than silently miss a message.
TEST(RelayHotPath, AMemberThatCannotTakeAReliableCopyIsLetGo) {
  FakeLink link;
  RelayServer relay(link, RelayServerConfig{});
  fill_room(link, relay, 3, "behind");
  ASSERT_EQ(relay.members_in(room_token("behind")), 3u);
  link.full_peer = 2;
  std::array<std::byte, 8> payload{};
  std::array<std::byte, kRelayForwardHeaderBytes + 8> to_all{};
  encode_forward(kAllMembers, payload, to_all);
  link.push_packet(1, Channel::kTracking, to_all);
  relay.service(0.1);
  EXPECT_EQ(relay.members_in(room_token("behind")), 3u) << "a lost tracking copy is no reason";
  const std::uint64_t reliable_before = link.sent[0];
  link.push_packet(1, Channel::kReliable, to_all);
  relay.service(0.2);
  EXPECT_EQ(relay.members_in(room_token("behind")), 2u);
  EXPECT_EQ(relay.stats().members_behind, 1u);
  EXPECT_EQ(link.disconnects, 1u);
  // Peer 3 got its copy and the news that member 2 left.
  EXPECT_EQ(link.sent[0] - reliable_before, 3u) << "one copy to 3, and member left to 1 and 3";
}

}  // namespace
}  // namespace deixis::net
