// `deixis relay` (docs/relay.md): a relay for rooms of several people, over ENet. It listens,
// prints "port N" (the port chosen, when 0 was asked for) once it does, and serves until SIGINT
// or SIGTERM. The signals are blocked and polled between service calls (sigtimedwait), so the
// relay needs no handler and no global flag, and a signal never interrupts a send half-way.

#include <spdlog/spdlog.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <ctime>

#include "app/commands.h"
#include "core/error.h"
#include "net/enet_link.h"
#include "net/relay_server.h"

namespace deixis::app {

namespace {

constexpr std::uint32_t kServiceWaitMs = 5;  // the longest a quiet relay sleeps per call
constexpr double kStatsEverySeconds = 60.0;  // a summary line while members are connected

sigset_t stop_signals() {
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, SIGINT);
  sigaddset(&set, SIGTERM);
  return set;
}

// The pending stop signal, if any (0: none), without waiting.
int pending_stop(const sigset_t& set) {
  const timespec zero{0, 0};
  const int s = sigtimedwait(&set, nullptr, &zero);
  return s > 0 ? s : 0;
}

void log_stats(const net::RelayServer& relay) {
  const net::RelayServerStats& s = relay.stats();
  spdlog::info(
      "relay: {} rooms, {} members, {} waiting to enter; since start {} entered, {} refused "
      "(room full {}), {} floods cut, {} forwards in, {} out, {} packets dropped",
      relay.rooms(), relay.members(), relay.pending(), s.entered,
      s.refused_room_full + s.refused_relay_full + s.refused_version, s.refused_room_full,
      s.floods_cut, s.forwards_in, s.forwards_out, relay.drops().total);
}

}  // namespace

int run_relay(const RelayOptions& options) {
  const sigset_t signals = stop_signals();
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  net::RelayServerConfig config;
  config.max_people = options.max_people;
  config.max_rooms = options.max_rooms;
  std::unique_ptr<net::EnetLink> link;
  std::unique_ptr<net::RelayServer> relay;
  try {
    link = net::EnetLink::host(options.bind, options.port,
                               net::HostLimits{config.max_connections, 64});
    relay = std::make_unique<net::RelayServer>(*link, config);
  } catch (const Error& e) {
    std::fprintf(stderr, "deixis relay: %s\n", e.what());
    return 2;
  }
  std::printf("port %u\n", static_cast<unsigned>(link->port()));
  std::fflush(stdout);
  spdlog::info("relay: listening on {}:{}, rooms of up to {} people, at most {} rooms",
               options.bind, link->port(), config.max_people, config.max_rooms);
  const auto start = std::chrono::steady_clock::now();
  const auto seconds = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  double next_stats = kStatsEverySeconds;
  int signal = 0;
  while ((signal = pending_stop(signals)) == 0) {
    const double now = seconds();
    relay->service(now, kServiceWaitMs);
    if (now >= next_stats) {
      next_stats = now + kStatsEverySeconds;
      if (relay->members() > 0) {
        log_stats(*relay);
      }
    }
  }
  spdlog::info("relay: stopping ({})", signal == SIGINT ? "SIGINT" : "SIGTERM");
  log_stats(*relay);
  relay.reset();
  link.reset();  // tells every member at once
  return 0;
}

}  // namespace deixis::app
