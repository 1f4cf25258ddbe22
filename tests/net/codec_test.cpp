// Every message survives encoding and decoding: fixed-size handshake messages byte for byte,
// hello and target map field for field (floats are sent as they are), tracking within the
// quantisation bounds of quantize.h, and re-encoding a decoded message gives the same bytes.

#include <gtest/gtest.h>

#include <random>

#include "angles.h"
#include "net/messages.h"
#include "net/quantize.h"
#include "net/tracking_codec.h"
#include "net/wire.h"
#include "net_fixtures.h"

namespace deixis::net {
namespace {

template <std::size_t N>
std::array<std::byte, N> random_array(std::mt19937& rng) {
  std::array<std::byte, N> a{};
  for (std::byte& b : a) {
    b = static_cast<std::byte>(rng() & 0xFFu);
  }
  return a;
}

TEST(Codec, WelcomeRoundTrip) {
  std::mt19937 rng(1);
  Welcome w;
  w.auth = AuthMode::kPassphrase;
  w.salt = random_array<kSaltBytes>(rng);
  w.kdf = {3, 65536};
  w.host_challenge = random_array<kChallengeBytes>(rng);
  std::vector<std::byte> bytes;
  encode(w, bytes);
  ASSERT_EQ(bytes.size(), kWelcomeBytes);
  EXPECT_EQ(bytes[0], std::byte{0x01});
  Welcome back;
  ASSERT_TRUE(decode(bytes, back).ok());
  EXPECT_EQ(back.protocol_version, kProtocolVersion);
  EXPECT_EQ(back.auth, AuthMode::kPassphrase);
  EXPECT_EQ(back.salt, w.salt);
  EXPECT_EQ(back.kdf, w.kdf);
  EXPECT_EQ(back.host_challenge, w.host_challenge);
}

TEST(Codec, JoinAndAcceptRoundTrip) {
  std::mt19937 rng(2);
  Join j;
  j.auth = AuthMode::kOpen;
  j.joiner_challenge = random_array<kChallengeBytes>(rng);
  j.proof = random_array<kProofBytes>(rng);
  std::vector<std::byte> bytes;
  encode(j, bytes);
  ASSERT_EQ(bytes.size(), kJoinBytes);
  Join jb;
  ASSERT_TRUE(decode(bytes, jb).ok());
  EXPECT_EQ(jb.auth, AuthMode::kOpen);
  EXPECT_EQ(jb.joiner_challenge, j.joiner_challenge);
  EXPECT_EQ(jb.proof, j.proof);

  Accept a;
  a.proof = random_array<kProofBytes>(rng);
  encode(a, bytes);
  ASSERT_EQ(bytes.size(), kAcceptBytes);
  Accept ab;
  ASSERT_TRUE(decode(bytes, ab).ok());
  EXPECT_EQ(ab.proof, a.proof);
}

TEST(Codec, HelloRoundTripKeepsEveryField) {
  for (const Hand hand : {Hand::kLeft, Hand::kRight}) {
    const Hello h = testing::make_hello("Site Ä — 東京", 1.61f, hand, -2.7f);
    std::vector<std::byte> bytes;
    ASSERT_TRUE(encode(h, bytes).ok());
    EXPECT_EQ(bytes.size(), 66 + h.site.size() + h.avatar.model.size());
    Hello back;
    ASSERT_TRUE(decode(bytes, back).ok());
    EXPECT_EQ(back.site, h.site);
    EXPECT_EQ(back.avatar.model, h.avatar.model);
    const BodyCalibration& b = back.avatar.body;
    EXPECT_EQ(b.height, h.avatar.body.height);
    EXPECT_EQ(b.arm_length, h.avatar.body.arm_length);
    EXPECT_EQ(b.deictic_hand, hand);
    EXPECT_EQ(b.T_world_root.translation, h.avatar.body.T_world_root.translation);
    EXPECT_LT((b.T_world_root.rotation - h.avatar.body.T_world_root.rotation).norm(), 1e-6f);
    EXPECT_EQ(b.rest_wrist_in_root[0], h.avatar.body.rest_wrist_in_root[0]);
    EXPECT_EQ(b.rest_wrist_in_root[1], h.avatar.body.rest_wrist_in_root[1]);
  }
}

TEST(Codec, TargetMapRoundTripKeepsEveryObject) {
  for (const int count : {0, 1, 7, static_cast<int>(kMaxTargetObjects)}) {
    const TargetMap m = testing::make_target_map("B", count);
    std::vector<std::byte> bytes;
    ASSERT_TRUE(encode(m, bytes).ok()) << count;
    ASSERT_LE(bytes.size() + kSealOverheadBytes, kMaxPacketBytes) << "fits a sealed packet";
    TargetMap back;
    ASSERT_TRUE(decode(bytes, back).ok()) << count;
    EXPECT_EQ(back.site, m.site);
    ASSERT_EQ(back.objects.size(), m.objects.size());
    for (std::size_t i = 0; i < m.objects.size(); ++i) {
      EXPECT_EQ(back.objects[i].id, m.objects[i].id);
      EXPECT_EQ(back.objects[i].name, m.objects[i].name);
      EXPECT_EQ(back.objects[i].kind, m.objects[i].kind);
      EXPECT_EQ(back.objects[i].position, m.objects[i].position);
      EXPECT_EQ(back.objects[i].size, m.objects[i].size);
    }
  }
}

TEST(Codec, HeartbeatAndByeRoundTrip) {
  std::array<std::byte, 16> buffer{};
  ASSERT_EQ(encode(Heartbeat{0xA1B2C3D4u}, buffer), kHeartbeatBytes);
  EXPECT_EQ(buffer[1], std::byte{0xD4}) << "little-endian";
  Heartbeat hb;
  ASSERT_TRUE(decode(std::span(buffer).first(kHeartbeatBytes), hb).ok());
  EXPECT_EQ(hb.count, 0xA1B2C3D4u);
  for (std::uint8_t r = 0; r <= kMaxByeReason; ++r) {
    ASSERT_EQ(encode(Bye{static_cast<ByeReason>(r)}, buffer), kByeBytes);
    Bye bye;
    ASSERT_TRUE(decode(std::span(buffer).first(kByeBytes), bye).ok());
    EXPECT_EQ(bye.reason, static_cast<ByeReason>(r));
  }
  EXPECT_EQ(encode(Heartbeat{}, std::span(buffer).first(4)), 0u) << "too small: nothing written";
}

void expect_frames_close(const TrackingFrame& back, const TrackingFrame& f) {
  constexpr float kPos = 0.0005f * 1.7321f + 1e-6f;  // 0.5 mm per axis
  EXPECT_NEAR(back.time, f.time, 0.0005);
  EXPECT_EQ(back.valid, f.valid);
  EXPECT_LE((back.T_world_head.translation - f.T_world_head.translation).norm(), kPos);
  EXPECT_LE(angle_deg(back.T_world_head.rotation, f.T_world_head.rotation), kRotationErrorBoundDeg);
  EXPECT_LE(angle_deg(back.gaze, f.gaze), kDirectionErrorBoundDeg);
  for (int h = 0; h < 2; ++h) {
    EXPECT_LE((back.T_world_wrist[h].translation - f.T_world_wrist[h].translation).norm(), kPos);
    EXPECT_LE(angle_deg(back.T_world_wrist[h].rotation, f.T_world_wrist[h].rotation),
              kRotationErrorBoundDeg);
    EXPECT_LE((back.index_tip[h] - f.index_tip[h]).norm(), kPos);
  }
  EXPECT_EQ(back.head_target, f.head_target);
  EXPECT_EQ(back.hand_target, f.hand_target);
  EXPECT_LE((back.head_target_position - f.head_target_position).norm(), kPos);
  EXPECT_LE((back.hand_target_position - f.hand_target_position).norm(), kPos);
}

TEST(Codec, TrackingRoundTripWithinQuantisationBounds) {
  const Vec3 root(0.5f, 1.6f, -1.25f);
  std::array<std::byte, kTrackingBytes> buffer{};
  for (std::uint32_t seq : {0u, 1u, 77u, 1000u, 0xFFFFFFFFu}) {
    const TrackingMessage m{seq, testing::moving_frame(seq % 5000, root)};
    const TrackingEncoding enc = encode_tracking(m, root, buffer);
    ASSERT_EQ(enc.bytes, kTrackingBytes);
    EXPECT_EQ(enc.dropped_parts, 0);
    TrackingMessage back;
    ASSERT_TRUE(decode_tracking(buffer, root, back).ok());
    EXPECT_EQ(back.sequence, seq);
    expect_frames_close(back.frame, m.frame);
    // Quantisation is idempotent: the decoded frame encodes to the same bytes.
    std::array<std::byte, kTrackingBytes> again{};
    ASSERT_EQ(encode_tracking(back, root, again).bytes, kTrackingBytes);
    EXPECT_EQ(again, buffer);
  }
}

TEST(Codec, TrackingPartsThatCannotBeSentAreSentAsNotValid) {
  const Vec3 root(0, 1.6f, 0);
  TrackingMessage m{5, testing::moving_frame(5, root)};
  m.frame.T_world_head.translation.x() = std::nanf("");
  m.frame.index_tip[index(Hand::kLeft)] = root + Vec3(40.0f, 0, 0);  // beyond ±32.767 m
  m.frame.gaze = Vec3::Zero();
  m.frame.hand_target_position = root + Vec3(0, 0, -500.0f);  // far, but the direction is kept
  m.frame.head_target = 2'000'000;                            // not a wire id
  std::array<std::byte, kTrackingBytes> buffer{};
  const TrackingEncoding enc = encode_tracking(m, root, buffer);
  ASSERT_EQ(enc.bytes, kTrackingBytes);
  EXPECT_EQ(enc.dropped_parts, tracked::kHead | tracked::kGaze | tracked::kLeftHand);
  TrackingMessage back;
  ASSERT_TRUE(decode_tracking(buffer, root, back).ok());
  EXPECT_EQ(back.frame.valid, tracked::kRightHand);
  EXPECT_EQ(back.frame.head_target, kNoTarget);
  EXPECT_EQ(back.frame.hand_target, m.frame.hand_target);
  const Vec3 far = back.frame.hand_target_position - root;
  EXPECT_NEAR(far.normalized().dot(Vec3(0, 0, -1)), 1.0f, 1e-6f);
  EXPECT_NEAR(far.norm(), kPositionLimit, 0.001f);
}

TEST(Codec, TrackingTimeIsWholeMillisecondsModulo32Bits) {
  const Vec3 root(0, 1.6f, 0);
  std::array<std::byte, kTrackingBytes> buffer{};
  TrackingMessage m{1, testing::moving_frame(1, root)};
  for (const double t : {0.0, 12.3456, 4294967.295, 4294967.296 + 1.5, -0.25}) {
    m.frame.time = t;
    ASSERT_EQ(encode_tracking(m, root, buffer).bytes, kTrackingBytes);
    TrackingMessage back;
    ASSERT_TRUE(decode_tracking(buffer, root, back).ok());
    const double wrapped =
        std::fmod(std::fmod(std::round(t * 1000.0), 4294967296.0) + 4294967296.0, 4294967296.0) /
        1000.0;
    EXPECT_DOUBLE_EQ(back.frame.time, wrapped) << t;
  }
}

}  // namespace
}  // namespace deixis::net

