// A table of malformed packets. Each is rejected by its decoder with the stated reason, and, fed
// to a streaming session, is counted under that reason and dropped while the session streams on.

#include <gtest/gtest.h>

#include <cstring>
#include <functional>

#include "net/avatar_transfer.h"
#include "net/messages.h"
#include "net/tracking_codec.h"
#include "net_fixtures.h"
#include "session_pair.h"

namespace deixis::net {
namespace {

using Bytes = std::vector<std::byte>;

const Vec3 kRoot = testing::make_hello("A").avatar.body.T_world_root.translation;

Bytes hello_bytes() {
  Bytes b;
  EXPECT_TRUE(encode(testing::make_hello("A"), b).ok());
  return b;
}
Bytes map_bytes(int objects = 2) {
  Bytes b;
  EXPECT_TRUE(encode(testing::make_target_map("A", objects), b).ok());
  return b;
}
Bytes tracking_bytes() {
  Bytes b(kTrackingBytes);
  encode_tracking({7, testing::moving_frame(7, kRoot)}, kRoot, b);
  return b;
}
Bytes welcome_bytes() {
  Welcome w;
  w.auth = AuthMode::kPassphrase;
  w.kdf = {2, 65536};
  Bytes b;
  encode(w, b);
  return b;
}
Bytes join_bytes() {
  Bytes b;
  encode(Join{}, b);
  return b;
}
Bytes accept_bytes() {
  Bytes b;
  encode(Accept{}, b);
  return b;
}
Bytes heartbeat_bytes() {
  Bytes b(kHeartbeatBytes);
  encode(Heartbeat{3}, b);
  return b;
}
Bytes bye_bytes() {
  Bytes b(kByeBytes);
  encode(Bye{}, b);
  return b;
}

Bytes avatar_request_bytes() {
  Bytes b(kAvatarRequestBytes);
  encode(AvatarRequest{}, b);
  return b;
}
Bytes avatar_data_bytes() {
  const Bytes chunk(100, std::byte{7});
  Bytes b(kAvatarDataHeaderBytes + chunk.size());
  encode(AvatarData{{}, 1000, 0, chunk}, b);
  return b;
}

Bytes prefix(const Bytes& b, std::size_t n) {
  return Bytes(b.begin(), b.begin() + static_cast<std::ptrdiff_t>(n));
}
Bytes with(Bytes b, const std::function<void(Bytes&)>& change) {
  change(b);
  return b;
}
void put_f32(Bytes& b, std::size_t at, float v) {
  std::memcpy(b.data() + at, &v, 4);
}
void put_u32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) {
    b[at + i] = static_cast<std::byte>((v >> (8 * i)) & 0xFF);
  }
}
void put_u16(Bytes& b, std::size_t at, std::uint16_t v) {
  b[at] = static_cast<std::byte>(v & 0xFF);
  b[at + 1] = static_cast<std::byte>(v >> 8);
}

// Offsets in hello_bytes(): type 0, version 1, site length 3, site "A" 4, model length 5, model
// "default" 6..12, height 13, arm 17, hand 21, root position 22, root rotation 34, wrists 50.
constexpr std::size_t kHeight = 13, kArm = 17, kHand = 21, kRootRotation = 34;
// Offsets in map_bytes(): type 0, site length 1, site "A" 2, count 3, first object at 5: id 5,
// kind 9, name length 10, name "object 1 Jüpiter" (17 bytes) 11, position 28, size 40.
constexpr std::size_t kCount = 3, kId = 5, kKind = 9, kNameLength = 10, kPosition = 28, kSize = 40,
                      kSecondId = 5 + 4 + 1 + 1 + 17 + 24;

struct Case {
  const char* name;
  Channel channel;
  Bytes packet;
  DropReason decoder;  // what the message's decoder says (kNone: no decoder applies)
  DropReason session;  // what a streaming, open session counts
};

