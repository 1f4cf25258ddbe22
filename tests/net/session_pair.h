#pragma once
// Two sessions, host and joiner, on one simulated network and one injected clock: the in-process
// endpoints of the session tests, the conditions matrix and the allocation test. Each step
// advances the clock by `dt`, services both sessions and lets the caller act in between.

#include <functional>
#include <memory>

#include "net/session.h"
#include "net/simulated_link.h"
#include "net_fixtures.h"

namespace deixis::testing {

struct SessionPair {
  net::SimulatedNetwork network;
  net::Session host;
  net::Session joiner;
  double now = 0.0;

  SessionPair(const net::LinkConditions& conditions, std::uint64_t seed,
              net::SessionConfig host_config, net::SessionConfig joiner_config)
      : network(conditions, seed),
        host(network.host(), std::move(host_config)),
        joiner(network.joiner(), std::move(joiner_config)) {}

  explicit SessionPair(const net::LinkConditions& conditions = {}, std::uint64_t seed = 1,
                       const std::string& host_passphrase = "",
                       const std::string& joiner_passphrase = "")
      : SessionPair(conditions, seed, session_config(net::Role::kHost, "A", host_passphrase),
                    session_config(net::Role::kJoiner, "B", joiner_passphrase)) {}

  void start() {
    host.start(now);
    joiner.start(now);
  }

  // One step of `dt` seconds: the clock moves, both sides service their links.
  void step(double dt = 0.005) {
    now += dt;
    network.set_time(now);
    host.service(now);
    joiner.service(now);
  }

  // Steps until `done` holds or `seconds` of simulated time pass; true if it held.
  bool run_until(const std::function<bool()>& done, double seconds, double dt = 0.005) {
    const double end = now + seconds;
    while (now < end) {
      if (done()) {
        return true;
      }
      step(dt);
    }
    return done();
  }

  bool both_streaming() const {
    return host.state() == net::SessionState::kStreaming &&
           joiner.state() == net::SessionState::kStreaming;
  }

  bool connect(double seconds = 5.0) {
    start();
    return run_until([&] { return both_streaming(); }, seconds);
  }
};

}  // namespace deixis::testing
