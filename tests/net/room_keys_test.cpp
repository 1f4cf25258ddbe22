// The room's cryptography (net/room_keys.h, docs/rooms-protocol.md): strict params and announces,
// per-pair transcripts and secrets, key messages that fail under another passphrase, another
// transcript, another direction or another pair, and per-sender sealing with a replay window.

#include <gtest/gtest.h>

#include "net/passphrase.h"
#include "net/room_keys.h"
#include "net/tracking_codec.h"

namespace deixis::net {
namespace {

constexpr KdfCost kCheap{1, 8};

// One member of a pair: id, entry, and the pair's secret from its side.
struct Side {
  RoomMemberId id;
  Entry entry;
};

struct Pair {
  RoomParams params = make_room_params(true, kCheap);
  Side low{3, make_entry(AuthMode::kPassphrase)};
  Side high{7, make_entry(AuthMode::kPassphrase)};

  Key transcript() const {
    return room_transcript(params, low.id, low.entry.announce, high.id, high.entry.announce);
  }
  std::optional<Key> prk(const Side& self, const Side& peer, std::string_view passphrase) const {
    const auto master = derive_master_key(passphrase, params.salt, params.kdf);
    if (!master) {
      return std::nullopt;
    }
    const Key t =
        room_transcript(params, self.id, self.entry.announce, peer.id, peer.entry.announce);
    return room_pair_secret(*master, t, self.id, self.entry.keys, peer.id, peer.entry.announce.key);
  }
};

Key key_of(std::uint8_t v) {
  Key k{};
  k.fill(std::byte{v});
  return k;
}

TEST(RoomParams, RoundTripAndStrictBounds) {
  const RoomParams p = make_room_params(true, kInteractiveKdf);
  std::array<std::byte, 64> bytes{};
  const std::size_t n = encode(p, bytes);
  ASSERT_EQ(n, kRoomParamsBytes);
  RoomParams back;
  ASSERT_TRUE(decode(std::span(bytes).first(n), back).ok());
  EXPECT_EQ(back, p);

  // Every shorter prefix is truncated, one more byte is trailing.
  for (std::size_t k = 1; k < n; ++k) {
    EXPECT_EQ(decode(std::span(bytes).first(k), back).reason, DropReason::kTruncated) << k;
  }
  EXPECT_EQ(decode(std::span(bytes).first(n + 1), back).reason, DropReason::kTrailingBytes);
  EXPECT_EQ(decode(std::span(bytes).first(0), back).reason, DropReason::kEmpty);

  auto with = [&](std::size_t offset, std::byte value) {
    std::array<std::byte, kRoomParamsBytes> b{};
    std::copy_n(bytes.begin(), n, b.begin());
    b[offset] = value;
    RoomParams out;
    return decode(b, out).reason;
  };
  EXPECT_EQ(with(0, std::byte{'X'}), DropReason::kBadMagic);
  EXPECT_EQ(with(4, std::byte{2}), DropReason::kWrongVersion);
  EXPECT_EQ(with(6, std::byte{2}), DropReason::kOutOfRange);
  EXPECT_EQ(with(23, std::byte{5}), DropReason::kOutOfRange);     // 5 passes: above the ceiling
  EXPECT_EQ(with(23, std::byte{0}), DropReason::kOutOfRange);     // 0 passes
  EXPECT_EQ(with(30, std::byte{0x10}), DropReason::kOutOfRange);  // memory far above 256 MiB
  // An open room carries no salt and no cost.
  RoomParams open = make_room_params(false, kInteractiveKdf);
  EXPECT_EQ(open.auth, AuthMode::kOpen);
  ASSERT_EQ(encode(open, bytes), kRoomParamsBytes);
  ASSERT_TRUE(decode(std::span(bytes).first(n), back).ok());
  bytes[10] = std::byte{1};
  EXPECT_EQ(decode(std::span(bytes).first(n), back).reason, DropReason::kOutOfRange);
}

TEST(RoomAnnounce, RoundTripAndStrictBounds) {
  const Entry e = make_entry(AuthMode::kPassphrase);
  std::array<std::byte, 128> bytes{};
  const std::size_t n = encode(e.announce, bytes);
  ASSERT_EQ(n, kAnnounceBytes);
  Announce back;
  ASSERT_TRUE(decode(std::span(bytes).first(n), back).ok());
  EXPECT_EQ(back, e.announce);
  EXPECT_EQ(decode(std::span(bytes).first(n - 1), back).reason, DropReason::kTruncated);
  EXPECT_EQ(decode(std::span(bytes).first(n + 1), back).reason, DropReason::kTrailingBytes);
  bytes[3] = std::byte{'P'};  // a params magic is not an announce
  EXPECT_EQ(decode(std::span(bytes).first(n), back).reason, DropReason::kBadMagic);
  // Two entries never share a challenge or a key.
  const Entry f = make_entry(AuthMode::kPassphrase);
  EXPECT_NE(e.announce.challenge, f.announce.challenge);
  EXPECT_NE(e.announce.key, f.announce.key);
  // An open announce with a key is refused.
  Entry open = make_entry(AuthMode::kOpen);
  EXPECT_EQ(open.announce.key, ExchangeKey{});
  open.announce.key[0] = std::byte{1};
  ASSERT_EQ(encode(open.announce, bytes), kAnnounceBytes);
  EXPECT_EQ(decode(std::span(bytes).first(n), back).reason, DropReason::kOutOfRange);
}

TEST(RoomKeys, BothSidesDeriveTheSameSecretAndTheKeyMessageOpens) {
  Pair pair;
  const auto low = pair.prk(pair.low, pair.high, "pw");
  const auto high = pair.prk(pair.high, pair.low, "pw");
  ASSERT_TRUE(low && high);
  EXPECT_EQ(*low, *high);
  const Key t = pair.transcript();
  std::array<std::byte, kKeyMessageBytes> message{};
  ASSERT_EQ(seal_key_message(*high, t, pair.high.id, pair.low.id, "Büro B", key_of(5), message),
            kKeyMessageBytes);
  KeyGrant grant;
  ASSERT_TRUE(open_key_message(*low, t, pair.high.id, pair.low.id, message, grant).ok());
  EXPECT_EQ(grant.site, "Büro B");
  EXPECT_EQ(grant.sender_key, key_of(5));
}

TEST(RoomKeys, AWrongPassphraseFailsToOpen) {
  Pair pair;
  const auto wrong = pair.prk(pair.low, pair.high, "another");
  const auto right = pair.prk(pair.high, pair.low, "pw");
  ASSERT_TRUE(wrong && right);
  EXPECT_NE(*wrong, *right);
  const Key t = pair.transcript();
  std::array<std::byte, kKeyMessageBytes> message{};
  seal_key_message(*right, t, pair.high.id, pair.low.id, "B", key_of(5), message);
  KeyGrant grant;
  EXPECT_EQ(open_key_message(*wrong, t, pair.high.id, pair.low.id, message, grant).reason,
            DropReason::kDecryptFailed);
  EXPECT_TRUE(grant.site.empty());
}

TEST(RoomKeys, ATamperedTranscriptFailsToOpen) {
  Pair pair;
  const auto prk = pair.prk(pair.high, pair.low, "pw");
  ASSERT_TRUE(prk);
  const Key t = pair.transcript();
  std::array<std::byte, kKeyMessageBytes> message{};
  seal_key_message(*prk, t, pair.high.id, pair.low.id, "B", key_of(5), message);
  KeyGrant grant;
  // The relay handed the low member other room params (another salt)...
  RoomParams other = pair.params;
  other.salt[0] ^= std::byte{1};
  const Key t_params = room_transcript(other, pair.low.id, pair.low.entry.announce, pair.high.id,
                                       pair.high.entry.announce);
  EXPECT_EQ(open_key_message(*prk, t_params, pair.high.id, pair.low.id, message, grant).reason,
            DropReason::kDecryptFailed);
  // ...or another challenge in the peer's announce...
  Announce changed = pair.high.entry.announce;
  changed.challenge[31] ^= std::byte{0x80};
  const Key t_announce =
      room_transcript(pair.params, pair.low.id, pair.low.entry.announce, pair.high.id, changed);
  EXPECT_EQ(open_key_message(*prk, t_announce, pair.high.id, pair.low.id, message, grant).reason,
            DropReason::kDecryptFailed);
  // ...or a flipped ciphertext bit.
  message[40] ^= std::byte{1};
  EXPECT_EQ(open_key_message(*prk, t, pair.high.id, pair.low.id, message, grant).reason,
            DropReason::kDecryptFailed);
}

TEST(RoomKeys, ARelaySwappingTheSenderOrReflectingAMessageFailsToOpen) {
  Pair pair;
  const auto prk = pair.prk(pair.high, pair.low, "pw");
  ASSERT_TRUE(prk);
  const Key t = pair.transcript();
  std::array<std::byte, kKeyMessageBytes> message{};
  seal_key_message(*prk, t, pair.high.id, pair.low.id, "B", key_of(5), message);
  KeyGrant grant;
  // Reflected back to its sender: the direction's key differs.
  EXPECT_EQ(open_key_message(*prk, t, pair.low.id, pair.high.id, message, grant).reason,
            DropReason::kDecryptFailed);
  // Forwarded as if from a third member 9 (the receiver uses the pair 3–9's transcript).
  Side third{9, make_entry(AuthMode::kPassphrase)};
  const Key t9 = room_transcript(pair.params, pair.low.id, pair.low.entry.announce, third.id,
                                 third.entry.announce);
  const auto prk9 = pair.prk(pair.low, third, "pw");
  ASSERT_TRUE(prk9);
  EXPECT_EQ(open_key_message(*prk9, t9, third.id, pair.low.id, message, grant).reason,
            DropReason::kDecryptFailed);
  // The same announces under swapped ids give another transcript.
  EXPECT_NE(t, room_transcript(pair.params, pair.high.id, pair.low.entry.announce, pair.low.id,
                               pair.high.entry.announce));
}

TEST(RoomKeys, BadSizesAndTypesAreRefusedBeforeDecrypting) {
  Pair pair;
  const auto prk = pair.prk(pair.high, pair.low, "pw");
  ASSERT_TRUE(prk);
  const Key t = pair.transcript();
  std::array<std::byte, kKeyMessageBytes + 1> message{};
  seal_key_message(*prk, t, pair.high.id, pair.low.id, "B", key_of(5), message);
  KeyGrant grant;
  const std::span<const std::byte> m(message);
  EXPECT_EQ(open_key_message(*prk, t, 7, 3, m.first(0), grant).reason, DropReason::kEmpty);
  EXPECT_EQ(open_key_message(*prk, t, 7, 3, m.first(50), grant).reason, DropReason::kTruncated);
  EXPECT_EQ(open_key_message(*prk, t, 7, 3, m, grant).reason, DropReason::kTrailingBytes);
  message[0] = std::byte{0x20};
  EXPECT_EQ(open_key_message(*prk, t, 7, 3, m.first(kKeyMessageBytes), grant).reason,
            DropReason::kUnknownType);
}

std::array<std::byte, kTrackingBytes> tracking_packet(std::uint32_t sequence) {
  std::array<std::byte, kTrackingBytes> out{};
  TrackingMessage m;
  m.sequence = sequence;
  m.frame.time = sequence / 30.0;
  encode_tracking(m, Vec3::Zero(), out);
  return out;
}

TEST(RoomSealing, EachSendersPacketsOpenOnlyWithItsKeyAndOnlyOnce) {
  RoomSealer a(key_of(1));
  RoomOpener from_a(key_of(1));
  RoomOpener from_b(key_of(2));  // what the receiver holds for another sender
  std::array<std::byte, kMaxPacketBytes> sealed{};
  std::array<std::byte, kMaxPacketBytes> scratch{};
  std::span<const std::byte> inner;
  const auto frame = tracking_packet(4);
  const std::size_t n = a.seal(Channel::kTracking, frame, sealed);
  ASSERT_EQ(n, kTrackingBytes + kSealOverheadBytes);
  const std::span<const std::byte> packet = std::span(sealed).first(n);
  // A relay that says A's packet came from B: B's key does not open it.
  EXPECT_EQ(from_b.open(Channel::kTracking, packet, scratch, inner).reason,
            DropReason::kDecryptFailed);
  ASSERT_TRUE(from_a.open(Channel::kTracking, packet, scratch, inner).ok());
  EXPECT_TRUE(std::equal(inner.begin(), inner.end(), frame.begin(), frame.end()));
  // Replayed: refused before decrypting.
  EXPECT_EQ(from_a.open(Channel::kTracking, packet, scratch, inner).reason, DropReason::kReplayed);
  // On the other channel: another nonce, does not open.
  const std::size_t n2 = a.seal(Channel::kTracking, tracking_packet(5), sealed);
  EXPECT_EQ(from_a.open(Channel::kReliable, std::span(sealed).first(n2), scratch, inner).reason,
            DropReason::kDecryptFailed);
}

TEST(RoomSealing, ReliablePacketsArePaddedAndMustBelongOnTheirChannel) {
  RoomSealer a(key_of(1));
  RoomOpener from_a(key_of(1));
  std::array<std::byte, kMaxPacketBytes> sealed{};
  std::array<std::byte, kMaxPacketBytes> scratch{};
  std::span<const std::byte> inner;
  const std::array<std::byte, 5> heartbeat = {std::byte{0x06}, std::byte{1}, std::byte{0},
                                              std::byte{0}, std::byte{0}};
  const std::size_t n = a.seal(Channel::kReliable, heartbeat, sealed);
  EXPECT_EQ(n, 64 + kSealOverheadBytes);
  ASSERT_TRUE(from_a.open(Channel::kReliable, std::span(sealed).first(n), scratch, inner).ok());
  EXPECT_EQ(inner.size(), heartbeat.size());
  // A tracking message sealed as reliable, or a heartbeat as tracking: wrong channel.
  const std::size_t t = a.seal(Channel::kReliable, tracking_packet(1), sealed);
  EXPECT_EQ(from_a.open(Channel::kReliable, std::span(sealed).first(t), scratch, inner).reason,
            DropReason::kWrongChannel);
  const std::size_t h = a.seal(Channel::kTracking, heartbeat, sealed);
  EXPECT_EQ(from_a.open(Channel::kTracking, std::span(sealed).first(h), scratch, inner).reason,
            DropReason::kWrongChannel);
}

}  // namespace
}  // namespace deixis::net
