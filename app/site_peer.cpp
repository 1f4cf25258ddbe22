#include "app/site_peer.h"

#include <spdlog/spdlog.h>

namespace deixis::app {

namespace {

net::Hello hello_of(const SiteConfig& site, const BodyCalibration& user) {
  net::Hello h;
  h.site = site.site;
  h.avatar.model = "";  // the receiving site chooses what the avatar wears
  h.avatar.body = user;
  return h;
}

}  // namespace

SitePeer::SitePeer(const SitePeerOptions& options, const SiteConfig& site,
                   const BodyCalibration& user, const std::array<MoeNetworks, 2>& networks,
                   const ik::AvatarSolver& solver, double now)
    : site_(site),
      networks_(networks),
      solver_(solver),
      net_(SiteSessionOptions{options.role, options.address, options.port, options.passphrase},
           hello_of(site, user), site.target_map) {
  net_.start(now, options.wait);
}

void SitePeer::meet_remote_person(const net::Hello& hello) {
  // A new connection (the first, or after a reconnect): the person may have changed.
  const BodyCalibration& person = hello.avatar.body;
  const MoeNetworks& n = networks_[static_cast<std::size_t>(index(person.deictic_hand))];
  avatar_.emplace(n.mpnet, n.ugnet, solver_,
                  presence::RemoteAvatarConfig{person, site_.remote_avatar.T_world_floor(), 1});
  stream_ = net_.session().status().streams;
  stats_.peer_site = hello.site;
  spdlog::info("streaming with site {}", hello.site);
}

void SitePeer::tick(const TrackingFrame& user, double now, const LocalTargets& room) {
  ++stats_.ticks;
  net_.poll(now);
  net::Session& session = net_.session();
  if (!net_.streaming()) {
    live_ = false;
    return;
  }
  if (const net::Hello* hello = session.remote_hello();
      hello != nullptr && session.status().streams != stream_) {
    meet_remote_person(*hello);
  }
  TrackingFrame frame = user;
  frame.time = now;  // the sender's clock
  stats_.sent += session.send_tracking(frame) ? 1 : 0;
  net::Playout p = session.next_frame(now);
  for (; p.kind == net::PlayoutKind::kFrame || p.kind == net::PlayoutKind::kMissed;
       p = session.next_frame(now)) {
    if (avatar_) {
      const bool missed = p.kind == net::PlayoutKind::kMissed;
      avatar_->tick(missed ? nullptr : p.frame, room);
      stats_.played += missed ? 0 : 1;
      stats_.missed += missed ? 1 : 0;
    }
  }
  live_ = p.kind != net::PlayoutKind::kNoStream;
  stats_.visible_ticks += visible_avatar() != nullptr ? 1 : 0;
}

const presence::RemoteAvatar* SitePeer::visible_avatar() const {
  return live_ && avatar_ && avatar_->visible() ? &*avatar_ : nullptr;
}

}  // namespace deixis::app
