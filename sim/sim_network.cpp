#include "sim/sim_network.h"

#include <cstdio>
#include <tuple>
#include <utility>

#include "core/error.h"

namespace deixis::sim {

namespace {

// Where the session goes: the host's address and port (the one to listen on for a host), or the
// relay's for a room.
std::pair<std::string_view, std::uint16_t> endpoint_of(const site::LivePeerOptions& options) {
  if (const site::RoomPeerOptions* room = std::get_if<site::RoomPeerOptions>(&options)) {
    return {room->relay_host, room->relay_port};
  }
  const site::SitePeerOptions& direct = std::get<site::SitePeerOptions>(options);
  return {direct.address, direct.port};
}

bool hosts(const site::LivePeerOptions& options) {
  const site::SitePeerOptions* direct = std::get_if<site::SitePeerOptions>(&options);
  return direct != nullptr && direct->role == net::Role::kHost;
}

}  // namespace

SimNetwork::SimNetwork(const site::LivePeerOptions& options, const site::SiteConfig& site,
                       const BodyCalibration& user,
                       const std::array<site::MoeNetworks, 2>& networks,
                       const ik::AvatarSolver& solver, const site::WornAvatars& worn)
    : options_(options) {
  std::tie(address_, port_) = endpoint_of(options_);
  try {
    peer_.emplace(options_, site, user, networks, solver, worn, clock_.now());
    if (hosts(options_)) {
      port_ = peer_->port();  // the bound one (--port 0 picks it), shown after a failure too
      std::printf("port %u\n", static_cast<unsigned>(port_));
      std::fflush(stdout);
    }
  } catch (const Error& e) {
    fail(e.what());
  }
}

void SimNetwork::fail(const char* what) {
  // The window stays: the panel shows why, and the run exits 1 at its end unless the person
  // starts another session that takes this one's place. Said at once on stderr too, so a failed
  // attempt is on record after a later one succeeded.
  error_ = what;
  std::fprintf(stderr, "deixis sim: %s\n", what);
  std::fflush(stderr);
  end_session();
}

void SimNetwork::end_session() {
  if (peer_) {
    stats_ = peer_->stats();  // shown and reported after the end
    people_count_ = 0;        // their names lived in the runtime
    peer_.reset();
  }
}

void SimNetwork::tick(const TrackingFrame& user, const LocalTargets& room, double sim_seconds) {
  if (!peer_) {
    return;
  }
  if (wall_at_sim_zero_ < 0.0) {
    wall_at_sim_zero_ = clock_.now() - sim_seconds;
  }
  try {
    // Played as of the tick's own time, as it was sampled: ticks a slow frame catches up on each
    // play what was due by then.
    const double sampled = wall_at_sim_zero_ + sim_seconds;
    peer_->tick(user, sampled, sampled, room);
    people_count_ = peer_->list_people(people_);
  } catch (const Error& e) {
    fail(e.what());
  }
}

std::span<const presence::RemoteAvatar* const> SimNetwork::visible_avatars() const {
  return peer_ ? peer_->visible() : std::span<const presence::RemoteAvatar* const>();
}

std::span<const site::DrawnAvatar> SimNetwork::drawn_avatars() const {
  return peer_ ? peer_->drawn() : std::span<const site::DrawnAvatar>();
}

const site::LivePeerStats& SimNetwork::stats() const {
  return peer_ ? peer_->stats() : stats_;
}

PanelNetwork SimNetwork::panel() const {
  PanelNetwork p;
  const site::RoomPeerOptions* room = std::get_if<site::RoomPeerOptions>(&options_);
  p.role = room != nullptr ? "room" : hosts(options_) ? "host" : "join";
  p.address = address_;
  p.room = room != nullptr ? std::string_view(room->room) : std::string_view();
  p.port = port_;
  p.passphrase = room != nullptr ? !room->passphrase.empty()
                                 : !std::get<site::SitePeerOptions>(options_).passphrase.empty();
  const site::LivePeerStats& s = stats();
  p.peer_site = s.peer_site;
  p.sent = s.sent;
  p.played = s.played;
  p.failed = !error_.empty();
  p.running = running();
  p.people = people();
  const bool connected = peer_ && peer_->connected();
  p.state = p.failed     ? std::string_view(error_)
            : left_      ? std::string_view(room != nullptr ? "left the room" : "left the session")
            : !connected ? std::string_view(room != nullptr ? "entering the room"
                                                            : "waiting for the other site")
            : room != nullptr ? std::string_view("in the room")
                              : std::string_view("streaming");
  return p;
}

void SimNetwork::close() {
  if (peer_) {
    peer_->close(clock_.now());
    left_ = true;
    end_session();
  }
}

}  // namespace deixis::sim
