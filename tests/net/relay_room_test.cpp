// Room sessions (net/room_session.h) over the real relay and its clients on loopback: three sealed
// members meet, each verifies the other two and hears their tracking; a member with the wrong
// passphrase sees no one and is shown to no one; a member that leaves is gone for the others.
// This is the transport's end of docs/rooms-protocol.md; the room layer's own rules are tested
// over an in-process relay (room_keys_test). Every wait is bounded.

#include <gtest/gtest.h>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "net/enet_link.h"
#include "net/relay_client.h"
#include "net/relay_server.h"
#include "net/room_session.h"
#include "net_fixtures.h"

namespace deixis::net {
namespace {

using SteadyClock = std::chrono::steady_clock;

// A site in the room: its relay client, the transport over it, and its room session.
struct Site {
  Site(const std::string& name, const std::string& passphrase, std::uint16_t port, double now) {
    RelayClientOptions o;
    o.port = port;
    o.room = room_token("relay room test");
    client = std::make_unique<RelayClient>(o, now);
    transport = std::make_unique<RelayTransport>(*client);
    RoomConfig c;
    c.hello = testing::make_hello(name);
    c.target_map = testing::make_target_map(name);
    c.passphrase = passphrase;
    c.kdf = c.min_kdf = {1, 8};  // the key's cost is not what this test is about
    session = std::make_unique<RoomSession>(*transport, std::move(c));
  }
  void poll(double now) {
    session->poll(now);
    client->poll(now, *session);
  }
  std::unique_ptr<RelayClient> client;
  std::unique_ptr<RelayTransport> transport;
  std::unique_ptr<RoomSession> session;
};

class RelayRoom : public ::testing::Test {
 protected:
  double now() const { return std::chrono::duration<double>(SteadyClock::now() - start_).count(); }
  Site& site(const std::string& name, const std::string& passphrase = "pw") {
    sites_.push_back(std::make_unique<Site>(name, passphrase, link_->port(), now()));
    return *sites_.back();
  }
  bool run(const std::function<bool()>& done, double seconds) {
    const double until = now() + seconds;
    while (now() < until) {
      relay_.service(now(), 1);
      for (auto& s : sites_) {
        s->poll(now());
      }
      if (done()) {
        return true;
      }
    }
    return done();
  }

  SteadyClock::time_point start_ = SteadyClock::now();
  std::unique_ptr<EnetLink> link_ = EnetLink::host("127.0.0.1", 0, HostLimits{64, 64});
  RelayServer relay_{*link_, RelayServerConfig{}};
  std::vector<std::unique_ptr<Site>> sites_;
};

TEST_F(RelayRoom, ThreeSealedMembersMeetAndHearEachOther) {
  Site& a = site("A");
  Site& b = site("B");
  Site& c = site("C");
  const auto met = [&] {
    return a.session->people().size() == 2 && b.session->people().size() == 2 &&
           c.session->people().size() == 2;
  };
  ASSERT_TRUE(run(met, 15.0)) << a.session->people().size() << " " << b.session->people().size()
                              << " " << c.session->people().size();
  EXPECT_TRUE(a.session->sealed());
  std::uint32_t frame = 0;
  const Vec3 root = a.session->config().hello.avatar.body.T_world_root.translation;
  const auto heard_all = [&] {
    for (Site* s : {&a, &b, &c}) {
      s->session->send_tracking(testing::moving_frame(frame, root), now());
    }
    ++frame;
    for (Site* s : {&a, &b, &c}) {
      for (const MemberId p : s->session->people()) {
        const PersonStats* st = s->session->person_stats(p);
        if (st == nullptr || st->tracking_received < 10) {
          return false;
        }
      }
    }
    return true;
  };
  ASSERT_TRUE(run(heard_all, 5.0));
  EXPECT_EQ(relay_.drops().total, 0u);
  // C leaves: A and B are left with each other.
  c.session->leave(now());
  c.client->close(now());
  ASSERT_TRUE(
      run([&] { return a.session->people().size() == 1 && b.session->people().size() == 1; }, 5.0));
}

TEST_F(RelayRoom, AWrongPassphraseSeesNoOneAndIsShownToNoOne) {
  Site& a = site("A");
  Site& b = site("B");
  ASSERT_TRUE(run(
      [&] { return a.session->people().size() == 1 && b.session->people().size() == 1; }, 15.0));
  Site& intruder = site("X", "not the passphrase");
  ASSERT_TRUE(run([&] { return intruder.client->in_room(); }, 5.0));
  run([] { return false; }, 3.0);  // time for keys to be tried (Argon2 included)
  EXPECT_TRUE(intruder.session->people().empty());
  EXPECT_EQ(a.session->people().size(), 1u);
  EXPECT_EQ(b.session->people().size(), 1u);
  EXPECT_EQ(relay_.members_in(room_token("relay room test")), 3u) << "the relay cannot tell";
}

}  // namespace
}  // namespace deixis::net
