// A live site's network tick (SitePeer::tick, site/site_peer.h: `deixis xr` and `deixis sim`
// with --host / --join) allocates nothing once streaming. Two SitePeers in this process, host A
// and joiner B, the demo's sites (assets/sites) with their virtual users' performances as the
// users' tracking, stream to each other over real ENet on 127.0.0.1, each tick on one injected
// 30 Hz clock. After a warm-up (connecting, the hellos and target maps, each remote avatar built
// and shown, the first heartbeats), 300 ticks of each peer (10 s: 300 frames each way sent,
// played out of the jitter buffer and translated into an avatar, heartbeats, ENet's
// acknowledgements) make zero heap allocations in this thread. B offers its own avatar (the BCN
// test rig, docs/avatars.md) and A fetches it during the warm-up and wears it: a site showing a
// person in the avatar they chose ticks without allocating as well.
//
// Excluded, and only that: ENet's own allocations. ENet mallocs every packet it sends or
// receives and every protocol command it queues (enet_packet_create, enet_malloc; enet_link.h),
// which no caller can avoid short of replacing ENet. The test gives ENet its allocator through
// ENet's documented hook (enet_initialize_with_callbacks) before any link exists: glibc's malloc
// called directly, past the counter (allocation_counter.h), and counted on its own. Everything
// else the tick runs — the session, codecs, sealing, jitter buffer, logging, translator, touch
// contact, IK, and the C++ and C libraries under them — goes through the counter. Not built under
// ASan (tests/CMakeLists.txt).

#include <enet/enet.h>
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "avatar/bcn_rig.h"  // tests/avatar
#include "site/avatar_cache.h"

#include "allocation_counter.h"
#include "avatar/avatar_loader.h"
#include "capture/subject.h"
#include "capture/virtual_user.h"
#include "core/error.h"
#include "presence/remote_avatar.h"
#include "site/moe_weights.h"
#include "site/site_config.h"
#include "site/site_peer.h"
#include "test_support.h"

// glibc's allocator entry points, which the counter's replacements forward to
// (allocation_counter.cpp); ENet's allocations call them directly.
extern "C" {
void* __libc_malloc(std::size_t size);
void __libc_free(void* pointer);
}

namespace deixis::site {
namespace {

namespace fs = std::filesystem;

constexpr double kTick = 1.0 / 30.0;
constexpr int kCountedTicks = 300;

std::size_t g_enet_allocations = 0;

void* enet_allocate(std::size_t size) {
  ++g_enet_allocations;
  return __libc_malloc(size);
}

void enet_release(void* memory) {
  __libc_free(memory);
}

// One site: its configuration, avatar and solver, and its user's tracking (the virtual user's
// performance, 30 Hz, at least `seconds` long).
struct Site {
  SiteConfig config;
  ik::AvatarSolver solver;
  capture::ScriptPerformance performance;

  Site(const std::string& name, double seconds)
      : config(read_site_config(deixis::testing::source_dir() / "assets/sites" / name)),
        solver(ik::AvatarSolver::build(avatar::load_avatar(config.avatar_path).rig)) {
    const Pose remote_origin =
        presence::avatar_origin(solver, config.remote_avatar.T_world_floor());
    const capture::VirtualUserScene scene{config.user.T_world_floor(), config.target_map.objects,
                                          remote_origin.translation};
    const VirtualUser* user = config.virtual_user ? &*config.virtual_user : nullptr;
    if (user == nullptr) {
      throw Error(name + ": no virtual user");
    }
    performance = capture::perform_script(capture::find_subject(user->subject), user->script, scene,
                                          user->seed, seconds);
  }

