// Rooms end to end over real ENet on loopback, in this process: three RoomSessions, each with its
// own RelayClient (through RelayTransport), meet through a RelayServer, verify each other with
// the passphrase (Argon2id off the frame loop, as in a site), and stream tracking sealed; a wrong
// passphrase sees no one and is seen by no one; after the relay restarts everyone is back with
// new ids and verified again. Every wait is bounded.

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <thread>
#include <vector>

#include "net/enet_link.h"
#include "net/relay_client.h"
#include "net/relay_server.h"
#include "net/room_session.h"
#include "room_fixture.h"

namespace deixis::net {
namespace {

using SteadyClock = std::chrono::steady_clock;

struct Site {
  Site(const std::string& room, std::uint16_t port, double now, RoomConfig config)
      : client(options(room, port), now),
        transport(client),
        session(transport, std::move(config)) {}
  static RelayClientOptions options(const std::string& room, std::uint16_t port) {
    RelayClientOptions o;
    o.port = port;
    o.room = room_token(room);
    return o;
  }
  RelayClient client;
  RelayTransport transport;
  RoomSession session;
};

struct Relay {
  explicit Relay(std::uint16_t port = 0)
      : link(EnetLink::host("127.0.0.1", port, HostLimits{64, 16})),
        server(*link, RelayServerConfig{}) {}
  std::unique_ptr<EnetLink> link;
  RelayServer server;
};

RoomConfig config(const std::string& site, const std::string& passphrase) {
  RoomConfig c = testing::room_config(site, passphrase);
  c.derive_on_this_thread = false;  // as a site does: the frame loop never waits for Argon2id
  return c;
}

class RoomOverRelay : public ::testing::Test {
 protected:
  double now() const { return std::chrono::duration<double>(SteadyClock::now() - start_).count(); }

  Site& add(const std::string& site, const std::string& passphrase) {
    sites_.push_back(
        std::make_unique<Site>("omega", relay_->link->port(), now(), config(site, passphrase)));
    return *sites_.back();
  }
  // One frame loop tick for every site: the room's timers, then the relay client's events.
  void step() {
    const double t = now();
    if (relay_) {
      relay_->server.service(t, 1);
    }
    for (auto& s : sites_) {
      s->session.poll(t);
      s->client.poll(t, s->session);
    }
  }
  bool run(const std::function<bool()>& done, double seconds) {
    const double until = now() + seconds;
    while (now() < until) {
      step();
      if (done()) {
        return true;
      }
    }
    return done();
  }
  // Every site sends a frame at 30 Hz for `seconds` and plays what is due; frames played per
  // (receiver, sender's site name).
  std::map<std::pair<std::size_t, std::string>, int> stream(double seconds) {
    std::map<std::pair<std::size_t, std::string>, int> played;
    const double until = now() + seconds;
    double next = now();
    std::uint32_t seq = 0;
    while (now() < until) {
      if (now() >= next) {
        next += 1.0 / 30.0;
        for (auto& s : sites_) {
          const Vec3 root = s->session.config().hello.avatar.body.T_world_root.translation;
          s->session.send_tracking(testing::moving_frame(seq, root), now());
        }
        ++seq;
      }
      step();
      for (std::size_t i = 0; i < sites_.size(); ++i) {
        RoomSession& r = sites_[i]->session;
        for (const MemberId p : r.people()) {
          for (Playout o = r.next_playout(p, now());
               o.kind == PlayoutKind::kFrame || o.kind == PlayoutKind::kMissed;
               o = r.next_playout(p, now())) {
            played[{i, r.hello(p)->site}] += o.kind == PlayoutKind::kFrame ? 1 : 0;
          }
        }
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return played;
  }
  bool everyone_sees(std::size_t n) const {
    return std::all_of(sites_.begin(), sites_.end(),
                       [&](const auto& s) { return s->session.people().size() == n; });
  }

  SteadyClock::time_point start_ = SteadyClock::now();
  std::unique_ptr<Relay> relay_ = std::make_unique<Relay>();
  std::vector<std::unique_ptr<Site>> sites_;
};

TEST_F(RoomOverRelay, ThreeSitesMeetVerifyEachOtherAndStreamSealed) {
  add("A", "pw");
  add("B", "pw");
  add("C", "pw");
  ASSERT_TRUE(run([&] { return everyone_sees(2); }, 5.0));
  for (const auto& s : sites_) {
    EXPECT_TRUE(s->session.sealed());
    EXPECT_EQ(s->session.stats().verified, 2u);
  }
  const auto played = stream(2.0);
  for (std::size_t i = 0; i < 3; ++i) {
    for (const char* site : {"A", "B", "C"}) {
      if (sites_[i]->session.config().hello.site != site) {
        EXPECT_GE((played.at({i, site})), 50) << i << " from " << site;
      }
    }
  }
  EXPECT_EQ(relay_->server.stats().entered, 3u);
}

TEST_F(RoomOverRelay, AWrongPassphraseSeesNoOneAndIsSeenByNoOne) {
  add("A", "pw");
  ASSERT_TRUE(run([&] { return sites_[0]->session.state() == RoomState::kInRoom; }, 3.0));
  Site& w = add("W", "guess");
  ASSERT_TRUE(run([&] { return w.session.state() == RoomState::kInRoom; }, 3.0));
  add("B", "pw");
  ASSERT_TRUE(run(
      [&] {
        return sites_[0]->session.people().size() == 1 && sites_[2]->session.people().size() == 1;
      },
      5.0));
  stream(1.0);
  EXPECT_TRUE(w.session.people().empty());
  EXPECT_EQ(w.session.stats().verified, 0u);
  EXPECT_GE(w.session.stats().auth_failures, 1u);
  EXPECT_GE(sites_[0]->session.stats().auth_failures, 1u);
  EXPECT_EQ(sites_[0]->session.hello(w.session.self()), nullptr);
  EXPECT_EQ(sites_[2]->session.hello(w.session.self()), nullptr);
  // W heard only B's key message: nothing sealed by A or B reached it.
  EXPECT_EQ(w.client.stats().received, 1u);
}

TEST_F(RoomOverRelay, EveryoneIsBackVerifiedWithin5sOfARestartedRelay) {
  add("A", "pw");
  add("B", "pw");
  add("C", "pw");
  ASSERT_TRUE(run([&] { return everyone_sees(2); }, 5.0));
  const std::uint16_t port = relay_->link->port();
  relay_.reset();
  ASSERT_TRUE(run([&] { return everyone_sees(0); }, 3.0));
  relay_ = std::make_unique<Relay>(port);
  const double listening = now();
  ASSERT_TRUE(run([&] { return everyone_sees(2); }, 5.0));
  EXPECT_LT(now() - listening, 5.0);
  for (const auto& s : sites_) {
    EXPECT_EQ(s->session.stats().entries, 2u);
    EXPECT_EQ(s->session.stats().verified, 4u);
  }
  const auto played = stream(1.0);
  EXPECT_GE((played.at({0, "B"})), 20);
}

}  // namespace
}  // namespace deixis::net