std::vector<Case> cases() {
  const Bytes t = tracking_bytes();
  const Bytes h = hello_bytes();
  const Bytes m = map_bytes();
  const auto R = Channel::kReliable;
  const auto T = Channel::kTracking;
  using D = DropReason;
  return {
      {"empty", T, {}, D::kNone, D::kEmpty},
      {"unknown type", R, {std::byte{0x7F}, std::byte{1}}, D::kNone, D::kUnknownType},
      {"tracking on the reliable channel", R, t, D::kNone, D::kWrongChannel},
      {"hello on the tracking channel", T, h, D::kNone, D::kWrongChannel},
      {"tracking truncated", T, prefix(t, t.size() - 1), D::kTruncated, D::kTruncated},
      {"tracking type byte only", T, prefix(t, 1), D::kTruncated, D::kTruncated},
      {"tracking with a trailing byte", T, with(t, [](Bytes& b) { b.push_back(std::byte{0}); }),
       D::kTrailingBytes, D::kTrailingBytes},
      {"tracking unknown validity bits", T, with(t, [](Bytes& b) { b[9] |= std::byte{0x10}; }),
       D::kOutOfRange, D::kOutOfRange},
      {"tracking head target id too large", T, with(t, [](Bytes& b) { put_u32(b, 62, 1'000'255); }),
       D::kOutOfRange, D::kOutOfRange},
      {"tracking hand target id below -1", T, with(t, [](Bytes& b) { put_u32(b, 66, 0xFFFFFFFE); }),
       D::kOutOfRange, D::kOutOfRange},
      {"tracking head rotation not a unit quaternion", T,
       with(t,
            [](Bytes& b) {
              // Every component at 1/√2 (32766): |v|² = 1.5.
              put_u16(b, 16, 0x7FFE);
              put_u32(b, 18, 0x1FFFBFFF);
            }),
       D::kOutOfRange, D::kOutOfRange},
      {"tracking rotation component 32767 (never sent)", T,
       with(t,
            [](Bytes& b) {
              put_u16(b, 16, 0x7FFF);
              put_u32(b, 18, 0x60000000);  // index 3; a = b = 0, c = 32767
            }),
       D::kOutOfRange, D::kOutOfRange},
      {"tracking head position -32768 mm (never sent)", T,
       with(t, [](Bytes& b) { put_u16(b, 10, 0x8000); }), D::kOutOfRange, D::kOutOfRange},
      {"tracking rotation with the reserved bit", T,
       with(t, [](Bytes& b) { b[37] |= std::byte{0x80}; }), D::kOutOfRange, D::kOutOfRange},
      {"hello wrong protocol version", R,
       with(h, [](Bytes& b) { put_u16(b, 1, kProtocolVersion + 1); }), D::kWrongVersion,
       D::kWrongVersion},
      {"hello truncated in the body", R, prefix(h, kArm + 2), D::kTruncated, D::kTruncated},
      {"hello site length beyond the packet", R, with(h, [](Bytes& b) { b[3] = std::byte{200}; }),
       D::kLengthBeyondPacket, D::kLengthBeyondPacket},
      {"hello height NaN", R, with(h, [](Bytes& b) { put_f32(b, kHeight, std::nanf("")); }),
       D::kNonFinite, D::kNonFinite},
      {"hello height infinite", R, with(h, [](Bytes& b) { put_f32(b, kHeight, INFINITY); }),
       D::kNonFinite, D::kNonFinite},
      {"hello arm length negative", R, with(h, [](Bytes& b) { put_f32(b, kArm, -0.7f); }),
       D::kOutOfRange, D::kOutOfRange},
      {"hello deictic hand 2", R, with(h, [](Bytes& b) { b[kHand] = std::byte{2}; }),
       D::kOutOfRange, D::kOutOfRange},
      {"hello root rotation not unit", R,
       with(h, [](Bytes& b) { put_f32(b, kRootRotation + 12, 3.0f); }), D::kOutOfRange,
       D::kOutOfRange},
      {"hello root rotation NaN", R,
       with(h, [](Bytes& b) { put_f32(b, kRootRotation, std::nanf("")); }), D::kNonFinite,
       D::kNonFinite},
      {"hello empty site", R,
       with(h, [](Bytes& b) { b.erase(b.begin() + 4), b[3] = std::byte{0}; }), D::kOutOfRange,
       D::kOutOfRange},
      {"hello site with a control character", R, with(h, [](Bytes& b) { b[4] = std::byte{0x07}; }),
       D::kBadText, D::kBadText},
      {"hello site not UTF-8", R, with(h, [](Bytes& b) { b[4] = std::byte{0xC3}; }), D::kBadText,
       D::kBadText},
      {"hello trailing bytes", R, with(h, [](Bytes& b) { b.push_back(std::byte{1}); }),
       D::kTrailingBytes, D::kTrailingBytes},
      {"target map 257 objects", R, with(m, [](Bytes& b) { put_u16(b, kCount, 257); }),
       D::kOutOfRange, D::kOutOfRange},
      {"target map count beyond the packet", R, with(m, [](Bytes& b) { put_u16(b, kCount, 200); }),
       D::kLengthBeyondPacket, D::kLengthBeyondPacket},
      {"target map id 0 (the partner, never listed)", R,
       with(m, [](Bytes& b) { put_u32(b, kId, 0); }), D::kOutOfRange, D::kOutOfRange},
      {"target map id too large", R, with(m, [](Bytes& b) { put_u32(b, kId, 1'000'001); }),
       D::kOutOfRange, D::kOutOfRange},
      {"target map duplicate id", R, with(m, [](Bytes& b) { put_u32(b, kSecondId, 1); }),
       D::kDuplicateId, D::kDuplicateId},
      {"target map kind 3", R, with(m, [](Bytes& b) { b[kKind] = std::byte{3}; }), D::kOutOfRange,
       D::kOutOfRange},
      {"target map position NaN", R,
       with(m, [](Bytes& b) { put_f32(b, kPosition + 4, std::nanf("")); }), D::kNonFinite,
       D::kNonFinite},
      {"target map size zero", R, with(m, [](Bytes& b) { put_f32(b, kSize, 0.0f); }),
       D::kOutOfRange, D::kOutOfRange},
      {"target map size infinite", R, with(m, [](Bytes& b) { put_f32(b, kSize + 8, -INFINITY); }),
       D::kNonFinite, D::kNonFinite},
      {"target map name length beyond the packet", R,
       with(m, [](Bytes& b) { b[kNameLength] = std::byte{255}; }), D::kLengthBeyondPacket,
       D::kLengthBeyondPacket},
      {"heartbeat truncated", R, prefix(heartbeat_bytes(), 3), D::kTruncated, D::kTruncated},
      {"heartbeat trailing bytes", R,
       with(heartbeat_bytes(), [](Bytes& b) { b.push_back(std::byte{0}); }), D::kTrailingBytes,
       D::kTrailingBytes},
      {"bye reason out of range", R,
       with(bye_bytes(), [](Bytes& b) { b[1] = std::byte{kMaxByeReason + 1}; }), D::kOutOfRange,
       D::kOutOfRange},
      {"welcome bad magic", R, with(welcome_bytes(), [](Bytes& b) { b[1] = std::byte{'X'}; }),
       D::kBadMagic, D::kUnexpected},
      {"welcome version 0", R, with(welcome_bytes(), [](Bytes& b) { put_u16(b, 5, 0); }),
       D::kWrongVersion, D::kUnexpected},
      {"welcome auth mode 2", R, with(welcome_bytes(), [](Bytes& b) { b[7] = std::byte{2}; }),
       D::kOutOfRange, D::kUnexpected},
      {"welcome KDF memory beyond the limit", R,
       with(welcome_bytes(), [](Bytes& b) { put_u32(b, 28, kMaxKdfMemKib + 1); }), D::kOutOfRange,
       D::kUnexpected},
      {"join truncated", R, prefix(join_bytes(), kJoinBytes - 1), D::kTruncated, D::kUnexpected},
      {"accept trailing bytes", R,
       with(accept_bytes(), [](Bytes& b) { b.push_back(std::byte{0}); }), D::kTrailingBytes,
       D::kUnexpected},
      {"avatar request with trailing bytes", R,
       with(avatar_request_bytes(), [](Bytes& b) { b.push_back(std::byte{0}); }), D::kTrailingBytes,
       D::kTrailingBytes},
      {"avatar data past the end of its file", R,
       with(avatar_data_bytes(), [](Bytes& b) { put_u32(b, 37, 950); }), D::kOutOfRange,
       D::kOutOfRange},
      {"avatar data of a file beyond the size limit", R,
       with(avatar_data_bytes(), [](Bytes& b) { put_u32(b, 33, kAvatarFileMaxBytes + 1); }),
       D::kOutOfRange, D::kOutOfRange},
      {"avatar request for a file we do not have", R, avatar_request_bytes(), D::kNone,
       D::kUnexpected},
      {"avatar data nobody asked for", R, avatar_data_bytes(), D::kNone, D::kUnexpected},
      {"sealed packet in an open session", T,
       Bytes(30, std::byte{static_cast<unsigned char>(MessageType::kSealed)}), D::kNone,
       D::kUnexpected},
  };
}

