// The relay and its clients over real ENet on loopback, in this process (docs/relay.md): rooms
// kept apart, member ids and joined/left events, the room-size cap, forwards to everyone or one
// member on the channel they came on, silent connections that do not keep a member out, a
// flooding member cut off, a restarted relay that its clients find again, garbage datagrams, and
// a relay and a direct-session host telling each other apart. Every wait is bounded.

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <functional>
#include <memory>
#include <vector>

#include "net/enet_link.h"
#include "net/relay_client.h"
#include "net/relay_server.h"
#include "net/relay_wire.h"
#include "session_pair.h"

namespace deixis::net {
namespace {

using SteadyClock = std::chrono::steady_clock;

struct Payload {
  MemberId from = kNoMember;
  Channel channel = Channel::kReliable;
  std::vector<std::uint8_t> bytes;
};

// A room member that records what its relay client tells it and enters when ready.
class Member : public RelayListener {
 public:
  Member(const std::string& room, std::uint16_t port, double now, const std::string& local = "",
         std::vector<std::uint8_t> announce = {1, 2, 3})
      : announce_(std::move(announce)) {
    RelayClientOptions o;
    o.port = port;
    o.room = room_token(room);
    o.local_address = local;
    client = std::make_unique<RelayClient>(o, now);
  }

  void on_relay_ready() override {
    ++ready;
    if (enter_when_ready) {
      client->enter(params, announce_);
    }
  }
  bool enter() { return client->enter(params, announce_); }
  void on_entered(MemberId self_id, std::span<const std::uint8_t> room_params,
                  std::span<const RoomMember> already_there) override {
    ++entered;
    self = self_id;
    seen_params.assign(room_params.begin(), room_params.end());
    others.clear();
    for (const RoomMember& m : already_there) {
      others.push_back(m.id);
      announces.emplace_back(m.announce.begin(), m.announce.end());
    }
  }
  void on_member_joined(const RoomMember& m) override {
    others.push_back(m.id);
    announces.emplace_back(m.announce.begin(), m.announce.end());
    ++joined;
  }
  void on_member_left(MemberId id) override {
    others.erase(std::remove(others.begin(), others.end(), id), others.end());
    ++left;
  }
  void on_payload(MemberId from, Channel channel, std::span<const std::uint8_t> p) override {
    payloads.push_back({from, channel, {p.begin(), p.end()}});
  }
  void on_refused(RelayRefusal why) override { refusals.push_back(why); }
  void on_relay_lost() override {
    ++lost;
    others.clear();
    self = kNoMember;
  }

  bool has(MemberId id) const {
    return std::find(others.begin(), others.end(), id) != others.end();
  }

  std::unique_ptr<RelayClient> client;
  bool enter_when_ready = true;
  std::vector<std::uint8_t> params = {'P', 1};
  int ready = 0, entered = 0, joined = 0, left = 0, lost = 0;
  MemberId self = kNoMember;
  std::vector<std::uint8_t> seen_params;
  std::vector<MemberId> others;
  std::vector<std::vector<std::uint8_t>> announces;
  std::vector<Payload> payloads;
  std::vector<RelayRefusal> refusals;

 private:
  std::vector<std::uint8_t> announce_;
};

struct Relay {
  explicit Relay(RelayServerConfig config = {}, std::uint16_t port = 0)
      : link(EnetLink::host("127.0.0.1", port, HostLimits{256, 64})),
        server(*link, std::move(config)) {}
  std::unique_ptr<EnetLink> link;
  RelayServer server;
};

class RelayLoopback : public ::testing::Test {
 protected:
  double now() const { return std::chrono::duration<double>(SteadyClock::now() - start_).count(); }

