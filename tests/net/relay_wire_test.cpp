// The relay's messages (net/relay_wire.h, docs/relay.md): each one round-trips, and every rule a
// decoder enforces has a packet that breaks it and is refused with its reason. Every prefix of a
// valid message is refused too (nothing is read past its end).

#include <gtest/gtest.h>

#include <vector>

#include "net/relay_wire.h"

namespace deixis::net {
namespace {

std::vector<std::byte> buffer() {
  return std::vector<std::byte>(kMaxPacketBytes);
}

template <class M>
std::vector<std::byte> encoded(const M& m) {
  std::vector<std::byte> out = buffer();
  out.resize(encode(m, out));
  return out;
}

const std::vector<std::uint8_t> kParams = {'D', 'X', 'R', 'P', 1, 0};
const std::vector<std::uint8_t> kAnnounce = {9, 8, 7, 6, 5};

RelayEnter enter_message() {
  RelayEnter m;
  m.room = room_token("room");
  m.params = kParams;
  m.announce = kAnnounce;
  return m;
}

RelayEntered entered_message() {
  RelayEntered m;
  m.self = 4;
  m.params = kParams;
  m.count = 2;
  m.members[0] = {1, kAnnounce};
  m.members[1] = {3, {}};
  return m;
}

// Every strict prefix of a valid packet fails to decode.
template <class M>
void expect_prefixes_refused(const std::vector<std::byte>& packet) {
  for (std::size_t n = 0; n < packet.size(); ++n) {
    M m;
    EXPECT_FALSE(decode(std::span(packet).first(n), m).ok()) << "prefix of " << n << " bytes";
  }
}

TEST(RelayWire, RoomTokensAreFixedHashesOfTheName) {
  EXPECT_EQ(room_token("a"), room_token("a"));
  EXPECT_NE(room_token("a"), room_token("b"));
  EXPECT_NE(room_token(""), RoomToken{});
}

TEST(RelayWire, TypesSitAboveTheDirectProtocols) {
  for (int t = 0; t < 256; ++t) {
    const auto type = static_cast<std::uint8_t>(t);
    if (is_relay_type(type)) {
      EXPECT_GE(type, kRelayTypeFirst);
      EXPECT_LE(type, kRelayTypeLast);
      EXPECT_FALSE(is_known_type(type)) << "no direct-session type is a relay type";
    }
  }
}

TEST(RelayWire, WelcomeRoundTripsAndChecksMagicVersionAndRange) {
  RelayWelcome w;
  w.max_people = 8;
  const std::vector<std::byte> p = encoded(w);
  ASSERT_EQ(p.size(), kRelayWelcomeBytes);
  RelayWelcome back;
  ASSERT_TRUE(decode(p, back).ok());
  EXPECT_EQ(back.max_people, 8);
  expect_prefixes_refused<RelayWelcome>(p);

  std::vector<std::byte> bad = p;
  bad[2] = std::byte{'Z'};
  EXPECT_EQ(decode(bad, back).reason, DropReason::kBadMagic);
  bad = p;
  bad[5] = std::byte{kRelayVersion + 1};
  EXPECT_EQ(decode(bad, back).reason, DropReason::kWrongVersion);
  bad = p;
  bad.back() = std::byte{1};
  EXPECT_EQ(decode(bad, back).reason, DropReason::kOutOfRange);
  bad.back() = std::byte{kMaxRoomPeople + 1};
  EXPECT_EQ(decode(bad, back).reason, DropReason::kOutOfRange);
  bad = p;
  bad.push_back(std::byte{0});
  EXPECT_EQ(decode(bad, back).reason, DropReason::kTrailingBytes);
}

TEST(RelayWire, EnterRoundTripsAndBoundsItsLengths) {
  const std::vector<std::byte> p = encoded(enter_message());
  RelayEnter back;
  ASSERT_TRUE(decode(p, back).ok());
  EXPECT_EQ(back.room, room_token("room"));
  EXPECT_TRUE(std::equal(back.params.begin(), back.params.end(), kParams.begin(), kParams.end()));
  EXPECT_TRUE(
      std::equal(back.announce.begin(), back.announce.end(), kAnnounce.begin(), kAnnounce.end()));
  expect_prefixes_refused<RelayEnter>(p);

  // A params length above kRoomParamsMax, and one beyond the packet.
  std::vector<std::byte> bad = p;
  const std::size_t params_length_at = kRelayHeaderBytes + 32;
  bad[params_length_at] = std::byte{kRoomParamsMax + 1};
  EXPECT_EQ(decode(bad, back).reason, DropReason::kOutOfRange);
  bad[params_length_at] = std::byte{60};
  EXPECT_EQ(decode(bad, back).reason, DropReason::kLengthBeyondPacket);
  // Too large to encode at all.
  RelayEnter too_big = enter_message();
  const std::vector<std::uint8_t> long_announce(kAnnounceMax + 1, 1);
  too_big.announce = long_announce;
  std::vector<std::byte> out = buffer();
  EXPECT_EQ(encode(too_big, out), 0u);
}

TEST(RelayWire, EnteredRoundTripsAndRefusesBadOrRepeatedIds) {
  const std::vector<std::byte> p = encoded(entered_message());
  ASSERT_FALSE(p.empty());
  RelayEntered back;
  ASSERT_TRUE(decode(p, back).ok());
  EXPECT_EQ(back.self, 4);
  ASSERT_EQ(back.count, 2);
  EXPECT_EQ(back.members[0].id, 1);
  EXPECT_EQ(back.members[0].announce.size(), kAnnounce.size());
  EXPECT_EQ(back.members[1].id, 3);
  EXPECT_TRUE(back.members[1].announce.empty());
  expect_prefixes_refused<RelayEntered>(p);

  RelayEntered dup = entered_message();
  dup.members[1].id = 4;  // the newcomer's own id
  EXPECT_EQ(decode(encoded(dup), back).reason, DropReason::kDuplicateId);
  std::vector<std::byte> bad = p;
  bad[1] = std::byte{0};  // self = nobody
  EXPECT_EQ(decode(bad, back).reason, DropReason::kOutOfRange);
  bad[1] = std::byte{kAllMembers};
  EXPECT_EQ(decode(bad, back).reason, DropReason::kOutOfRange);
  bad = p;
  bad[3 + kParams.size()] = std::byte{kMaxRoomPeople};  // count above what a room holds
  EXPECT_EQ(decode(bad, back).reason, DropReason::kOutOfRange);
}

TEST(RelayWire, JoinedLeftRefusedAndKeepaliveRoundTrip) {
  RelayJoined j;
  j.member = {7, kAnnounce};
  RelayJoined jb;
  ASSERT_TRUE(decode(encoded(j), jb).ok());
  EXPECT_EQ(jb.member.id, 7);
  expect_prefixes_refused<RelayJoined>(encoded(j));

  RelayLeft l;
  l.id = 254;
  RelayLeft lb;
  ASSERT_TRUE(decode(encoded(l), lb).ok());
  EXPECT_EQ(lb.id, 254);
  std::vector<std::byte> bad = encoded(l);
  bad[1] = std::byte{255};
  EXPECT_EQ(decode(bad, lb).reason, DropReason::kOutOfRange);

  RelayRefused r;
  r.reason = RelayRefusal::kRoomFull;
  RelayRefused rb;
  ASSERT_TRUE(decode(encoded(r), rb).ok());
  EXPECT_EQ(rb.reason, RelayRefusal::kRoomFull);
  expect_prefixes_refused<RelayRefused>(encoded(r));
  bad = encoded(r);
  bad.back() = std::byte{kMaxRelayRefusal + 1};
  EXPECT_EQ(decode(bad, rb).reason, DropReason::kOutOfRange);
  // A refusal from another relay version still says why.
  bad = encoded(r);
  bad[5] = std::byte{9};
  ASSERT_TRUE(decode(bad, rb).ok());
  EXPECT_EQ(rb.reason, RelayRefusal::kRoomFull);

  std::vector<std::byte> k = buffer();
  k.resize(encode_keepalive(k));
  EXPECT_TRUE(decode_keepalive(k).ok());
  k.push_back(std::byte{0});
  EXPECT_EQ(decode_keepalive(k).reason, DropReason::kTrailingBytes);
}

TEST(RelayWire, ForwardsCarryOnePayloadOfBoundedSize) {
  const std::vector<std::byte> payload(100, std::byte{3});
  std::vector<std::byte> p = buffer();
  p.resize(encode_forward(kAllMembers, payload, p));
  ASSERT_EQ(p.size(), kRelayForwardHeaderBytes + payload.size());
  RelayForward f;
  ASSERT_TRUE(decode(p, f).ok());
  EXPECT_EQ(f.to, kAllMembers);
  EXPECT_EQ(f.payload.size(), payload.size());
  p[1] = std::byte{0};
  EXPECT_EQ(decode(p, f).reason, DropReason::kOutOfRange) << "to nobody";
  p.resize(2);
  p[1] = std::byte{5};
  EXPECT_EQ(decode(p, f).reason, DropReason::kTruncated) << "an empty payload";

  std::vector<std::byte> largest(kRelayPayloadMax + 1, std::byte{1});
  std::vector<std::byte> out = buffer();
  EXPECT_EQ(encode_forward(3, largest, out), 0u);
  largest[0] = static_cast<std::byte>(RelayType::kForward);
  largest[1] = std::byte{3};
  largest.resize(kRelayForwardHeaderBytes + kRelayPayloadMax + 1, std::byte{1});
  EXPECT_EQ(decode(largest, f).reason, DropReason::kOutOfRange) << "above kRelayPayloadMax";

  std::vector<std::byte> fw = buffer();
  fw.resize(encode_forwarded(9, payload, fw));
  RelayForwarded back;
  ASSERT_TRUE(decode(fw, back).ok());
  EXPECT_EQ(back.from, 9);
  fw[1] = std::byte{kAllMembers};
  EXPECT_EQ(decode(fw, back).reason, DropReason::kOutOfRange) << "from everyone";
  EXPECT_TRUE(
      relay_channel_allowed(static_cast<std::uint8_t>(RelayType::kForward), Channel::kTracking));
  EXPECT_FALSE(
      relay_channel_allowed(static_cast<std::uint8_t>(RelayType::kEnter), Channel::kTracking));
}

TEST(RelayWire, AnotherMessagesBytesAreNotTakenForThisOne) {
  const std::vector<std::byte> p = encoded(enter_message());
  RelayWelcome w;
  EXPECT_EQ(decode(p, w).reason, DropReason::kUnknownType);
  RelayEntered e;
  EXPECT_EQ(decode(p, e).reason, DropReason::kUnknownType);
  RelayForward f;
  EXPECT_EQ(decode(std::span<const std::byte>(), f).reason, DropReason::kEmpty);
}

}  // namespace
}  // namespace deixis::net
