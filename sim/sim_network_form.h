#pragma once
// The panel's network form (docs/sim.md): what a person types to host or join a session from the
// simulator's window — the role, the host's HOST:PORT (join) or the port to listen on (host), a
// room's name (join: the HOST:PORT is then a relay's), the passphrase — and its check into the
// options `--host` / `--join` / `--connect --room` give, so a session started from the panel is
// the same site runtime's session as one started from the flags.

#include <array>
#include <optional>
#include <string>

#include "sim/sim_options.h"
#include "site/room_peer.h"
#include "site/site_peer.h"

namespace deixis::sim {

struct NetworkForm {
  bool host = false;                   // host, else join
  std::array<char, 64> endpoint{};     // join: the host's HOST:PORT
  std::array<char, 8> port{};          // host: the port to listen on (0 picks a free one)
  std::array<char, 65> room{};         // join: a room on the relay at `endpoint`; empty: direct
  std::array<char, 256> passphrase{};  // shown as asterisks, never in clear
  std::string bind;                    // host: where to listen (--bind); not in the panel
  double wait = 30.0;                  // s for the other site to come (--wait); not in the panel
};

// The form as first shown: the flags' session if they give one (its role, endpoint or port),
// else a join of 127.0.0.1 at the default port; the passphrase, --bind and --wait of the flags.
NetworkForm initial_network_form(const SimOptions& flags);

// The session the form asks for — a direct one (`options`) or a room (`room`) — or why it cannot
// start (`problem`, shown under the form).
struct FormSession {
  std::optional<site::SitePeerOptions> options;
  std::optional<site::RoomPeerOptions> room;
  std::string problem;
};
FormSession form_session(const NetworkForm& form);

}  // namespace deixis::sim