  void step() {
    const double t = now();
    if (relay) {
      relay->server.service(t, 1);
    }
    for (Member* m : members_) {
      m->client->poll(t, *m);
    }
    for (auto& l : silent) {
      for (LinkEvent e = l->next_event(0); e.kind != LinkEvent::Kind::kNone; e = l->next_event(0)) {
        if (e.kind == LinkEvent::Kind::kDisconnected) {
          l->connect();  // let go: try again at once
        }
      }
    }
  }
  // Runs until `done` or `seconds` more pass.
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
  void settle(double seconds) {
    run([] { return false; }, seconds);
  }
  std::unique_ptr<Member> member(const std::string& room, const std::string& local = "",
                                 std::vector<std::uint8_t> announce = {1, 2, 3}) {
    auto m = std::make_unique<Member>(room, relay->link->port(), now(), local, std::move(announce));
    members_.push_back(m.get());
    return m;
  }
  void forget(Member* m) {
    members_.erase(std::remove(members_.begin(), members_.end(), m), members_.end());
  }
  bool all_in(std::initializer_list<Member*> ms, std::size_t others_each) {
    return std::all_of(ms.begin(), ms.end(), [&](Member* m) {
      return m->client->in_room() && m->others.size() == others_each;
    });
  }

  SteadyClock::time_point start_ = SteadyClock::now();
  std::unique_ptr<Relay> relay = std::make_unique<Relay>();
  std::vector<Member*> members_;
  std::vector<std::unique_ptr<EnetLink>> silent;
};

std::vector<std::uint8_t> bytes_of(std::initializer_list<int> v) {
  std::vector<std::uint8_t> out;
  for (int x : v) {
    out.push_back(static_cast<std::uint8_t>(x));
  }
  return out;
}

TEST_F(RelayLoopback, MembersGetIdsAndSeeJoinsAndLeavesOfTheirRoomOnly) {
  auto a1 = member("alpha", "", bytes_of({0xA1}));
  ASSERT_TRUE(run([&] { return a1->client->in_room(); }, 3.0));
  auto a2 = member("alpha", "", bytes_of({0xA2}));
  auto b1 = member("beta", "", bytes_of({0xB1}));
  ASSERT_TRUE(run([&] { return all_in({a1.get(), a2.get()}, 1) && b1->client->in_room(); }, 3.0));
  EXPECT_NE(a1->self, a2->self);
  EXPECT_GE(a1->self, kFirstMember);
  EXPECT_LE(a2->self, kLastMember);
  EXPECT_TRUE(a1->has(a2->self));
  EXPECT_TRUE(a2->has(a1->self));
  EXPECT_EQ(a1->joined, 1);
  EXPECT_EQ(a2->announces.at(0), bytes_of({0xA1})) << "the newcomer gets the others' announces";
  EXPECT_EQ(a1->announces.at(0), bytes_of({0xA2})) << "and they get its";
  EXPECT_TRUE(b1->others.empty()) << "beta sees nobody of alpha";
  EXPECT_EQ(relay->server.rooms(), 2u);
  EXPECT_EQ(relay->server.members_in(room_token("alpha")), 2u);

  // Forwards to everyone stay in their room.
  ASSERT_TRUE(b1->client->send(kAllMembers, Channel::kReliable, bytes_of({9, 9})));
  ASSERT_TRUE(a1->client->send(kAllMembers, Channel::kReliable, bytes_of({7})));
  ASSERT_TRUE(run([&] { return !a2->payloads.empty(); }, 2.0));
  settle(0.2);
  EXPECT_TRUE(b1->payloads.empty());
  EXPECT_TRUE(a1->payloads.empty()) << "a sender does not hear itself";
  EXPECT_EQ(a2->payloads.size(), 1u);

  // A leaves; the other hears it, beta hears nothing.
  const MemberId gone = a2->self;
  a2->client->close(now());
  forget(a2.get());
  ASSERT_TRUE(run([&] { return a1->left == 1; }, 2.0));
  EXPECT_FALSE(a1->has(gone));
  EXPECT_EQ(b1->left, 0);
  // Back again: a fresh id.
  auto a3 = member("alpha");
  ASSERT_TRUE(run([&] { return all_in({a1.get(), a3.get()}, 1); }, 3.0));
  EXPECT_NE(a3->self, gone) << "a member coming back gets a fresh id";
  // The last member leaving forgets the room.
  b1->client->close(now());
  forget(b1.get());
  ASSERT_TRUE(run([&] { return relay->server.rooms() == 1; }, 2.0));
  EXPECT_EQ(relay->server.members_in(room_token("beta")), 0u);
}

TEST_F(RelayLoopback, TheFirstMembersParamsAreTheRooms) {
  auto a = member("gamma");
  a->params = bytes_of({'F', 'I', 'R', 'S', 'T'});
  ASSERT_TRUE(run([&] { return a->client->in_room(); }, 3.0));
  auto b = member("gamma");
  b->params = bytes_of({'O', 'T', 'H'});
  ASSERT_TRUE(run([&] { return b->client->in_room(); }, 3.0));
  EXPECT_EQ(a->seen_params, a->params);
  EXPECT_EQ(b->seen_params, a->params);
}

TEST_F(RelayLoopback, AMemberMayTakeAWhileToEnter) {
  // The room layer may enter a little after the welcome: the client does not count the quiet
  // relay as lost meanwhile.
  auto m = member("late");
  m->enter_when_ready = false;
  ASSERT_TRUE(run([&] { return m->ready == 1; }, 3.0));
  settle(2.0);
  EXPECT_EQ(m->lost, 0);
  ASSERT_TRUE(m->enter());
  ASSERT_TRUE(run([&] { return m->client->in_room(); }, 2.0));
  EXPECT_EQ(m->client->stats().attempts, 1u);
}

TEST_F(RelayLoopback, AFullRoomIsRefusedClearly) {
  RelayServerConfig c;
  c.max_people = 2;
  relay = std::make_unique<Relay>(c);
  auto a = member("small");
  auto b = member("small");
  ASSERT_TRUE(run([&] { return all_in({a.get(), b.get()}, 1); }, 3.0));
  auto third = member("small");
  ASSERT_TRUE(run([&] { return !third->refusals.empty(); }, 3.0));
  EXPECT_EQ(third->refusals.front(), RelayRefusal::kRoomFull);
  EXPECT_TRUE(is_final(RelayRefusal::kRoomFull));
  EXPECT_TRUE(third->client->stopped());
  EXPECT_FALSE(third->client->in_room());
  EXPECT_NE(describe(RelayRefusal::kRoomFull).find("full"), std::string_view::npos);
  EXPECT_EQ(relay->server.stats().refused_room_full, 1u);
  settle(0.5);
  EXPECT_EQ(third->client->stats().attempts, 1u) << "a final refusal is not retried";
  EXPECT_EQ(a->joined + b->joined, 1) << "nobody saw the third";
}

TEST_F(RelayLoopback, ForwardsReachEveryoneElseOrOneMemberOnTheirChannel) {
  auto a = member("delta");
  auto b = member("delta");
  auto c = member("delta");
  ASSERT_TRUE(run([&] { return all_in({a.get(), b.get(), c.get()}, 2); }, 4.0));
  std::vector<std::uint8_t> big(kRelayPayloadMax, 0x5A);
  ASSERT_TRUE(a->client->send(kAllMembers, Channel::kTracking, bytes_of({1, 2, 3, 4})));
  ASSERT_TRUE(a->client->send(c->self, Channel::kReliable, bytes_of({42})));
  ASSERT_TRUE(b->client->send(a->self, Channel::kReliable, big));
  EXPECT_FALSE(b->client->send(a->self, Channel::kReliable,
                               std::vector<std::uint8_t>(kRelayPayloadMax + 1)));
  EXPECT_FALSE(b->client->send(a->self, Channel::kReliable, {}));
  ASSERT_TRUE(run(
      [&] { return b->payloads.size() == 1 && c->payloads.size() == 2 && a->payloads.size() == 1; },
      3.0));
  settle(0.2);
  ASSERT_EQ(b->payloads.size(), 1u) << "the unicast to c reached c only";
  EXPECT_EQ(b->payloads[0].from, a->self);
  EXPECT_EQ(b->payloads[0].channel, Channel::kTracking) << "the channel is kept";
  EXPECT_EQ(b->payloads[0].bytes, bytes_of({1, 2, 3, 4}));
  ASSERT_EQ(c->payloads.size(), 2u);
  const auto reliable = std::find_if(c->payloads.begin(), c->payloads.end(), [](const Payload& p) {
    return p.channel == Channel::kReliable;
  });
  ASSERT_NE(reliable, c->payloads.end());
  EXPECT_EQ(reliable->bytes, bytes_of({42}));
  EXPECT_EQ(reliable->from, a->self);
  ASSERT_EQ(a->payloads.size(), 1u);
  EXPECT_EQ(a->payloads[0].bytes, big) << "the largest payload goes through whole";
  // To an id not in the room: counted, delivered to no one.
  ASSERT_TRUE(a->client->send(static_cast<MemberId>(200), Channel::kReliable, bytes_of({1})));
  ASSERT_TRUE(run([&] { return relay->server.stats().to_absent == 1; }, 2.0));
}

TEST_F(RelayLoopback, SilentConnectionsDoNotKeepAMemberOut) {
  // Silent connections from several other addresses, each reconnecting when let go: more than
  // the pending table holds.
  RelayServerConfig c;
  c.max_pending = 16;
  relay = std::make_unique<Relay>(c);
  for (int i = 0; i < 40; ++i) {
    silent.push_back(
        EnetLink::join("127.0.0.1", relay->link->port(), "127.0.0." + std::to_string(2 + i / 8)));
    silent.back()->connect();
  }
  settle(1.0);
  EXPECT_GT(relay->server.pending(), 0u) << "the silent ones hold pending slots";
  const double tried_at = now();
  auto m = member("epsilon");
  ASSERT_TRUE(run([&] { return m->client->in_room(); }, 5.0));
  EXPECT_LT(now() - tried_at, 2.0) << "in within 2 s of trying";
  const RelayServerStats& s = relay->server.stats();
  EXPECT_GT(s.pending_over_budget + s.pending_evicted, 0u);
  settle(3.5);
  EXPECT_GT(relay->server.stats().pending_timed_out + s.pending_evicted, 0u);
  EXPECT_TRUE(m->client->in_room()) << "the member stays";
}

TEST_F(RelayLoopback, AFloodingMemberIsCutOff) {
  auto calm = member("zeta");
  auto flood = member("zeta");
  ASSERT_TRUE(run([&] { return all_in({calm.get(), flood.get()}, 1); }, 3.0));
  const MemberId flooder = flood->self;
  const std::vector<std::uint8_t> p(64, 1);
  bool cut = run(
      [&] {
        for (int i = 0; i < 20; ++i) {
          flood->client->send(kAllMembers, Channel::kTracking, p);
        }
        return relay->server.stats().floods_cut > 0;
      },
      4.0);
  ASSERT_TRUE(cut);
  ASSERT_TRUE(run([&] { return !calm->has(flooder); }, 2.0)) << "the others see it leave";
  ASSERT_TRUE(run([&] { return !flood->refusals.empty(); }, 2.0));
  EXPECT_EQ(flood->refusals.front(), RelayRefusal::kFlooding);
  EXPECT_FALSE(flood->client->stopped()) << "a flooder may come back after its backoff";
}

TEST_F(RelayLoopback, ClientsAreBackInTheirRoomWithin5sOfARestartedRelay) {
  auto a = member("eta");
  auto b = member("eta");
  ASSERT_TRUE(run([&] { return all_in({a.get(), b.get()}, 1); }, 3.0));
  const std::uint16_t port = relay->link->port();
  relay.reset();  // the relay dies
  ASSERT_TRUE(run([&] { return a->lost == 1 && b->lost == 1; }, 2.5))
      << "clients notice a dead relay within 2 s (plus slack)";
  settle(0.5);
  relay = std::make_unique<Relay>(RelayServerConfig{}, port);
  const double listening = now();
  ASSERT_TRUE(run([&] { return all_in({a.get(), b.get()}, 1); }, 5.0));
  EXPECT_LT(now() - listening, 5.0);
  EXPECT_EQ(a->entered, 2);
  ASSERT_TRUE(a->client->send(kAllMembers, Channel::kTracking, bytes_of({3})));
  ASSERT_TRUE(run([&] { return !b->payloads.empty(); }, 2.0));
}

TEST_F(RelayLoopback, ClientsNoticeADeadRelayWithin2s) {
  auto a = member("theta");
  ASSERT_TRUE(run([&] { return a->client->in_room(); }, 3.0));
  // A relay that stops answering (its process hangs): its link stays, nothing is serviced.
  auto frozen = std::move(relay);
  const double died = now();
  ASSERT_TRUE(run([&] { return a->lost == 1; }, 3.0));
  EXPECT_LT(now() - died, 2.0);
}

TEST_F(RelayLoopback, GarbageIsDroppedAndCountedWhileMembersCarryOn) {
  auto a = member("iota");
  auto b = member("iota");
  ASSERT_TRUE(run([&] { return all_in({a.get(), b.get()}, 1); }, 3.0));
  // Raw UDP datagrams that are not ENet at all.
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(relay->link->port());
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  std::vector<unsigned char> junk(200);
  for (int i = 0; i < 500; ++i) {
    for (std::size_t k = 0; k < junk.size(); ++k) {
      junk[k] = static_cast<unsigned char>((i * 131 + static_cast<int>(k) * 7) & 0xFF);
    }
    sendto(fd, junk.data(), 1 + static_cast<std::size_t>(i) % junk.size(), 0,
           reinterpret_cast<const sockaddr*>(&to), sizeof to);
  }
  close(fd);
  // A connected stranger sending relay garbage before entering, then a member sending garbage.
  auto stranger = EnetLink::join("127.0.0.1", relay->link->port(), "127.0.0.5");
  const PeerId sp = stranger->connect();
  bool up = false;
  run(
      [&] {
        for (LinkEvent e = stranger->next_event(0); e.kind != LinkEvent::Kind::kNone;
             e = stranger->next_event(0)) {
          up = up || e.kind == LinkEvent::Kind::kConnected;
        }
        return up;
      },
      2.0);
  ASSERT_TRUE(up);
  const std::array<std::byte, 3> bad_enter = {std::byte{0x31}, std::byte{'D'}, std::byte{'X'}};
  stranger->send(sp, Channel::kReliable, bad_enter);
  const std::uint64_t drops_before = relay->server.drops().total;
  ASSERT_TRUE(run([&] { return relay->server.drops().total > drops_before; }, 2.0));
  EXPECT_EQ(relay->server.drops()[DropReason::kTruncated], 1u);
  // Members carry on.
  ASSERT_TRUE(a->client->send(kAllMembers, Channel::kTracking, bytes_of({1})));
  ASSERT_TRUE(run([&] { return !b->payloads.empty(); }, 2.0));
  EXPECT_TRUE(a->client->in_room());
}

TEST_F(RelayLoopback, ADirectJoinerThatReachesARelayIsToldItIsTheWrongProtocol) {
  auto link = EnetLink::join("127.0.0.1", relay->link->port());
  Session joiner(*link, testing::session_config(Role::kJoiner, "B", ""));
  joiner.start(now());
  const bool refused = run(
      [&] {
        joiner.service(now());
        return joiner.state() == SessionState::kRefused;
      },
      5.0);
  ASSERT_TRUE(refused) << "state " << state_name(joiner.state());
  EXPECT_EQ(joiner.status().last_bye, ByeReason::kVersionMismatch);
  EXPECT_GE(joiner.drops()[DropReason::kUnknownType], 1u) << "the relay's welcome is not a welcome";
}

TEST_F(RelayLoopback, ARelayClientThatReachesADirectHostIsToldItIsNotARelay) {
  auto link = EnetLink::host("127.0.0.1", 0);
  Session host(*link, testing::session_config(Role::kHost, "A", ""));
  host.start(now());
  RelayClientOptions o;
  o.port = link->port();
  o.room = room_token("kappa");
  Member m("kappa", link->port(), now());
  const bool refused = run(
      [&] {
        host.service(now());
        m.client->poll(now(), m);
        return !m.refusals.empty();
      },
      3.0);
  ASSERT_TRUE(refused);
  EXPECT_EQ(m.refusals.front(), RelayRefusal::kNotARelay);
  EXPECT_TRUE(m.client->stopped());
  EXPECT_NE(describe(RelayRefusal::kNotARelay).find("not a relay"), std::string_view::npos);
}

}  // namespace
}  // namespace deixis::net
