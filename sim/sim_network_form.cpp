#include "sim/sim_network_form.h"

#include <arpa/inet.h>

#include <cstdio>
#include <exception>

#include "core/io/text_rules.h"
#include "site/endpoint.h"

namespace deixis::sim {

namespace {

template <std::size_t N>
void fill(std::array<char, N>& field, const std::string& text) {
  std::snprintf(field.data(), field.size(), "%s", text.c_str());
}

// Only a numeric address: looking a name up (getaddrinfo) can take seconds, and the panel starts
// a session inside the frame loop, which must not stop drawing.
bool numeric_ipv4(const std::string& address) {
  in_addr parsed{};
  return inet_pton(AF_INET, address.c_str(), &parsed) == 1;
}

FormSession join_session(const NetworkForm& form) {
  FormSession s;
  site::SitePeerOptions o;
  o.role = net::Role::kJoiner;
  const std::string problem = site::parse_endpoint(form.endpoint.data(), o.address, o.port);
  if (!problem.empty()) {
    s.problem = std::string("Join: ") + form.endpoint.data() + ": " + problem;
  } else if (!numeric_ipv4(o.address)) {
    s.problem = "Join: " + o.address +
                ": the panel takes a numeric address, e.g. 127.0.0.1 (a name is looked up on the "
                "command line: --join)";
  } else {
    s.options = o;
  }
  return s;
}

FormSession host_session(const NetworkForm& form) {
  FormSession s;
  site::SitePeerOptions o;
  o.role = net::Role::kHost;
  o.address = form.bind;
  const std::string text = form.port.data();
  try {
    std::size_t used = 0;
    const int port = std::stoi(text, &used);
    if (used == text.size() && port >= 0 && port <= 65535) {
      o.port = static_cast<std::uint16_t>(port);
      s.options = o;
      return s;
    }
  } catch (const std::exception&) {
  }
  s.problem = "Host: port '" + text + "': expected 0 to 65535 (0 picks a free one)";
  return s;
}

}  // namespace

NetworkForm initial_network_form(const SimOptions& flags) {
  const SimOptions defaults;
  NetworkForm form;
  form.host = flags.network && flags.host;
  const bool joined = flags.network && !flags.host;
  fill(form.endpoint, joined ? flags.address + ":" + std::to_string(flags.port)
                             : "127.0.0.1:" + std::to_string(defaults.port));
  fill(form.port, std::to_string(joined ? defaults.port : flags.port));
  fill(form.passphrase, flags.passphrase);
  fill(form.room, flags.room);
  form.bind = form.host ? flags.address : defaults.address;
  form.wait = flags.wait;
  return form;
}

// Join with a room's name: the endpoint is the relay's, and the room is entered with the same
// rules as `--connect --room` (an open room through a relay beyond loopback needs --open).
FormSession room_session(const NetworkForm& form) {
  FormSession s = join_session(form);
  const std::string name = form.room.data();
  if (!s.options) {
    s.problem.replace(0, 4, "Room");  // "Join: …" about the relay's address
    return s;
  }
  if (!is_wire_text(name)) {
    s.options.reset();
    s.problem = "Room: a room name is 1 to 64 bytes of UTF-8 without control characters";
    return s;
  }
  const std::string passphrase = form.passphrase.data();
  const std::string problem = site::open_room_problem(s.options->address, !passphrase.empty());
  if (!problem.empty()) {
    s.options.reset();
    s.problem = "Room: " + problem;
    return s;
  }
  site::RoomPeerOptions room;
  room.relay_host = s.options->address;
  room.relay_port = s.options->port;
  room.room = name;
  room.passphrase = passphrase;
  room.wait = form.wait;
  s.options.reset();
  s.room = room;
  return s;
}

FormSession form_session(const NetworkForm& form) {
  if (!form.host && form.room[0] != '\0') {
    return room_session(form);
  }
  FormSession s = form.host ? host_session(form) : join_session(form);
  if (s.options) {
    s.options->passphrase = form.passphrase.data();
    s.options->wait = form.wait;
    // The rule of every host (site::SiteSession checks it again): said under the form before
    // trying.
    const std::string problem =
        form.host ? site::host_exposure_problem(s.options->address, !s.options->passphrase.empty())
                  : std::string();
    if (!problem.empty()) {
      s.options.reset();
      s.problem = "Host: " + problem;
    }
  }
  return s;
}

}  // namespace deixis::sim