  const TrackingFrame& frame(std::size_t tick) const {
    const std::vector<TrackingFrame>& frames = performance.sequence.frames;
    return frames[tick % frames.size()];
  }
  // Target 0 for the remote avatar: this site's user's eyes.
  LocalTargets room(std::size_t tick) const {
    return {&config.target_map, frame(tick).T_world_head.translation};
  }
};

// What both tests share: the networks by deictic hand, and the two sites.
struct Assets {
  std::array<MoeNetworks, 2> networks;
  Site a;
  Site b;
};

const Assets& assets() {
  static const Assets shared{
      {load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kLeft),
       load_moe_networks(deixis::testing::reference_dir() / "weights", Hand::kRight)},
      Site("a.json", 40.0),
      Site("b.json", 40.0)};
  return shared;
}

class SitePeerHotPath : public ::testing::TestWithParam<const char*> {};

TEST_P(SitePeerHotPath, StreamingTicksAllocateNothing) {
  // Before any ENet host exists, so that all of ENet's memory comes from this allocator.
  ENetCallbacks callbacks{};
  callbacks.malloc = enet_allocate;
  callbacks.free = enet_release;
  ASSERT_EQ(enet_initialize_with_callbacks(ENET_VERSION, &callbacks), 0);
  const Assets& x = assets();
  const Site& a = x.a;
  const Site& b = x.b;
  const std::string passphrase(GetParam());
  double now = 0.0;
  // The host measures its remote person as it plays them (completion states and gazes).
  SitePeerOptions host_options{net::Role::kHost, "127.0.0.1", 0, passphrase, 30.0, {256}};
  host_options.chosen_avatars = true;  // in memory only: no cache directory
  SitePeer host(host_options, a.config, a.performance.sequence.calibration, x.networks, a.solver,
                now);
  SitePeerOptions joiner_options{net::Role::kJoiner, "127.0.0.1", host.port(), passphrase, 30.0};
  load_person_avatar(deixis::testing::bcn_glb(), AvatarSource::kChosen,
                     &joiner_options.avatar_file);
  SitePeer joiner(joiner_options, b.config, b.performance.sequence.calibration, x.networks,
                  b.solver, now);
  std::size_t tick = 0;
  const auto step = [&] {
    host.tick(a.frame(tick), now, a.room(tick));
    joiner.tick(b.frame(tick), now, b.room(tick));
    ++tick;
    now += kTick;
  };
  const auto both_shown = [&] {
    return host.visible_avatar() != nullptr && joiner.visible_avatar() != nullptr;
  };

  // Warm-up: connect, exchange hellos and target maps, build and show each remote avatar, then
  // 5 s more. These ticks do allocate (the decoded hellos and maps, the avatars): the positive
  // control that the counter sees what tick does.
  deixis::testing::AllocationCounter warm_up;
  while (!both_shown() && tick < 600) {
    step();
    // Until both stream, at the pace of real time: the passphrase key is derived on a thread of
    // its own (docs/protocol.md §5), which a clock racing ahead would leave behind.
    std::this_thread::sleep_for(std::chrono::duration<double>(kTick));
  }
  ASSERT_TRUE(both_shown()) << "no frames both ways after " << tick << " ticks";
  for (int i = 0; i < 150; ++i) {
    step();
  }
  // B's file arrives (paced at 128 KiB/s of the injected clock) and loads on a thread (real time).
  const auto wears = [&] { return host.people().wearing(SitePeer::kDirectPerson) != nullptr; };
  for (int i = 0; i < 3000 && !wears(); ++i) {
    step();
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  ASSERT_TRUE(wears()) << "A never dressed B in the avatar B chose";
  for (int i = 0; i < 60; ++i) {
    step();
  }
  ASSERT_NE(host.visible_avatar(), nullptr);
  EXPECT_EQ(host.visible_avatar()->model_pose().size(), 54u) << "B in the BCN rig";
  EXPECT_GT(warm_up.count(), 0u) << "the counter must see what tick allocates";

  const SitePeerStats host_before = host.stats();
  const SitePeerStats joiner_before = joiner.stats();
  const std::size_t enet_before = g_enet_allocations;
  deixis::testing::AllocationCounter counter;
  for (int i = 0; i < kCountedTicks; ++i) {
    step();
  }
  const std::size_t ours = counter.count();
  const std::size_t enet = g_enet_allocations - enet_before;
  EXPECT_EQ(ours, 0u) << "over " << kCountedTicks << " ticks of each peer";
  std::printf("%d ticks of each peer: %zu allocations of ours, %zu by ENet (excluded)\n",
              kCountedTicks, ours, enet);
  EXPECT_GT(enet, static_cast<std::size_t>(2 * kCountedTicks))
      << "ENet's packets go through its own allocator, outside the count";

  // Frames flowed both ways the whole time, and each avatar was shown on every tick.
  for (const auto& [peer, before] :
       {std::pair{&host, host_before}, std::pair{&joiner, joiner_before}}) {
    const SitePeerStats& after = peer->stats();
    EXPECT_TRUE(peer->streaming());
    EXPECT_EQ(after.sent - before.sent, static_cast<std::uint64_t>(kCountedTicks));
    EXPECT_GE(after.played - before.played, static_cast<std::uint64_t>(kCountedTicks - 2));
    EXPECT_LE(after.missed - before.missed, 2u);
    EXPECT_EQ(after.visible_ticks - before.visible_ticks,
              static_cast<std::uint64_t>(kCountedTicks));
  }
  EXPECT_EQ(host.stats().peer_site, "B");
  // The host's record of B: every played frame, shown on every counted tick, B's gazes measured.
  const std::vector<PersonRecord> people = host.people().records();
  ASSERT_EQ(people.size(), 1u);
  EXPECT_EQ(people[0].site, "B");
  EXPECT_EQ(people[0].frames_played, host.stats().played);
  EXPECT_GE(people[0].visible_ticks, static_cast<std::uint64_t>(kCountedTicks));
  EXPECT_FALSE(people[0].gazes.empty());
  EXPECT_EQ(joiner.stats().peer_site, "A");
  joiner.close(now);
  host.close(now);
}

INSTANTIATE_TEST_SUITE_P(PlainAndSealed, SitePeerHotPath, ::testing::Values("", "pw"),
                         [](const ::testing::TestParamInfo<const char*>& param) {
                           return std::string(param.param).empty() ? "Plain" : "Sealed";
                         });

}  // namespace
}  // namespace deixis::site
