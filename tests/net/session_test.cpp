// The session state machine over the simulated network, on an injected clock: connect, handshake,
// hello exchange, streaming; passphrases right, wrong and one-sided; heartbeat time-out with the
// stream hidden first; automatic reconnect with backoff; bye; and hostile peers that skip the
// handshake or speak another version.

#include <gtest/gtest.h>

#include "angles.h"
#include "core/error.h"
#include "net/messages.h"
#include "net/tracking_codec.h"
#include "session_pair.h"

namespace deixis::net {
namespace {

using testing::SessionPair;
using Side = SimulatedNetwork::Side;

// Both sides send a frame every tick and play what they receive; returns frames played by the
// host (sent by the joiner).
struct Streams {
  std::uint32_t sent = 0;
  std::vector<std::pair<std::uint32_t, TrackingFrame>> host_played;
  std::uint64_t joiner_played = 0;
  std::uint64_t host_missed = 0;
};

void stream(SessionPair& pair, double seconds, Streams& s) {
  const Vec3 host_root = pair.host.config().hello.avatar.body.T_world_root.translation;
  const Vec3 joiner_root = pair.joiner.config().hello.avatar.body.T_world_root.translation;
  const double end = pair.now + seconds;
  double next_tick = pair.now;
  while (pair.now < end) {
    if (pair.now >= next_tick) {
      pair.host.send_tracking(testing::moving_frame(s.sent, host_root));
      pair.joiner.send_tracking(testing::moving_frame(s.sent, joiner_root));
      ++s.sent;
      next_tick += testing::kTick;
    }
    pair.step(0.002);
    for (Playout p = pair.host.next_frame(pair.now);
         p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed;
         p = pair.host.next_frame(pair.now)) {
      if (p.kind == PlayoutKind::kFrame) {
        s.host_played.emplace_back(p.sequence, *p.frame);
      } else {
        ++s.host_missed;
      }
    }
    for (Playout p = pair.joiner.next_frame(pair.now);
         p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed;
         p = pair.joiner.next_frame(pair.now)) {
      s.joiner_played += p.kind == PlayoutKind::kFrame ? 1 : 0;
    }
  }
}

void expect_streams_tracking(SessionPair& pair) {
  Streams s;
  stream(pair, 2.0, s);
  ASSERT_GT(s.host_played.size(), 50u);
  EXPECT_GT(s.joiner_played, 50u);
  EXPECT_EQ(s.host_missed, 0u);
  const Vec3 joiner_root = pair.joiner.config().hello.avatar.body.T_world_root.translation;
  for (std::size_t i = 0; i < s.host_played.size(); ++i) {
    const auto& [seq, frame] = s.host_played[i];
    if (i > 0) {
      EXPECT_EQ(seq, s.host_played[i - 1].first + 1) << "in order, no gaps";
    }
    // What the joiner's tracker produced for that sequence number, within quantisation.
    const TrackingFrame sent = testing::moving_frame(seq, joiner_root);
    EXPECT_LT((frame.T_world_head.translation - sent.T_world_head.translation).norm(), 0.001f);
    EXPECT_LT(angle_deg(frame.T_world_wrist[1].rotation, sent.T_world_wrist[1].rotation), 0.1);
    EXPECT_EQ(frame.hand_target, sent.hand_target);
  }
}

TEST(Session, OpenSessionConnectsExchangesHellosAndStreams) {
  SessionPair pair;
  ASSERT_TRUE(pair.connect());
  EXPECT_FALSE(pair.host.sealed());
  const Hello* at_host = pair.host.remote_hello();
  const Hello* at_joiner = pair.joiner.remote_hello();
  ASSERT_NE(at_host, nullptr);
  ASSERT_NE(at_joiner, nullptr);
  EXPECT_EQ(at_host->site, "B");
  EXPECT_EQ(at_joiner->site, "A");
  EXPECT_EQ(at_host->avatar.body.height, pair.joiner.config().hello.avatar.body.height);
  EXPECT_EQ(at_host->avatar.body.deictic_hand, Hand::kLeft);
  pair.run_until([&] { return pair.host.remote_target_map() && pair.joiner.remote_target_map(); },
                 1.0);
  const TargetMap* map_at_host = pair.host.remote_target_map();
  const TargetMap* map_at_joiner = pair.joiner.remote_target_map();
  ASSERT_NE(map_at_host, nullptr);
  ASSERT_NE(map_at_joiner, nullptr);
  EXPECT_EQ(map_at_host->objects.size(), 5u);
  ASSERT_EQ(map_at_joiner->objects.size(), 3u);
  EXPECT_EQ(map_at_joiner->objects[2].name, "object 3 Jüpiter");
  expect_streams_tracking(pair);
  EXPECT_EQ(pair.host.drops().total, 0u);
  EXPECT_EQ(pair.joiner.drops().total, 0u);
  EXPECT_EQ(pair.host.status().streams, 1u);
  EXPECT_EQ(pair.joiner.status().attempts, 1u);
}

TEST(Session, TrackingIsNotSentBeforeStreaming) {
  SessionPair pair;
  EXPECT_FALSE(pair.joiner.send_tracking(testing::moving_frame(0, Vec3::Zero())));
  pair.start();
  EXPECT_FALSE(pair.joiner.send_tracking(testing::moving_frame(0, Vec3::Zero())));
  EXPECT_EQ(pair.joiner.next_frame(pair.now).kind, PlayoutKind::kNoStream);
}

TEST(Session, TheSamePassphraseAuthenticatesAndSealsEverything) {
  SessionPair pair({}, 2, "correct horse battery staple", "correct horse battery staple");
  ASSERT_TRUE(pair.connect());
  EXPECT_TRUE(pair.host.sealed());
  EXPECT_TRUE(pair.joiner.sealed());
  const Hello* hello = pair.host.remote_hello();
  ASSERT_NE(hello, nullptr);
  EXPECT_EQ(hello->site, "B");
  expect_streams_tracking(pair);
  EXPECT_EQ(pair.host.drops().total, 0u);
  EXPECT_EQ(pair.joiner.drops().total, 0u);
}

TEST(Session, AWrongPassphraseIsRefusedAndLearnsNothing) {
  SessionPair pair({}, 3, "correct horse", "incorrect horse");
  pair.start();
  pair.run_until([&] { return pair.joiner.state() == SessionState::kRefused; }, 3.0);
  EXPECT_EQ(pair.joiner.state(), SessionState::kRefused);
  EXPECT_EQ(pair.joiner.status().last_bye, ByeReason::kAuthenticationFailed);
  EXPECT_EQ(pair.host.status().auth_failures, 1u);
  EXPECT_EQ(pair.host.pending(), 0u) << "the stranger was let go";
  EXPECT_EQ(pair.host.status().streams, 0u);
  EXPECT_EQ(pair.host.state(), SessionState::kWaiting) << "the host listens on";
  EXPECT_EQ(pair.joiner.remote_hello(), nullptr);
  EXPECT_EQ(pair.joiner.remote_target_map(), nullptr);
  EXPECT_EQ(pair.host.remote_hello(), nullptr);
  // The refused joiner does not come back by itself.
  pair.run_until([] { return false; }, 10.0, 0.01);
  EXPECT_EQ(pair.joiner.status().attempts, 1u);
  EXPECT_EQ(pair.host.status().auth_failures, 1u);
}

TEST(Session, APassphraseOnOneSideOnlyIsRefused) {
  {
    SessionPair pair({}, 4, "secret", "");
    pair.start();
    pair.run_until([&] { return pair.joiner.state() == SessionState::kRefused; }, 3.0);
    EXPECT_EQ(pair.joiner.state(), SessionState::kRefused);
    EXPECT_EQ(pair.joiner.status().last_bye, ByeReason::kPassphraseRequired);
  }
  {
    SessionPair pair({}, 5, "", "secret");
    pair.start();
    pair.run_until([&] { return pair.joiner.state() == SessionState::kRefused; }, 3.0);
    EXPECT_EQ(pair.joiner.state(), SessionState::kRefused);
    EXPECT_EQ(pair.joiner.status().last_bye, ByeReason::kPassphraseUnexpected);
    EXPECT_EQ(pair.joiner.status().last_end, EndCause::kRefusedPeer);
  }
}

TEST(Session, SilenceHidesTheStreamThenTimesOutThenReconnects) {
  SessionPair pair;
  ASSERT_TRUE(pair.connect());
  Streams s;
  stream(pair, 1.0, s);
  pair.network.set_partitioned(true);
  const double cut = pair.now;
  // The stream is hidden after jitter.stop_after; the peer times out after heartbeat_timeout.
  double hidden_at = -1.0;
  double timed_out_at = -1.0;
  const Vec3 root = pair.joiner.config().hello.avatar.body.T_world_root.translation;
  while (pair.now < cut + 5.0 && timed_out_at < 0.0) {
    pair.joiner.send_tracking(testing::moving_frame(s.sent++, root));
    pair.step(0.01);
    Playout p = pair.host.next_frame(pair.now);
    while (p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed) {
      p = pair.host.next_frame(pair.now);
    }
    if (hidden_at < 0.0 && p.kind == PlayoutKind::kNoStream) {
      hidden_at = pair.now;
    }
    if (pair.host.status().last_end == EndCause::kTimedOut) {
      timed_out_at = pair.now;
    }
  }
  ASSERT_GT(hidden_at, 0.0);
  ASSERT_GT(timed_out_at, 0.0);
  EXPECT_LT(hidden_at - cut, 0.5 + 0.1) << "hidden, not frozen";
  EXPECT_NEAR(timed_out_at - cut, 3.0, 0.6) << "the visible time-out";
  EXPECT_EQ(pair.host.status().timeouts, 1u);
  EXPECT_EQ(pair.host.state(), SessionState::kWaiting);
  pair.run_until([&] { return pair.joiner.status().last_end == EndCause::kTimedOut; }, 1.0);
  EXPECT_EQ(pair.joiner.status().timeouts, 1u);
  // While partitioned, the joiner keeps trying with a growing backoff.
  pair.run_until([] { return false; }, 8.0, 0.01);
  EXPECT_GE(pair.joiner.status().attempts, 3u);
  EXPECT_LE(pair.joiner.status().attempts, 5u);
  EXPECT_FALSE(pair.both_streaming());
  // The network heals: back to streaming by itself.
  pair.network.set_partitioned(false);
  ASSERT_TRUE(pair.run_until([&] { return pair.both_streaming(); }, 8.0));
  EXPECT_EQ(pair.host.status().streams, 2u);
  EXPECT_EQ(pair.joiner.status().streams, 2u);
  expect_streams_tracking(pair);
}

TEST(Session, ByeEndsTheConnectionAndHidesTheStream) {
  SessionPair pair;
  ASSERT_TRUE(pair.connect());
  Streams s;
  stream(pair, 0.5, s);
  pair.joiner.close(pair.now);
  EXPECT_EQ(pair.joiner.state(), SessionState::kIdle);
  pair.run_until([&] { return pair.host.state() == SessionState::kWaiting; }, 1.0);
  EXPECT_EQ(pair.host.state(), SessionState::kWaiting);
  EXPECT_EQ(pair.host.status().last_end, EndCause::kByeFromPeer);
  EXPECT_EQ(pair.host.status().last_bye, ByeReason::kLeaving);
  EXPECT_EQ(pair.host.next_frame(pair.now).kind, PlayoutKind::kNoStream);
  // The joiner stays closed until started again, then connects to the same host.
  pair.run_until([] { return false; }, 3.0);
  EXPECT_EQ(pair.joiner.state(), SessionState::kIdle);
  pair.joiner.start(pair.now);
  ASSERT_TRUE(pair.run_until([&] { return pair.both_streaming(); }, 3.0));
}

TEST(Session, AHostThatLeavesIsReconnectedToWhenItReturns) {
  SessionPair pair;
  ASSERT_TRUE(pair.connect());
  pair.host.close(pair.now);
  pair.run_until([&] { return pair.joiner.status().last_end == EndCause::kByeFromPeer; }, 1.0);
  EXPECT_NE(pair.joiner.state(), SessionState::kRefused) << "leaving is not refusing";
  pair.run_until([] { return false; }, 2.0);
  pair.host.start(pair.now);
  ASSERT_TRUE(pair.run_until([&] { return pair.both_streaming(); }, 6.0));
}

TEST(Session, PlainPacketsInAPassphraseSessionAreDroppedAsUnauthenticated) {
  SessionPair pair({}, 6, "pw", "pw");
  ASSERT_TRUE(pair.connect());
  const Vec3 root = pair.host.config().hello.avatar.body.T_world_root.translation;
  std::vector<std::byte> tracking(kTrackingBytes);
  encode_tracking({999, testing::moving_frame(999, root)}, root, tracking);
  std::vector<std::byte> hello;
  ASSERT_TRUE(encode(testing::make_hello("Mallory"), hello).ok());
  std::vector<std::byte> forged(tracking.size() + kSealOverheadBytes, std::byte{0});
  forged[0] = std::byte{0x20};
  const std::uint64_t received = pair.joiner.stats().tracking_received;
  pair.network.inject(Side::kJoiner, Channel::kTracking, tracking);
  pair.network.inject(Side::kJoiner, Channel::kReliable, hello);
  pair.network.inject(Side::kJoiner, Channel::kTracking, forged);
  pair.step(0.05);
  EXPECT_EQ(pair.joiner.drops()[DropReason::kUnauthenticated], 2u);
  EXPECT_EQ(pair.joiner.drops()[DropReason::kDecryptFailed], 1u);
  EXPECT_EQ(pair.joiner.stats().tracking_received, received);
  const Hello* remote = pair.joiner.remote_hello();
  ASSERT_NE(remote, nullptr);
  EXPECT_EQ(remote->site, "A");
  EXPECT_EQ(pair.joiner.state(), SessionState::kStreaming);
}

TEST(Session, DuplicatedSealedPacketsAreRejectedAsReplays) {
  LinkConditions c;
  c.duplicate = 0.5;
  SessionPair pair(c, 7, "pw", "pw");
  ASSERT_TRUE(pair.connect());
  Streams s;
  stream(pair, 2.0, s);
  EXPECT_GT(pair.host.drops()[DropReason::kReplayed], 10u);
  EXPECT_EQ(pair.host.jitter().duplicates, 0u) << "stopped before the jitter buffer";
  EXPECT_EQ(pair.host.drops().total, pair.host.drops()[DropReason::kReplayed]);
}

// The test plays the host by hand: a joiner session meets a host speaking protocol version 3.
TEST(Session, AnotherProtocolVersionIsRefusedWithAReason) {
  SimulatedNetwork network({}, 8);
  Session joiner(network.joiner(), testing::session_config(Role::kJoiner, "B"));
  Link& host = network.host();
  double now = 0.0;
  joiner.start(now);
  std::vector<std::byte> welcome;
  encode(Welcome{}, welcome);
  welcome[5] = static_cast<std::byte>(kProtocolVersion + 1);  // a version after ours
  bool got_bye = false;
  for (int i = 0; i < 200 && !got_bye; ++i) {
    now += 0.005;
    network.set_time(now);
    for (LinkEvent e = host.next_event(0); e.kind != LinkEvent::Kind::kNone;
         e = host.next_event(0)) {
      if (e.kind == LinkEvent::Kind::kConnected) {
        host.send(e.peer, Channel::kReliable, welcome);
      }
      Bye bye;
      if (e.kind == LinkEvent::Kind::kReceived && decode(e.bytes, bye).ok()) {
        EXPECT_EQ(bye.reason, ByeReason::kVersionMismatch);
        got_bye = true;
      }
    }
    joiner.service(now);
  }
  EXPECT_TRUE(got_bye);
  EXPECT_EQ(joiner.state(), SessionState::kRefused);
  EXPECT_EQ(joiner.drops()[DropReason::kWrongVersion], 1u);
}

// The test plays a joiner that does not know the passphrase and does not follow the protocol:
// tracking and a hello before any handshake, then a join with a made-up proof.
TEST(Session, AHostileJoinerGetsNothingButAWelcomeAndABye) {
  SimulatedNetwork network({}, 9);
  Session host(network.host(), testing::session_config(Role::kHost, "A", "pw"));
  Link& rogue = network.joiner();
  double now = 0.0;
  host.start(now);
  const PeerId peer = rogue.connect();
  const Vec3 root = Vec3::Zero();
  std::vector<std::byte> tracking(kTrackingBytes);
  encode_tracking({0, testing::moving_frame(0, root)}, root, tracking);
  std::vector<std::byte> hello;
  ASSERT_TRUE(encode(testing::make_hello("Mallory"), hello).ok());
  std::vector<std::uint8_t> received_types;
  bool sent_join = false;
  for (int i = 0; i < 400; ++i) {
    now += 0.005;
    network.set_time(now);
    for (LinkEvent e = rogue.next_event(0); e.kind != LinkEvent::Kind::kNone;
         e = rogue.next_event(0)) {
      if (e.kind == LinkEvent::Kind::kConnected) {
        rogue.send(peer, Channel::kTracking, tracking);
        rogue.send(peer, Channel::kReliable, hello);
      }
      if (e.kind == LinkEvent::Kind::kReceived) {
        received_types.push_back(std::to_integer<std::uint8_t>(e.bytes[0]));
        if (!sent_join && e.bytes[0] == std::byte{0x01}) {
          Join join;
          join.auth = AuthMode::kPassphrase;
          join.proof.fill(std::byte{0x42});
          std::vector<std::byte> bytes;
          encode(join, bytes);
          rogue.send(peer, Channel::kReliable, bytes);
          rogue.send(peer, Channel::kTracking, tracking);
          sent_join = true;
        }
      }
    }
    host.service(now);
  }
  EXPECT_EQ(received_types, (std::vector<std::uint8_t>{0x01, 0x07})) << "welcome, bye";
  EXPECT_EQ(host.status().auth_failures, 1u);
  EXPECT_EQ(host.stats().tracking_received, 0u);
  EXPECT_EQ(host.remote_hello(), nullptr);
  // The tracking before the join and the hello; the tracking sent after the join arrives once the
  // host has already closed the connection, so the transport discards it.
  EXPECT_EQ(host.drops()[DropReason::kUnauthenticated], 2u);
  EXPECT_EQ(host.state(), SessionState::kWaiting);
}

TEST(Session, AJoinerThatSaysNothingIsLetGoAfterThePendingTimeOut) {
  SimulatedNetwork network({}, 10);
  const net::SessionConfig config = testing::session_config(Role::kHost, "A");
  Session host(network.host(), config);
  double now = 0.0;
  host.start(now);
  network.joiner().connect();
  bool was_pending = false;
  for (; now < config.pending_timeout - 0.1; now += 0.01) {
    network.set_time(now);
    host.service(now);
    network.joiner().next_event(0);
    was_pending = was_pending || host.pending() == 1;
  }
  EXPECT_TRUE(was_pending);
  EXPECT_EQ(host.pending(), 1u) << "still within its deadline";
  for (; now < config.pending_timeout + 0.5; now += 0.01) {
    network.set_time(now);
    host.service(now);
    network.joiner().next_event(0);
  }
  EXPECT_EQ(host.pending(), 0u);
  EXPECT_EQ(host.strangers().timed_out, 1u);
  EXPECT_EQ(host.state(), SessionState::kWaiting);
}

TEST(Session, StatusShowsSilenceAndRoundTrip) {
  LinkConditions c;
  c.delay = 0.04;
  SessionPair pair(c);
  ASSERT_TRUE(pair.connect());
  pair.run_until([] { return false; }, 1.0);
  EXPECT_EQ(pair.joiner.status().round_trip_ms, 80u);
  EXPECT_LE(pair.joiner.silence(pair.now), 0.5 + 0.04 + 0.01) << "heartbeats every 0.5 s";
  EXPECT_EQ(state_name(pair.joiner.state()), "streaming");
}

TEST(Session, AnInvalidOwnHelloIsAConfigurationError) {
  SimulatedNetwork network({}, 11);
  SessionConfig config = testing::session_config(Role::kHost, "A");
  config.hello.avatar.body.height = std::nanf("");
  EXPECT_THROW(Session(network.host(), config), Error);
  config = testing::session_config(Role::kHost, "A");
  config.target_map.objects.push_back(config.target_map.objects.front());  // duplicate id
  EXPECT_THROW(Session(network.host(), config), Error);
}

// A recalibration (deixis xr's button): our hello again, mid-stream, sealed like the first. The
// peer takes the new body and counts a second hello in the same stream; tracking goes on.
TEST(Session, ANewHelloMidStreamReachesThePeerWithTheNewBody) {
  SessionPair pair({}, 12, "correct horse battery staple", "correct horse battery staple");
  ASSERT_TRUE(pair.connect());
  ASSERT_EQ(pair.host.status().hellos, 1u);
  Hello again = pair.joiner.config().hello;
  again.avatar.body.height = 1.52f;
  again.avatar.body.arm_length = 0.66f;
  pair.joiner.set_hello(again);
  ASSERT_TRUE(pair.run_until([&] { return pair.host.status().hellos == 2; }, 1.0));
  EXPECT_EQ(pair.host.remote_hello()->avatar.body.height, 1.52f);
  EXPECT_EQ(pair.host.remote_hello()->avatar.body.arm_length, 0.66f);
  EXPECT_EQ(pair.host.status().streams, 1u) << "the same stream";
  EXPECT_EQ(pair.host.state(), SessionState::kStreaming);
  expect_streams_tracking(pair);
  EXPECT_EQ(pair.host.drops().total, 0u);
  // A hello under another name is refused here rather than sent (the proof bound the name), and
  // one that breaks a wire rule too; neither replaces the hello we send.
  Hello renamed = again;
  renamed.site = "C";
  EXPECT_THROW(pair.joiner.set_hello(renamed), Error);
  Hello broken = again;
  broken.avatar.body.height = std::nanf("");
  EXPECT_THROW(pair.joiner.set_hello(broken), Error);
  EXPECT_EQ(pair.joiner.config().hello.avatar.body.height, 1.52f);
}

}  // namespace
}  // namespace deixis::net
