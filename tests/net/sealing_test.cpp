// Passphrase keys, proofs and sealed packets: both sides derive the same keys only from the same
// passphrase; a sealed packet opens once, on its channel, under the peer's key, untampered.

#include <gtest/gtest.h>

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

TEST(Passphrase, ProofsVerifyOnlyWithTheSameKeyAndChallenges) {
  const Key key = *derive_master_key("pw", salt_of(1), kCheap);
  const Key wrong = *derive_master_key("pW", salt_of(1), kCheap);
  const Proof p = join_proof(key, salt_of(1), challenge_of(1), challenge_of(2));
  EXPECT_TRUE(proofs_equal(p, join_proof(key, salt_of(1), challenge_of(1), challenge_of(2))));
  EXPECT_FALSE(proofs_equal(p, join_proof(wrong, salt_of(1), challenge_of(1), challenge_of(2))));
  EXPECT_FALSE(proofs_equal(p, join_proof(key, salt_of(1), challenge_of(3), challenge_of(2))));
  EXPECT_FALSE(proofs_equal(p, join_proof(key, salt_of(1), challenge_of(1), challenge_of(3))));
  // The host's answer is not the joiner's proof replayed.
  EXPECT_FALSE(proofs_equal(p, accept_proof(key, salt_of(1), challenge_of(1), challenge_of(2))));
}

TEST(Passphrase, SessionKeysPairUpAndDifferPerDirectionAndConnection) {
  const Key key = *derive_master_key("pw", salt_of(1), kCheap);
  const SessionKeys host = derive_session_keys(key, challenge_of(1), challenge_of(2), true);
  const SessionKeys joiner = derive_session_keys(key, challenge_of(1), challenge_of(2), false);
  EXPECT_EQ(host.send, joiner.receive);
  EXPECT_EQ(host.receive, joiner.send);
  EXPECT_NE(host.send, host.receive);
  const SessionKeys next = derive_session_keys(key, challenge_of(1), challenge_of(9), true);
  EXPECT_NE(next.send, host.send);
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