// The decoder of the packet's own type.
DropReason decode_as_typed(const Bytes& p) {
  if (p.empty()) {
    return DropReason::kEmpty;
  }
  switch (static_cast<MessageType>(p[0])) {
    case MessageType::kWelcome: {
      Welcome m;
      return decode(p, m).reason;
    }
    case MessageType::kJoin: {
      Join m;
      return decode(p, m).reason;
    }
    case MessageType::kAccept: {
      Accept m;
      return decode(p, m).reason;
    }
    case MessageType::kHello: {
      Hello m;
      return decode(p, m).reason;
    }
    case MessageType::kTargetMap: {
      TargetMap m;
      return decode(p, m).reason;
    }
    case MessageType::kHeartbeat: {
      Heartbeat m;
      return decode(p, m).reason;
    }
    case MessageType::kBye: {
      Bye m;
      return decode(p, m).reason;
    }
    case MessageType::kAvatarRequest: {
      AvatarRequest m;
      return decode(p, m).reason;
    }
    case MessageType::kAvatarData: {
      AvatarData m;
      return decode(p, m).reason;
    }
    case MessageType::kTracking: {
      TrackingMessage m;
      return decode_tracking(p, kRoot, m).reason;
    }
    case MessageType::kSealed:
      break;
  }
  return DropReason::kUnknownType;
}

