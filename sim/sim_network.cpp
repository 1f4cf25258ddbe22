#include "sim/sim_network.h"

#include <cstdio>

#include "core/error.h"

namespace deixis::sim {

SimNetwork::SimNetwork(const site::SitePeerOptions& options, const site::SiteConfig& site,
                       const BodyCalibration& user,
                       const std::array<site::MoeNetworks, 2>& networks,
                       const ik::AvatarSolver& solver)
    : options_(options), port_(options.port) {
  try {
    peer_.emplace(options, site, user, networks, solver, clock_.now());
    if (options.role == net::Role::kHost) {
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
    peer_->tick(user, wall_at_sim_zero_ + sim_seconds, room);
  } catch (const Error& e) {
    fail(e.what());
  }
}

const presence::RemoteAvatar* SimNetwork::visible_avatar() const {
  return peer_ ? peer_->visible_avatar() : nullptr;
}

const site::SitePeerStats& SimNetwork::stats() const {
  return peer_ ? peer_->stats() : stats_;
}

PanelNetwork SimNetwork::panel() const {
  PanelNetwork p;
  const bool host = options_.role == net::Role::kHost;
  p.role = host ? "host" : "join";
  p.address = options_.address;
  p.port = port_;
  p.passphrase = !options_.passphrase.empty();
  const site::SitePeerStats& s = stats();
  p.peer_site = s.peer_site;
  p.sent = s.sent;
  p.played = s.played;
  p.failed = !error_.empty();
  p.running = running();
  p.state = p.failed                      ? std::string_view(error_)
            : left_                       ? std::string_view("left the session")
            : peer_ && peer_->streaming() ? std::string_view("streaming")
                                          : std::string_view("waiting for the other site");
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
