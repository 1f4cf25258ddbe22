// A person's own avatar file between two sessions (net/avatar_transfer.h, docs/protocol.md §4.10):
// the messages' bounds, the sender's pace, the receiver's checks, and the whole transfer over the
// simulated network, open and sealed.

#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <vector>

#include "core/error.h"
#include "net/avatar_transfer.h"
#include "session_pair.h"

namespace deixis::net {
namespace {

std::vector<std::byte> random_file(std::size_t n, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<std::byte> file(n);
  for (std::byte& b : file) {
    b = static_cast<std::byte>(rng() & 0xFFu);
  }
  return file;
}

TEST(AvatarHash, HexRoundTripsAndRefusesAnythingElse) {
  const AvatarHash h = avatar_hash(random_file(1000, 1));
  const std::string hex = to_hex(h);
  ASSERT_EQ(hex.size(), 64u);
  EXPECT_EQ(parse_avatar_hash(hex), h);
  EXPECT_FALSE(parse_avatar_hash(""));
  EXPECT_FALSE(parse_avatar_hash(hex.substr(1)));
  std::string upper = hex;
  upper[0] = 'A';
  EXPECT_FALSE(parse_avatar_hash(upper));  // lowercase only: one spelling per file
  EXPECT_FALSE(parse_avatar_hash(std::string(64, 'g')));
  EXPECT_NE(avatar_hash(random_file(1000, 2)), h);
}

TEST(AvatarMessages, DataRoundTripsAndDecodeChecksEveryBound) {
  const std::vector<std::byte> file = random_file(40'000, 3);
  AvatarData m{avatar_hash(file), 40'000, 16'384, std::span(file).subspan(16'384, 100)};
  std::vector<std::byte> packet(kAvatarDataHeaderBytes + kAvatarChunkMaxBytes);
  const std::size_t n = encode(m, packet);
  ASSERT_EQ(n, kAvatarDataHeaderBytes + 100);
  AvatarData back;
  ASSERT_TRUE(decode(std::span(packet).first(n), back).ok());
  EXPECT_EQ(back.hash, m.hash);
  EXPECT_EQ(back.total, 40'000u);
  EXPECT_EQ(back.offset, 16'384u);
  ASSERT_EQ(back.bytes.size(), 100u);
  EXPECT_EQ(back.bytes[7], file[16'384 + 7]);

  const auto decoded_with = [&](auto&& edit) {
    std::vector<std::byte> p(packet.begin(), packet.begin() + static_cast<std::ptrdiff_t>(n));
    edit(p);
    AvatarData out;
    return decode(p, out);
  };
  const auto put_u32 = [](std::vector<std::byte>& p, std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) {
      p[at + static_cast<std::size_t>(i)] = static_cast<std::byte>((v >> (8 * i)) & 0xFFu);
    }
  };
  EXPECT_EQ(decoded_with([&](auto& p) { put_u32(p, 33, 0); }).reason, DropReason::kOutOfRange);
  EXPECT_EQ(decoded_with([&](auto& p) { put_u32(p, 33, kAvatarFileMaxBytes + 1); }).reason,
            DropReason::kOutOfRange);
  // A chunk that runs past the end of the file it claims.
  EXPECT_EQ(decoded_with([&](auto& p) { put_u32(p, 37, 39'950); }).reason, DropReason::kOutOfRange);
  EXPECT_EQ(decoded_with([&](auto& p) { p.resize(kAvatarDataHeaderBytes); }).reason,
            DropReason::kOutOfRange);  // no bytes
  EXPECT_EQ(decoded_with([&](auto& p) { p.resize(20); }).reason, DropReason::kTruncated);
  EXPECT_EQ(decoded_with([&](auto& p) { p[0] = std::byte{0x08}; }).reason,
            DropReason::kUnknownType);

  // The encoder refuses what the decoder would.
  AvatarData too_big = m;
  too_big.bytes = std::span(file).first(kAvatarChunkMaxBytes + 1);
  too_big.offset = 0;
  EXPECT_EQ(encode(too_big, packet), 0u);
}

TEST(AvatarMessages, RequestHasNoRoomForAnythingElse) {
  std::array<std::byte, kAvatarRequestBytes + 1> packet{};
  const AvatarRequest m{avatar_hash(random_file(10, 4))};
  ASSERT_EQ(encode(m, packet), kAvatarRequestBytes);
  AvatarRequest back;
  EXPECT_TRUE(decode(std::span(packet).first(kAvatarRequestBytes), back).ok());
  EXPECT_EQ(back.hash, m.hash);
  EXPECT_EQ(decode(packet, back).reason, DropReason::kTrailingBytes);
  EXPECT_EQ(decode(std::span(packet).first(10), back).reason, DropReason::kTruncated);
}

TEST(AvatarSender, KeepsItsPaceAndAnswersOnlyForItsFile) {
  const std::vector<std::byte> file = random_file(200'000, 5);
  AvatarSender sender(file, "test.glb");
  EXPECT_FALSE(sender.on_request(1, avatar_hash(random_file(10, 6)), 0.0));
  EXPECT_FALSE(sender.next_chunk(1, 0.0));
  ASSERT_TRUE(sender.on_request(1, sender.hash(), 10.0));
  std::size_t sent = 0;
  for (double t = 10.0; t <= 10.5; t += 1.0 / 30.0) {
    while (const auto chunk = sender.next_chunk(1, t)) {
      EXPECT_EQ(chunk->offset, sent);
      sent += chunk->bytes.size();
    }
    // Never ahead of the pace: one chunk at once, then kAvatarBytesPerSecond.
    EXPECT_LE(static_cast<double>(sent), kAvatarChunkMaxBytes + kAvatarBytesPerSecond * (t - 10.0));
  }
  EXPECT_GT(sent, 0u);
  EXPECT_LT(sent, file.size());
  for (double t = 10.5; t < 20.0; t += 1.0 / 30.0) {
    while (const auto chunk = sender.next_chunk(1, t)) {
      sent += chunk->bytes.size();
    }
  }
  EXPECT_EQ(sent, file.size());
}

TEST(AvatarSender, RefusesAnEmptyOrOversizedFileNamingIt) {
  EXPECT_THROW(AvatarSender({}, "empty.glb"), Error);
  try {
    AvatarSender(std::vector<std::byte>(kAvatarFileMaxBytes + 1), "huge.glb");
    FAIL() << "an oversized file was taken";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("huge.glb"), std::string::npos);
  }
}

TEST(AvatarReceiver, AcceptsOnlyTheNamedFileInOrder) {
  const std::vector<std::byte> file = random_file(50'000, 7);
  AvatarSender sender(file, "a.glb");
  sender.on_request(1, sender.hash(), 0.0);
  std::vector<AvatarData> chunks;
  for (double t = 0.0; t < 5.0; t += 0.1) {
    while (const auto c = sender.next_chunk(1, t)) {
      chunks.push_back(*c);
    }
  }
  ASSERT_EQ(chunks.size(), 4u);  // 16 + 16 + 16 + 1.8 kB

  AvatarReceiver ok;
  ok.expect(sender.hash());
  for (const AvatarData& c : chunks) {
    EXPECT_TRUE(ok.on_data(c));
  }
  ASSERT_EQ(ok.status(), AvatarReceiveStatus::kComplete);
  EXPECT_TRUE(std::equal(file.begin(), file.end(), ok.file().begin(), ok.file().end()));

  AvatarReceiver other;  // expects another file: the chunks are not its business
  other.expect(avatar_hash(random_file(10, 8)));
  EXPECT_FALSE(other.on_data(chunks[0]));
  EXPECT_EQ(other.status(), AvatarReceiveStatus::kReceiving);

  AvatarReceiver reordered;
  reordered.expect(sender.hash());
  EXPECT_TRUE(reordered.on_data(chunks[0]));
  EXPECT_TRUE(reordered.on_data(chunks[2]));
  EXPECT_EQ(reordered.status(), AvatarReceiveStatus::kFailed);
  EXPECT_NE(reordered.failure().find("out of order"), std::string::npos);
  EXPECT_TRUE(reordered.file().empty());

  // The right hash in every chunk, other bytes: caught when the file is whole.
  std::vector<std::byte> forged = file;
  forged[49'000] ^= std::byte{1};
  AvatarReceiver fooled;
  fooled.expect(sender.hash());
  for (const AvatarData& c : chunks) {
    AvatarData f = c;
    f.bytes = std::span(forged).subspan(c.offset, c.bytes.size());
    fooled.on_data(f);
  }
  EXPECT_EQ(fooled.status(), AvatarReceiveStatus::kFailed);
  EXPECT_NE(fooled.failure().find("hash"), std::string::npos);
}

// The whole transfer between two sessions: the joiner's hello names its file, the host asks, the
// file arrives intact while tracking keeps streaming.
class AvatarSessionTest : public ::testing::TestWithParam<bool> {};

TEST_P(AvatarSessionTest, TheFileArrivesWhenAskedFor) {
  const std::string passphrase = GetParam() ? "correct horse" : "";
  const auto file = std::make_shared<const std::vector<std::byte>>(random_file(150'000, 9));
  SessionConfig joiner = testing::session_config(Role::kJoiner, "B", passphrase);
  joiner.avatar_file = file;
  testing::SessionPair pair({}, 1, testing::session_config(Role::kHost, "A", passphrase),
                            std::move(joiner));
  ASSERT_TRUE(pair.connect());
  EXPECT_EQ(pair.host.sealed(), GetParam());
  ASSERT_TRUE(pair.host.remote_avatar_hash());
  EXPECT_EQ(*pair.host.remote_avatar_hash(), avatar_hash(*file));
  EXPECT_FALSE(pair.joiner.remote_avatar_hash());  // the host chose none

  ASSERT_TRUE(pair.host.request_avatar());
  const bool arrived = pair.run_until(
      [&] { return pair.host.avatar_download().status() != AvatarReceiveStatus::kReceiving; }, 5.0,
      1.0 / 30.0);
  ASSERT_TRUE(arrived);
  ASSERT_EQ(pair.host.avatar_download().status(), AvatarReceiveStatus::kComplete)
      << pair.host.avatar_download().failure();
  const auto got = pair.host.avatar_download().file();
  EXPECT_TRUE(std::equal(got.begin(), got.end(), file->begin(), file->end()));
  EXPECT_EQ(pair.joiner.stats().avatar_requests_received, 1u);
  EXPECT_EQ(pair.host.stats().avatar_chunks_received, pair.joiner.stats().avatar_chunks_sent);
  EXPECT_EQ(pair.host.stats().floods_cut + pair.joiner.stats().floods_cut, 0u);
  EXPECT_TRUE(pair.both_streaming());
}

TEST_P(AvatarSessionTest, NothingToAskForWhenTheHelloNamesNoFile) {
  const std::string passphrase = GetParam() ? "correct horse" : "";
  testing::SessionPair pair({}, 2, passphrase, passphrase);
  ASSERT_TRUE(pair.connect());
  EXPECT_FALSE(pair.host.request_avatar());  // the joiner's hello names no file
  EXPECT_EQ(pair.joiner.stats().avatar_requests_received, 0u);
}

INSTANTIATE_TEST_SUITE_P(OpenAndSealed, AvatarSessionTest, ::testing::Bool());

}  // namespace
}  // namespace deixis::net
