// libFuzzer target for a session receiving hostile packets. Two sessions (host and joiner) run on
// the simulated network; the input decides whether there is a passphrase, when the packets come
// (during the handshake or while streaming) and which packets a third party injects into the
// joiner's or the host's link between steps:
//   byte 0: bit 0 passphrase, bit 1 inject while streaming (else from the start)
//   then records: [flags: bit 0 channel, bit 1 to the host] [length] [length bytes]
// Whatever arrives, nothing crashes, every packet the sessions received and did not take is
// counted once, states stay valid, and every frame played is finite.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <span>

#include <spdlog/spdlog.h>

#include "net/session.h"
#include "net/simulated_link.h"

namespace {

using namespace deixis;
using namespace deixis::net;

void check(bool holds, const char* invariant) {
  if (!holds) {
    std::fprintf(stderr, "net_session_fuzz: invariant violated: %s\n", invariant);
    __builtin_trap();
  }
}

SessionConfig config(Role role, const char* site, bool passphrase) {
  SessionConfig c;
  c.role = role;
  c.hello.site = site;
  c.hello.avatar.body.T_world_root.translation = Vec3(0, 1.6f, 0);
  c.target_map.site = site;
  c.target_map.objects.push_back(
      {1, "TV", TargetKind::kScreen, Vec3(0, 1, -2), Vec3(1, 0.6f, 0.1f)});
  c.passphrase = passphrase ? "fuzz" : "";
  c.kdf = c.min_kdf = {1, 8};
  c.derive_on_this_thread = true;  // results must not depend on a thread's timing
  // A logger without sinks: thousands of sessions a second must not flood the fuzzer's output.
  static const auto quiet = std::make_shared<spdlog::logger>("net_session_fuzz");
  c.logger = quiet;
  return c;
}

bool valid_state(SessionState s) {
  return static_cast<int>(s) <= static_cast<int>(SessionState::kRefused);
}

void step(SimulatedNetwork& net, Session& host, Session& joiner, double& now) {
  now += 0.01;
  net.set_time(now);
  host.service(now);
  joiner.service(now);
  for (Session* s : {&host, &joiner}) {
    for (Playout p = s->next_frame(now);
         p.kind == PlayoutKind::kFrame || p.kind == PlayoutKind::kMissed; p = s->next_frame(now)) {
      if (p.kind == PlayoutKind::kFrame) {
        check(p.frame != nullptr && std::isfinite(p.frame->time) &&
                  p.frame->T_world_head.translation.allFinite() && p.frame->gaze.allFinite(),
              "played frames are finite");
      }
    }
    check(valid_state(s->state()), "a valid state");
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) {
    return 0;
  }
  try {
    const bool passphrase = (data[0] & 1u) != 0;
    const bool while_streaming = (data[0] & 2u) != 0;
    SimulatedNetwork net({}, 1);
    Session host(net.host(), config(Role::kHost, "A", passphrase));
    Session joiner(net.joiner(), config(Role::kJoiner, "B", passphrase));
    double now = 0.0;
    host.start(now);
    joiner.start(now);
    if (while_streaming) {
      for (int i = 0; i < 50 && !(host.state() == SessionState::kStreaming &&
                                  joiner.state() == SessionState::kStreaming);
           ++i) {
        step(net, host, joiner, now);
      }
      check(host.state() == SessionState::kStreaming, "the honest pair streams");
    }
    std::size_t at = 1;
    while (at + 2 <= size) {
      const std::uint8_t flags = data[at];
      const std::size_t length = data[at + 1];
      at += 2;
      const std::size_t n = std::min(length, size - at);
      const auto channel = (flags & 1u) != 0 ? Channel::kTracking : Channel::kReliable;
      const auto to =
          (flags & 2u) != 0 ? SimulatedNetwork::Side::kHost : SimulatedNetwork::Side::kJoiner;
      net.inject(to, channel,
                 std::span<const std::byte>(reinterpret_cast<const std::byte*>(data + at), n));
      at += n;
      step(net, host, joiner, now);
    }
    for (int i = 0; i < 20; ++i) {
      step(net, host, joiner, now);
      if (i % 3 == 0) {
        const TrackingFrame f;
        host.send_tracking(f);
        joiner.send_tracking(f);
      }
    }
    for (const Session* s : {&host, &joiner}) {
      const DropCounters& d = s->drops();
      std::uint64_t sum = 0;
      for (const std::uint64_t c : d.by_reason) {
        sum += c;
      }
      check(sum == d.total, "every drop counted once under one reason");
      check(d[DropReason::kNone] == 0, "no drop without a reason");
      check(s->stats().packets_received >= d.total, "only received packets are dropped");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "net_session_fuzz: unexpected exception: %s\n", e.what());
    __builtin_trap();
  }
  return 0;
}
