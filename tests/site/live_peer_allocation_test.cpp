// The live front ends' runtime (site::LivePeer, site/live_peer.h: `deixis sim` and `deixis xr`)
// allocates nothing per tick once everyone is there, in a direct session and in a room. Two
// LivePeers in this process, sites A and B of the demo with their virtual users' performances as
// the users' tracking, meet over real ENet on 127.0.0.1: directly (A hosts, B joins), or in a
// sealed room on a `RelayServer` that runs on a thread of its own (its work is the relay's, not a
// site's). Ticks are paced to the wall clock, as the front ends' are. After a warm-up (entering,
// hellos and target maps, each avatar built and shown), 150 ticks of each peer — each also asking
// what a front end asks every tick: the avatars to draw, the people present, the selection's
// candidates, the presence panel's lines — make zero heap allocations in this thread. ENet's own
// allocations go through its allocator hook, past the counter, as in site_peer_allocation_test. Not
// built under ASan.

#include <enet/enet.h>
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "allocation_counter.h"
#include "live_peer_fixtures.h"
#include "net/enet_link.h"
#include "site/live_peer.h"
#include "site/moe_weights.h"
#include "site/presence_panel.h"
#include "site/site_config.h"
#include "test_support.h"

extern "C" {
void* __libc_malloc(std::size_t size);
void __libc_free(void* pointer);
}

namespace deixis::site {
namespace {

using fixtures::RelayThread;
using fixtures::Site;

constexpr double kTick = 1.0 / 30.0;
constexpr int kCountedTicks = 150;

std::atomic<std::size_t> g_enet_allocations{0};  // the relay's thread allocates through ENet too

void* enet_allocate(std::size_t size) {
  ++g_enet_allocations;
  return __libc_malloc(size);
}

void enet_release(void* memory) {
  __libc_free(memory);
}

class LivePeerHotPath : public ::testing::TestWithParam<bool> {};

TEST_P(LivePeerHotPath, TicksAllocateNothingOnceEveryoneIsThere) {
  const bool room = GetParam();
  ENetCallbacks callbacks{};
  callbacks.malloc = enet_allocate;
  callbacks.free = enet_release;
  ASSERT_EQ(enet_initialize_with_callbacks(ENET_VERSION, &callbacks), 0);
  const std::array<MoeNetworks, 2> networks = {
      load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kLeft),
      load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kRight)};
  const Site a("a.json");
  const Site b("b.json");
  std::unique_ptr<RelayThread> relay;
  const SiteClock clock;
  const auto options = [&](bool host, std::uint16_t port) {
    return live_peer_options(host, "127.0.0.1", port, room ? "hot path" : "", "pw", 30.0);
  };
  if (room) {
    relay = std::make_unique<RelayThread>();
  }
  LivePeer pa(options(true, room ? relay->port() : 0), a.config, a.body, networks, a.solver,
              WornAvatars{}, clock.now());
  LivePeer pb(options(false, room ? relay->port() : pa.port()), b.config, b.body, networks,
              b.solver, WornAvatars{}, clock.now());
  std::array<LivePerson, 4> listed;
  PresencePanel panel;  // what deixis xr shows, rebuilt every tick here (it allows every 0.5 s)
  std::size_t tick = 0;
  std::size_t asked = 0;  // what the front ends read each tick, so that it is not optimised away
  const auto step = [&] {
    for (const auto& [peer, site] : {std::pair{&pa, &a}, std::pair{&pb, &b}}) {
      TrackingFrame user = site->frame(tick);
      const Vec3 head = user.T_world_head.translation;
      const SelectionCandidates candidates =
          peer->candidates(site->config.target_map, head, Vec3(0, 1.6f, -2.2f));
      asked += candidates.people.size();
      const double now = clock.now();
      peer->tick(user, now, now, LocalTargets{&site->config.target_map, head});
      asked += peer->visible().size() + peer->drawn().size() + peer->list_people(listed);
      panel.update(now, *peer, true);
      asked += panel.lines().size();
    }
    ++tick;
    std::this_thread::sleep_until(std::chrono::steady_clock::now() +
                                  std::chrono::duration<double>(kTick));
  };
  const auto both_shown = [&] { return !pa.visible().empty() && !pb.visible().empty(); };

  deixis::testing::AllocationCounter warm_up;
  while (!both_shown() && tick < 900) {
    step();
  }
  ASSERT_TRUE(both_shown()) << "no avatar both ways after " << tick << " ticks";
  for (int i = 0; i < 90; ++i) {
    step();
  }
  EXPECT_GT(warm_up.count(), 0u) << "the counter must see what tick allocates";

  const LivePeerStats a_before = pa.stats();
  const std::size_t enet_before = g_enet_allocations;
  deixis::testing::AllocationCounter counter;
  for (int i = 0; i < kCountedTicks; ++i) {
    step();
  }
  const std::size_t ours = counter.count();
  EXPECT_EQ(ours, 0u) << "over " << kCountedTicks << " ticks of each peer";
  std::printf("%s: %d ticks of each peer, %zu allocations of ours, %zu by ENet (excluded)\n",
              room ? "room" : "direct", kCountedTicks, ours, g_enet_allocations - enet_before);

  // Frames flowed and the other person was shown the whole time; each lists the other.
  EXPECT_EQ(pa.stats().sent - a_before.sent, static_cast<std::uint64_t>(kCountedTicks));
  EXPECT_GE(pa.stats().played - a_before.played, static_cast<std::uint64_t>(kCountedTicks - 5));
  EXPECT_EQ(pa.stats().visible_ticks - a_before.visible_ticks,
            static_cast<std::uint64_t>(kCountedTicks));
  EXPECT_EQ(pa.stats().peer_site, "B");
  EXPECT_EQ(pb.stats().peer_site, "A");
  ASSERT_EQ(pa.list_people(listed), 1u);
  EXPECT_EQ(listed[0].site, "B");
  EXPECT_TRUE(listed[0].live);
  EXPECT_EQ(pa.in_room(), room);
  EXPECT_GT(asked, 0u);
  pb.close(clock.now());
  pa.close(clock.now());
}

INSTANTIATE_TEST_SUITE_P(DirectAndRoom, LivePeerHotPath, ::testing::Values(false, true),
                         [](const ::testing::TestParamInfo<bool>& param) {
                           return param.param ? "Room" : "Direct";
                         });

}  // namespace
}  // namespace deixis::site
