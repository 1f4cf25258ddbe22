// Passphrase keys, proofs and sealed packets: both sides derive the same keys only from the same
// passphrase; a sealed packet opens once, on its channel, under the peer's key, untampered.

#include <gtest/gtest.h>

#include <algorithm>
#include <string_view>
#include <vector>

#include "net/passphrase.h"
#include "net/sealing.h"

namespace deixis::net {
namespace {

constexpr KdfCost kCheap{1, 8};

Salt salt_of(std::uint8_t v) {
  Salt s{};
  s.fill(std::byte{v});
  return s;
}
Challenge challenge_of(std::uint8_t v) {
  Challenge c{};
  c.fill(std::byte{v});
  return c;
}

TEST(Passphrase, KeysDependOnPassphraseSaltAndCost) {
  const auto a = derive_master_key("correct horse", salt_of(1), kCheap);
  const auto b = derive_master_key("correct horse", salt_of(1), kCheap);
  const auto other_phrase = derive_master_key("correct horse!", salt_of(1), kCheap);
  const auto other_salt = derive_master_key("correct horse", salt_of(2), kCheap);
  const auto other_cost = derive_master_key("correct horse", salt_of(1), KdfCost{2, 8});
  ASSERT_TRUE(a && b && other_phrase && other_salt && other_cost);
  EXPECT_EQ(*a, *b);
  EXPECT_NE(*a, *other_phrase);
  EXPECT_NE(*a, *other_salt);
  EXPECT_NE(*a, *other_cost);
}

// Both ends of one handshake: the welcome and join as they would go over the wire, each side's
// ephemeral key pair, and the handshake secret each side computes.
struct Handshake {
  Welcome welcome;
  Join join;
  ExchangeKeyPair host_keys = make_exchange_keys();
  ExchangeKeyPair joiner_keys = make_exchange_keys();

