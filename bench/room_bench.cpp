// room_bench: one room member's network tick in a sealed room of N people (net/room_session.h,
// docs/rooms-protocol.md): seal our frame once and hand it to the transport, open and decode one
// sealed frame from each of the N − 1 others, the timers (heartbeats, time-outs), and play out each
// person's next frame. The others' frames are sealed beforehand by real members (through the
// tests' in-process relay, tests/net/room_fixture.h), so the loop measures the member alone, not
// the relay. Counter `us_per_person`: the tick's time divided by N − 1.
//
//   build/release/bench/room_bench --benchmark_filter=RoomMemberTick

#include <benchmark/benchmark.h>

#include <algorithm>
#include <map>
#include <string>
#include <vector>

#include "net/room_fixture.h"
#include "net/room_session.h"

namespace {

using namespace deixis;
using namespace deixis::net;

constexpr int kFrames = 3000;  // ticks measured: 100 s of tracking

void BM_RoomMemberTick(benchmark::State& state) {
  const auto people = static_cast<std::size_t>(state.range(0));
  testing::RoomHarness room;
  for (std::size_t i = 0; i < people; ++i) {
    const std::string site(1, static_cast<char>('A' + i));
    room.add(testing::room_config(site, "pw"));
    room.run_until([] { return false; }, 0.05);
  }
  if (!room.run_until(
          [&] {
            return std::all_of(room.members.begin(), room.members.end(),
                               [&](const auto& m) { return m->people().size() == people - 1; });
          },
          5.0)) {
    state.SkipWithError("the room did not form");
    return;
  }
  // Every other member's sealed frames for member 0, in order.
  RoomSession& me = *room.members[0];
  std::map<MemberId, std::vector<std::vector<std::uint8_t>>> frames;
  room.relay.on_forward = [&](testing::FakeRelay::Forward& f) {
    if (f.to == room.endpoints[0] && f.channel == Channel::kTracking) {
      frames[f.from].push_back(f.bytes);
    }
    // Member 0 hears these in the measured loop instead (and the heartbeats now).
    return f.to != room.endpoints[0] || f.channel != Channel::kTracking;
  };
  for (int k = 0; k < kFrames; ++k) {
    for (std::size_t i = 1; i < people; ++i) {
      const Vec3 root = room.members[i]->config().hello.avatar.body.T_world_root.translation;
      room.members[i]->send_tracking(testing::moving_frame(static_cast<std::uint32_t>(k), root),
                                     k * testing::kTick);
    }
    room.step(testing::kTick);
  }
  room.endpoints[0]->uplink.blocked = true;  // what member 0 sends goes no further
  const Vec3 my_root = me.config().hello.avatar.body.T_world_root.translation;
  const TrackingFrame mine = testing::moving_frame(7, my_root);
  double now = room.now;
  int k = 0;
  std::uint64_t played = 0;
  for (auto _ : state) {
    now += testing::kTick;
    me.poll(now);
    me.send_tracking(mine, now);
    for (const auto& [from, stream] : frames) {
      me.on_payload(from, Channel::kTracking, stream[static_cast<std::size_t>(k)]);
    }
    for (const MemberId p : me.people()) {
      for (Playout o = me.next_playout(p, now);
           o.kind == PlayoutKind::kFrame || o.kind == PlayoutKind::kMissed;
           o = me.next_playout(p, now)) {
        played += o.kind == PlayoutKind::kFrame ? 1 : 0;
      }
    }
    ++k;
  }
  // Time per tick over N − 1, in microseconds: an inverted rate of (N − 1) / 10^6 per iteration.
  state.counters["us_per_person"] = benchmark::Counter(
      static_cast<double>(people - 1) / 1e6,
      benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["played_per_tick"] = static_cast<double>(played) / static_cast<double>(k);
}
BENCHMARK(BM_RoomMemberTick)
    ->Arg(2)
    ->Arg(4)
    ->Arg(8)
    ->Iterations(kFrames)
    ->Unit(benchmark::kMicrosecond);

}  // namespace