namespace deixis::net {
namespace {

TEST(WireText, AcceptsUtf8WithoutControlCharactersOnly) {
  EXPECT_TRUE(is_wire_text(std::string_view("Jupiter")));
  EXPECT_TRUE(is_wire_text(std::string_view("Jüpiter — 東京 🪐")));
  EXPECT_TRUE(is_wire_text(std::string_view("")));
  EXPECT_FALSE(is_wire_text(std::string_view("tab\there")));
  EXPECT_FALSE(is_wire_text(std::string_view("nul\0here", 8)));
  EXPECT_FALSE(is_wire_text(std::string_view("del\x7f")));
  EXPECT_FALSE(is_wire_text(std::string_view("\xc2\x85")));          // U+0085, a C1 control
  EXPECT_FALSE(is_wire_text(std::string_view("\xc0\xaf")));          // overlong '/'
  EXPECT_FALSE(is_wire_text(std::string_view("\xed\xa0\x80")));      // a surrogate
  EXPECT_FALSE(is_wire_text(std::string_view("\xf4\x90\x80\x80")));  // beyond U+10FFFF
  EXPECT_FALSE(is_wire_text(std::string_view("\xe6\x9d")));          // cut short
  EXPECT_FALSE(is_wire_text(std::string_view("\x80")));              // a lone continuation byte
  EXPECT_FALSE(is_wire_text(std::string_view("\xff")));
}

}  // namespace
}  // namespace deixis::net