TEST(Malformed, TheValidPacketsTheTableStartsFromDecode) {
  for (const Bytes& p :
       {tracking_bytes(), hello_bytes(), map_bytes(), welcome_bytes(), join_bytes(), accept_bytes(),
        heartbeat_bytes(), bye_bytes(), avatar_request_bytes(), avatar_data_bytes()}) {
    EXPECT_EQ(decode_as_typed(p), DropReason::kNone)
        << message_name(std::to_integer<std::uint8_t>(p[0]));
  }
  // The offsets the table patches are where the comments say.
  const Bytes h = hello_bytes();
  float height = 0;
  std::memcpy(&height, h.data() + kHeight, 4);
  EXPECT_EQ(height, testing::make_hello("A").avatar.body.height);
  const Bytes m = map_bytes();
  EXPECT_EQ(m[kSecondId], std::byte{2});
}

TEST(Malformed, EachPacketIsRejectedByItsDecoderWithItsReason) {
  for (const Case& c : cases()) {
    if (c.decoder == DropReason::kNone) {
      continue;
    }
    EXPECT_EQ(decode_as_typed(c.packet), c.decoder)
        << c.name << ": got " << drop_reason_name(decode_as_typed(c.packet));
  }
}

TEST(Malformed, EachPacketIsCountedUnderItsReasonAndTheSessionStreamsOn) {
  testing::SessionPair pair;  // an open session: the packets reach the decoders unsealed
  ASSERT_TRUE(pair.connect());
  pair.run_until([] { return false; }, 0.2);  // hellos and target maps are in
  const std::uint64_t maps_before = pair.joiner.stats().target_maps_received;
  for (const Case& c : cases()) {
    const std::uint64_t before = pair.joiner.drops()[c.session];
    const std::uint64_t total = pair.joiner.drops().total;
    pair.network.inject(SimulatedNetwork::Side::kJoiner, c.channel, c.packet);
    pair.step(0.05);
    EXPECT_EQ(pair.joiner.drops()[c.session], before + 1)
        << c.name << ": expected " << drop_reason_name(c.session);
    EXPECT_EQ(pair.joiner.drops().total, total + 1) << c.name << ": counted once";
    EXPECT_EQ(pair.joiner.state(), SessionState::kStreaming) << c.name;
  }
  EXPECT_EQ(pair.joiner.stats().target_maps_received, maps_before) << "nothing bad was taken";
  const Hello* hello = pair.joiner.remote_hello();
  ASSERT_NE(hello, nullptr);
  EXPECT_EQ(hello->site, "A");
}

}  // namespace
}  // namespace deixis::net