  explicit Handshake(std::uint8_t seed) {
    welcome.auth = join.auth = AuthMode::kPassphrase;
    welcome.salt = salt_of(1);
    welcome.kdf = kCheap;
    welcome.host_challenge = challenge_of(seed);
    welcome.host_key = host_keys.public_key;
    join.joiner_challenge = challenge_of(static_cast<std::uint8_t>(seed + 1));
    join.joiner_key = joiner_keys.public_key;
  }
  Key transcript() const { return transcript_of(welcome, join); }
  Key host_secret(const Key& master) const {
    return *handshake_secret(master, transcript(), host_keys, join.joiner_key, true);
  }
  Key joiner_secret(const Key& master) const {
    return *handshake_secret(master, transcript(), joiner_keys, welcome.host_key, false);
  }
};

TEST(Passphrase, BothSidesComputeTheSameHandshakeSecretOnlyWithTheSamePassphrase) {
  const Key key = *derive_master_key("pw", salt_of(1), kCheap);
  const Key wrong = *derive_master_key("pW", salt_of(1), kCheap);
  const Handshake h(1);
  EXPECT_EQ(h.host_secret(key), h.joiner_secret(key));
  EXPECT_NE(h.host_secret(key), h.joiner_secret(wrong));
  // Forward secrecy: the same passphrase and the same public values, other ephemeral secrets.
  const Handshake again(1);
  EXPECT_NE(again.host_secret(key), h.host_secret(key));
}

TEST(Passphrase, ProofsOpenOnlyUnderTheSameSecretAndTranscriptAndCarryTheSite) {
  const Key key = *derive_master_key("pw", salt_of(1), kCheap);
  const Key wrong = *derive_master_key("pW", salt_of(1), kCheap);
  const Handshake h(1);
  const Proof join = seal_join_proof(h.joiner_secret(key), h.transcript(), "site B");
  EXPECT_EQ(open_join_proof(h.host_secret(key), h.transcript(), join), "site B");
  EXPECT_FALSE(open_join_proof(h.host_secret(wrong), h.transcript(), join));
  // Another transcript: another version, cost, challenge or ephemeral key.
  Handshake other = h;
  other.welcome.protocol_version = 1;
  EXPECT_FALSE(open_join_proof(h.host_secret(key), other.transcript(), join));
  other = h;
  other.welcome.kdf = KdfCost{2, 8};
  EXPECT_FALSE(open_join_proof(h.host_secret(key), other.transcript(), join));
  other = h;
  other.join.joiner_challenge = challenge_of(9);
  EXPECT_FALSE(open_join_proof(h.host_secret(key), other.transcript(), join));
  // The host's answer binds both sites and is not the joiner's proof replayed.
  const Proof accept = seal_accept_proof(h.host_secret(key), h.transcript(), "site B", "site A");
  EXPECT_EQ(open_accept_proof(h.joiner_secret(key), h.transcript(), "site B", accept), "site A");
  EXPECT_FALSE(open_accept_proof(h.joiner_secret(key), h.transcript(), "site C", accept));
  EXPECT_FALSE(open_join_proof(h.host_secret(key), h.transcript(), accept));
  EXPECT_FALSE(open_accept_proof(h.joiner_secret(key), h.transcript(), "site B", join));
  // A flipped bit anywhere fails.
  Proof tampered = join;
  tampered[10] ^= std::byte{1};
  EXPECT_FALSE(open_join_proof(h.host_secret(key), h.transcript(), tampered));
}

TEST(Passphrase, ProofsHideTheSiteNamesLength) {
  const Key key = *derive_master_key("pw", salt_of(1), kCheap);
  const Handshake h(1);
  // Every proof has the same size whatever the name, and the name is not in it in clear.
  const Proof a = seal_join_proof(h.joiner_secret(key), h.transcript(), "B");
  const Proof b = seal_join_proof(h.joiner_secret(key), h.transcript(),
                                  "a site with a much longer name than the other");
  EXPECT_EQ(a.size(), b.size());
  const std::string_view name = "a site with a much longer name";
  const auto* bytes = reinterpret_cast<const char*>(b.data());
  EXPECT_EQ(std::string_view(bytes, b.size()).find(name), std::string_view::npos);
}

TEST(Passphrase, AnUnusableEphemeralKeyIsRefused) {
  const Key key = *derive_master_key("pw", salt_of(1), kCheap);
  const Handshake h(1);
  const ExchangeKey zero{};  // a low-order point: X25519 gives an all-zero secret
  EXPECT_FALSE(handshake_secret(key, h.transcript(), h.host_keys, zero, true));
}

TEST(Passphrase, SessionKeysPairUpAndDifferPerDirectionConnectionAndSites) {
  const Key key = *derive_master_key("pw", salt_of(1), kCheap);
  const Handshake h(1);
  const SessionKeys host = derive_session_keys(h.host_secret(key), "B", "A", true);
  const SessionKeys joiner = derive_session_keys(h.joiner_secret(key), "B", "A", false);
  EXPECT_EQ(host.send, joiner.receive);
  EXPECT_EQ(host.receive, joiner.send);
  EXPECT_NE(host.send, host.receive);
  const Handshake next(5);
  EXPECT_NE(derive_session_keys(next.host_secret(key), "B", "A", true).send, host.send);
  EXPECT_NE(derive_session_keys(h.host_secret(key), "B", "A2", true).send, host.send);
}

TEST(Padding, ReliablePacketsGrowToTheirBucketAndComeBackWhole) {
  std::vector<std::byte> out(kMaxPacketBytes);
  for (const std::size_t n : {std::size_t{1}, std::size_t{5}, std::size_t{63}, std::size_t{64},
                              std::size_t{200}, std::size_t{24'132}}) {
    std::vector<std::byte> inner(n, std::byte{0});  // zeros at the end: the hardest case
    inner[0] = std::byte{0x04};
    const std::size_t size = pad(inner, out);
    ASSERT_GT(size, n) << n;
    EXPECT_NE(std::find(kPaddingBuckets.begin(), kPaddingBuckets.end(), size),
              kPaddingBuckets.end())
        << n;
    const auto back = unpad(std::span(out).first(size));
    EXPECT_EQ(back.size(), n);
  }
  // Two hellos whose names differ in length by up to a bucket look the same.
  EXPECT_EQ(padded_size(68), padded_size(194));
  // Broken padding: no marker, a non-zero byte after it, or not a bucket's size.
  std::vector<std::byte> bad(64, std::byte{0});
  EXPECT_TRUE(unpad(bad).empty());
  bad[10] = std::byte{0x80};
  bad[20] = std::byte{1};
  EXPECT_TRUE(unpad(bad).empty());
  std::vector<std::byte> odd(70, std::byte{0});
  odd[0] = std::byte{4};
  odd[1] = std::byte{0x80};
  EXPECT_TRUE(unpad(odd).empty());
}

struct Pair {
  PacketSealer sealer;
  PacketOpener opener;
  std::vector<std::byte> sealed = std::vector<std::byte>(256);
  std::vector<std::byte> scratch = std::vector<std::byte>(256);
  std::span<const std::byte> plain;

  explicit Pair(const Key& k) : sealer(k), opener(k) {}
  std::span<const std::byte> seal(Channel c, std::span<const std::byte> m) {
    return std::span(sealed).first(sealer.seal(c, m, sealed));
  }
  WireResult open(Channel c, std::span<const std::byte> packet) {
    return opener.open(c, packet, scratch, plain);
  }
};

const std::array<std::byte, 5> kMessage = {std::byte{0x06}, std::byte{1}, std::byte{2},
                                           std::byte{3}, std::byte{4}};

TEST(Sealing, OpensOnceAndExactly) {
  Key key{};
  key.fill(std::byte{7});
  Pair p(key);
  const auto packet = p.seal(Channel::kReliable, kMessage);
  ASSERT_EQ(packet.size(), kMessage.size() + kSealOverheadBytes);
  EXPECT_EQ(packet[0], std::byte{0x20});
  ASSERT_TRUE(p.open(Channel::kReliable, packet).ok());
  EXPECT_TRUE(std::equal(p.plain.begin(), p.plain.end(), kMessage.begin(), kMessage.end()));
  EXPECT_EQ(p.open(Channel::kReliable, packet).reason, DropReason::kReplayed);
}

TEST(Sealing, RefusesTamperingTheWrongKeyAndTheWrongChannel) {
  Key key{};
  key.fill(std::byte{7});
  Key other = key;
  other[0] = std::byte{8};
  Pair p(key);
  const auto sealed = p.seal(Channel::kTracking, kMessage);
  const std::vector<std::byte> packet(sealed.begin(), sealed.end());
  for (std::size_t i = 0; i < packet.size(); ++i) {
    std::vector<std::byte> bad = packet;
    bad[i] ^= std::byte{0x01};
    const DropReason r = p.open(Channel::kTracking, bad).reason;
    EXPECT_TRUE(r == DropReason::kDecryptFailed || r == DropReason::kUnauthenticated) << i;
  }
  EXPECT_EQ(p.open(Channel::kReliable, packet).reason, DropReason::kDecryptFailed)
      << "a packet moved to the other channel";
  PacketOpener stranger(other);
  std::vector<std::byte> scratch(256);
  std::span<const std::byte> plain;
  EXPECT_EQ(stranger.open(Channel::kTracking, packet, scratch, plain).reason,
            DropReason::kDecryptFailed);
  EXPECT_TRUE(p.open(Channel::kTracking, packet).ok()) << "failures did not burn the counter";
  EXPECT_EQ(p.open(Channel::kTracking, std::span(packet).first(20)).reason, DropReason::kTruncated);
  EXPECT_EQ(p.open(Channel::kTracking, std::span(kMessage)).reason, DropReason::kUnauthenticated);
}

TEST(Sealing, ReplayWindowAcceptsReorderingButNotRepeatsOrAncientCounters) {
  ReplayWindow w;
  for (const std::uint32_t c : {5u, 3u, 4u, 10u, 70u}) {
    ASSERT_EQ(w.check(c), DropReason::kNone) << c;
    w.record(c);
  }
  for (const std::uint32_t c : {5u, 3u, 70u, 10u}) {
    EXPECT_EQ(w.check(c), DropReason::kReplayed) << c;
  }
  EXPECT_EQ(w.check(6), DropReason::kReplayed) << "older than 64 below the highest";
  EXPECT_EQ(w.check(7), DropReason::kNone) << "inside the window, never seen";
  EXPECT_EQ(w.check(71), DropReason::kNone);
}

TEST(Sealing, ReorderedTrackingOpensReplayedDoesNot) {
  Key key{};
  key.fill(std::byte{3});
  Pair p(key);
  std::vector<std::vector<std::byte>> packets;
  for (int i = 0; i < 5; ++i) {
    const auto s = p.seal(Channel::kTracking, kMessage);
    packets.emplace_back(s.begin(), s.end());
  }
  for (const int i : {1, 0, 3, 2, 4}) {
    EXPECT_TRUE(p.open(Channel::kTracking, packets[i]).ok()) << i;
  }
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(p.open(Channel::kTracking, packets[i]).reason, DropReason::kReplayed) << i;
  }
}

}  // namespace
}  // namespace deixis::net
