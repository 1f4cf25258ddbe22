// The session's defences on the simulated network and on real loopback sockets in this process
// (docs/security.md): the joiner's floor on the key cost, unauthenticated disconnect data and byes
// that cannot end a sealed session, bounded work per service() call, the flood cut-off, padded
// sealed packets, the key derived off the caller's thread, and a host that serves the first peer
// to complete its handshake while strangers hold connections, with per-address budgets and
// backoff.

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <thread>
#include <vector>

#include "net/enet_link.h"
#include "net/messages.h"
#include "net/passphrase.h"
#include "net/tracking_codec.h"
#include "session_pair.h"

namespace deixis::net {
namespace {

using testing::SessionPair;
using Side = SimulatedNetwork::Side;

TEST(Hardening, AJoinerRefusesAHostThatAsksForAWeakKeyCost) {
  SessionConfig host = testing::session_config(Role::kHost, "A", "pw");
  host.kdf = {1, 8};
  SessionConfig joiner = testing::session_config(Role::kJoiner, "B", "pw");
  joiner.min_kdf = kInteractiveKdf;  // the default floor
  SessionPair pair({}, 21, std::move(host), std::move(joiner));
  pair.start();
  pair.run_until([&] { return pair.joiner.state() == SessionState::kRefused; }, 3.0);
  EXPECT_EQ(pair.joiner.state(), SessionState::kRefused);
  EXPECT_EQ(pair.joiner.status().last_bye, ByeReason::kWeakKeyCost);
  EXPECT_FALSE(pair.joiner.deriving_key()) << "no key was derived for the weak cost";
  EXPECT_EQ(pair.host.status().auth_failures, 0u) << "the joiner sent no proof";
  EXPECT_EQ(pair.host.status().streams, 0u);
}

TEST(Hardening, AKeyCostAtTheFloorIsAccepted) {
  SessionConfig host = testing::session_config(Role::kHost, "A", "pw");
  host.kdf = {2, 8};
  SessionConfig joiner = testing::session_config(Role::kJoiner, "B", "pw");
  joiner.min_kdf = {2, 8};
  SessionPair pair({}, 22, std::move(host), std::move(joiner));
  EXPECT_TRUE(pair.connect());
}

TEST(Hardening, SpoofedDisconnectDataCannotRefuseAStreamingJoiner) {
  SessionPair pair({}, 23, "pw", "pw");
  ASSERT_TRUE(pair.connect());
  // "Authentication failed" as ENet disconnect data, from nobody who could seal it.
  pair.network.inject_disconnect(Side::kJoiner,
                                 static_cast<std::uint32_t>(ByeReason::kAuthenticationFailed));
  pair.step(0.05);
  EXPECT_NE(pair.joiner.state(), SessionState::kRefused);
  EXPECT_EQ(pair.joiner.status().last_end, EndCause::kTransportLost);
  // It comes back by itself (the host notices the old connection gone by its time-out).
  EXPECT_TRUE(pair.run_until([&] { return pair.joiner.status().streams == 2; }, 10.0));
}

TEST(Hardening, DisconnectDataStillRefusesDuringTheHandshake) {
  // Before anything is authenticated, a refusal is all a joiner has to go by (a lost bye).
  SessionPair pair({}, 24, "pw", "pw");
  pair.start();
  pair.run_until([&] { return pair.joiner.state() == SessionState::kHandshake; }, 1.0);
  ASSERT_EQ(pair.joiner.state(), SessionState::kHandshake);
  pair.network.inject_disconnect(Side::kJoiner,
                                 static_cast<std::uint32_t>(ByeReason::kAuthenticationFailed));
  pair.step(0.05);
  EXPECT_EQ(pair.joiner.state(), SessionState::kRefused);
}

TEST(Hardening, APlainByeCannotEndASealedSession) {
  SessionPair pair({}, 25, "pw", "pw");
  ASSERT_TRUE(pair.connect());
  std::array<std::byte, kByeBytes> bye{};
  encode(Bye{ByeReason::kAuthenticationFailed}, bye);
  pair.network.inject(Side::kJoiner, Channel::kReliable, bye);
  pair.step(0.05);
  EXPECT_EQ(pair.joiner.state(), SessionState::kStreaming);
  EXPECT_EQ(pair.joiner.drops()[DropReason::kUnauthenticated], 1u);
}

TEST(Hardening, OneServiceCallHandlesABoundedNumberOfEvents) {
  SessionPair pair({}, 26);
  ASSERT_TRUE(pair.connect());
  pair.run_until([] { return false; }, 0.2);
  const std::size_t limit = pair.joiner.config().max_events_per_service;
  std::vector<std::byte> junk = {std::byte{0x7F}};  // an unknown type: dropped, counted
  const std::size_t flood = 3 * limit;
  for (std::size_t i = 0; i < flood; ++i) {
    pair.network.inject(Side::kJoiner, Channel::kReliable, junk);
  }
  pair.now += 0.05;
  pair.network.set_time(pair.now);
  const std::uint64_t before = pair.joiner.drops().total;
  pair.joiner.service(pair.now);
  EXPECT_EQ(pair.joiner.drops().total - before, limit) << "the rest waits for the next call";
  EXPECT_EQ(pair.joiner.stats().service_bounded, 1u);
  pair.joiner.service(pair.now);
  pair.joiner.service(pair.now);
  EXPECT_EQ(pair.joiner.drops().total - before, flood);
}

TEST(Hardening, APeerSendingTrackingAtTenTimesTheRateIsCutOff) {
  SessionPair pair({}, 27, "pw", "pw");
  ASSERT_TRUE(pair.connect());
  const Vec3 root = pair.joiner.config().hello.avatar.body.T_world_root.translation;
  std::uint32_t sent = 0;
  // 300 frames a second from the joiner, for up to 4 s.
  const bool cut = pair.run_until(
      [&] {
        pair.joiner.send_tracking(testing::moving_frame(sent++, root));
        return pair.host.stats().floods_cut > 0;
      },
      4.0, 1.0 / 300.0);
  EXPECT_TRUE(cut);
  EXPECT_EQ(pair.host.status().last_end, EndCause::kFlooded);
  EXPECT_EQ(pair.host.status().last_bye, ByeReason::kFlooding);
  // The budget holds 2 s at 120 packets/s beyond the rate: cut after about 1.3 s, not at once.
  EXPECT_GT(sent, 300u);
}

TEST(Hardening, TrackingAtTheNormalRateIsNeverCutOff) {
  SessionPair pair({}, 28, "pw", "pw");
  ASSERT_TRUE(pair.connect());
  const Vec3 root = pair.joiner.config().hello.avatar.body.T_world_root.translation;
  std::uint32_t sent = 0;
  double next = pair.now;
  pair.run_until(
      [&] {
        if (pair.now >= next) {
          pair.joiner.send_tracking(testing::moving_frame(sent++, root));
          pair.host.send_tracking(testing::moving_frame(sent, root));
          next += testing::kTick;
        }
        return false;
      },
      10.0, 0.002);
  EXPECT_EQ(pair.host.stats().floods_cut + pair.joiner.stats().floods_cut, 0u);
  EXPECT_TRUE(pair.both_streaming());
}

TEST(Hardening, SealedHellosAndMapsDoNotTellNameLengths) {
  // Two sessions whose sites' names (and target maps' names) differ in length send the same
  // number of bytes through the handshake and hellos.
  const auto bytes_until_streaming = [](const std::string& host_site) {
    SessionConfig host = testing::session_config(Role::kHost, host_site, "pw");
    SessionPair pair({}, 29, std::move(host), testing::session_config(Role::kJoiner, "B", "pw"));
    EXPECT_TRUE(pair.connect());
    return pair.host.stats().bytes_sent;
  };
  EXPECT_EQ(bytes_until_streaming("A"), bytes_until_streaming("A site with a much longer name"));
}

TEST(Hardening, TheHelloMustCarryTheSiteNameTheProofBound) {
  // The proofs carry "B"; a hello that says "Mallory" afterwards is refused. The test seals it
  // as the joiner would: it cannot, without the session's keys, so it checks the other way round:
  // a joiner whose hello differs from the name it proved is never accepted.
  SessionConfig joiner = testing::session_config(Role::kJoiner, "B", "pw");
  SessionPair pair({}, 30, testing::session_config(Role::kHost, "A", "pw"), std::move(joiner));
  ASSERT_TRUE(pair.connect());
  const Hello* remote = pair.host.remote_hello();
  ASSERT_NE(remote, nullptr);
  EXPECT_EQ(remote->site, "B");
}

TEST(Hardening, TheKeyIsDerivedOffTheCallersThread) {
  SimulatedNetwork network({}, 31);
  SessionConfig config = testing::session_config(Role::kHost, "A", "pw");
  config.kdf = kInteractiveKdf;  // 64 MiB: tens of milliseconds at least
  config.derive_on_this_thread = false;
  Session host(network.host(), config);
  EXPECT_TRUE(host.deriving_key()) << "the constructor returned before Argon2id finished";
  for (int i = 0; i < 2000 && host.deriving_key(); ++i) {
    host.service(0.0);
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  EXPECT_FALSE(host.deriving_key()) << "the key arrived and was taken";
}

TEST(Hardening, AVersionOneJoinerIsToldItsVersionIsWrong) {
  // A join as protocol version 1 laid it out: 72 bytes, version 1. The host reads type, magic
  // and version first, so the old peer hears "version mismatch", not silence.
  SimulatedNetwork network({}, 32);
  Session host(network.host(), testing::session_config(Role::kHost, "A", "pw"));
  Link& old = network.joiner();
  double now = 0.0;
  host.start(now);
  const PeerId peer = old.connect();
  std::vector<std::byte> join(72, std::byte{0});
  join[0] = std::byte{0x02};
  join[1] = std::byte{'D'};
  join[2] = std::byte{'E'};
  join[3] = std::byte{'I'};
  join[4] = std::byte{'X'};
  join[5] = std::byte{1};  // version 1, little-endian
  join[7] = std::byte{1};  // passphrase
  int bye = -1;
  for (int i = 0; i < 200 && bye < 0; ++i) {
    now += 0.005;
    network.set_time(now);
    for (LinkEvent e = old.next_event(0); e.kind != LinkEvent::Kind::kNone; e = old.next_event(0)) {
      Bye b;
      if (e.kind == LinkEvent::Kind::kReceived && e.bytes[0] == std::byte{0x01}) {
        old.send(peer, Channel::kReliable, join);  // answers the welcome
      } else if (e.kind == LinkEvent::Kind::kReceived && decode(e.bytes, b).ok()) {
        bye = static_cast<int>(b.reason);
      }
    }
    host.service(now);
  }
  EXPECT_EQ(bye, static_cast<int>(ByeReason::kVersionMismatch));
  EXPECT_EQ(host.drops()[DropReason::kWrongVersion], 1u);
}

// ---- real loopback sockets in this process: the many-peer host ----

using SteadyClock = std::chrono::steady_clock;

double seconds_since(SteadyClock::time_point start) {
  return std::chrono::duration<double>(SteadyClock::now() - start).count();
}

struct LoopbackHost {
  std::unique_ptr<EnetLink> link = EnetLink::host("127.0.0.1", 0);
  Session session;
  explicit LoopbackHost(SessionConfig config) : session(*link, std::move(config)) {}
};

// Services `sessions` and the silent `links` until `done` or `seconds` pass.
bool run_real(const std::vector<Session*>& sessions, std::vector<std::unique_ptr<EnetLink>>& links,
              SteadyClock::time_point start, double seconds, const std::function<bool()>& done) {
  while (seconds_since(start) < seconds) {
    for (Session* s : sessions) {
      s->service(seconds_since(start), 1);
    }
    for (auto& l : links) {
      for (LinkEvent e = l->next_event(0); e.kind != LinkEvent::Kind::kNone; e = l->next_event(0)) {
        if (e.kind == LinkEvent::Kind::kDisconnected) {
          l->connect();  // let go: try again at once
        }
      }
    }
    if (done()) {
      return true;
    }
  }
  return done();
}

SessionConfig real_config(Role role, const std::string& site) {
  SessionConfig c = testing::session_config(role, site, "pw");
  c.derive_on_this_thread = false;
  return c;
}

TEST(HardeningLoopback, StrangersHoldingConnectionsDoNotKeepTheJoinerOut) {
  LoopbackHost host(real_config(Role::kHost, "A"));
  const auto start = SteadyClock::now();
  host.session.start(0.0);
  // Silent strangers from other addresses, each reconnecting when let go: more than the table
  // holds, so the host must evict and turn away.
  std::vector<std::unique_ptr<EnetLink>> strangers;
  for (int i = 0; i < 40; ++i) {
    strangers.push_back(
        EnetLink::join("127.0.0.1", host.link->port(), "127.0.0." + std::to_string(2 + i / 4)));
    strangers.back()->connect();
  }
  run_real({&host.session}, strangers, start, 1.0, [] { return false; });
  EXPECT_GT(host.session.pending(), 0u) << "the strangers hold handshake slots";
  auto link = EnetLink::join("127.0.0.1", host.link->port());
  Session joiner(*link, real_config(Role::kJoiner, "B"));
  const double tried_at = seconds_since(start);
  joiner.start(tried_at);
  const bool streaming = run_real({&host.session, &joiner}, strangers, start, tried_at + 5.0,
                                  [&] { return joiner.state() == SessionState::kStreaming; });
  EXPECT_TRUE(streaming);
  EXPECT_LT(seconds_since(start) - tried_at, 2.0) << "in within 2 s of trying";
  EXPECT_LE(host.session.pending(), host.session.config().max_pending);
  const StrangerStats& s = host.session.strangers();
  std::printf(
      "strangers: connected %llu, over budget %llu, evicted %llu, timed out %llu\n",
      static_cast<unsigned long long>(s.connected), static_cast<unsigned long long>(s.over_budget),
      static_cast<unsigned long long>(s.evicted), static_cast<unsigned long long>(s.timed_out));
}

TEST(HardeningLoopback, AnAddressThatFailsProofsIsHeldBackAndOthersAreNot) {
  SessionConfig host_config = real_config(Role::kHost, "A");
  host_config.free_failures = 2;
  LoopbackHost host(std::move(host_config));
  const auto start = SteadyClock::now();
  host.session.start(0.0);
  std::vector<std::unique_ptr<EnetLink>> none;
  // A guesser at 127.0.0.9: sessions with the wrong passphrase, one after the other.
  std::uint64_t refusals = 0;
  for (int i = 0; i < 5; ++i) {
    auto link = EnetLink::join("127.0.0.1", host.link->port(), "127.0.0.9");
    SessionConfig c = real_config(Role::kJoiner, "M");
    c.passphrase = "guess " + std::to_string(i);
    Session guesser(*link, c);
    guesser.start(seconds_since(start));
    run_real({&host.session, &guesser}, none, start, seconds_since(start) + 3.0, [&] {
      return guesser.state() == SessionState::kRefused || guesser.status().attempts > 1;
    });
    refusals += guesser.state() == SessionState::kRefused ? 1 : 0;
  }
  EXPECT_EQ(host.session.status().auth_failures, refusals);
  EXPECT_GE(host.session.strangers().held_back, 1u) << "after 2 free failures, a backoff";
  // The rightful joiner, from another address, is not held back.
  auto link = EnetLink::join("127.0.0.1", host.link->port());
  Session joiner(*link, real_config(Role::kJoiner, "B"));
  const double tried_at = seconds_since(start);
  joiner.start(tried_at);
  EXPECT_TRUE(run_real({&host.session, &joiner}, none, start, tried_at + 5.0,
                       [&] { return joiner.state() == SessionState::kStreaming; }));
  EXPECT_LT(seconds_since(start) - tried_at, 2.0);
}

TEST(HardeningLoopback, BusyIsToldOnlyToAPeerThatProvedThePassphrase) {
  LoopbackHost host(real_config(Role::kHost, "A"));
  const auto start = SteadyClock::now();
  host.session.start(0.0);
  std::vector<std::unique_ptr<EnetLink>> none;
  auto first_link = EnetLink::join("127.0.0.1", host.link->port());
  Session first(*first_link, real_config(Role::kJoiner, "B"));
  first.start(0.0);
  ASSERT_TRUE(run_real({&host.session, &first}, none, start, 5.0,
                       [&] { return first.state() == SessionState::kStreaming; }));
  // A stranger without the passphrase: refused as any wrong guess is, never told "busy".
  auto stranger_link = EnetLink::join("127.0.0.1", host.link->port(), "127.0.0.7");
  SessionConfig wrong = real_config(Role::kJoiner, "M");
  wrong.passphrase = "wrong";
  Session stranger(*stranger_link, wrong);
  stranger.start(seconds_since(start));
  run_real({&host.session, &first, &stranger}, none, start, seconds_since(start) + 3.0,
           [&] { return stranger.state() == SessionState::kRefused; });
  EXPECT_EQ(stranger.status().last_bye, ByeReason::kAuthenticationFailed);
  // A second site with the passphrase is told busy (and keeps trying), and the call goes on.
  auto second_link = EnetLink::join("127.0.0.1", host.link->port(), "127.0.0.8");
  Session second(*second_link, real_config(Role::kJoiner, "C"));
  second.start(seconds_since(start));
  run_real({&host.session, &first, &second}, none, start, seconds_since(start) + 3.0,
           [&] { return second.status().last_bye == ByeReason::kBusy; });
  EXPECT_EQ(second.status().last_bye, ByeReason::kBusy);
  EXPECT_NE(second.state(), SessionState::kRefused);
  EXPECT_EQ(first.state(), SessionState::kStreaming);
  EXPECT_GE(host.session.strangers().busy, 1u);
}

}  // namespace
}  // namespace deixis::net
