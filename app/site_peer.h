#pragma once
// The network side of a site with a live user (`deixis xr` and `deixis sim` with `--host` /
// `--join`, docs/xr.md, docs/sim.md): the user's tracking goes to the other site every 30 Hz
// tick; the other site's person comes back as a translated avatar in this room
// (presence::RemoteAvatar), exactly as `deixis host` / `join` do for a scripted user
// (app/site_run.cpp). Unlike them it never blocks: a headset's frame loop must keep submitting
// frames and a window must keep drawing, so connecting is polled tick by tick
// (SiteSession::start/poll).

#include <array>
#include <cstdint>
#include <optional>
#include <string>

#include "app/moe_weights.h"
#include "app/site_config.h"
#include "app/site_session.h"
#include "presence/remote_avatar.h"

namespace deixis::app {

struct SitePeerOptions {
  net::Role role = net::Role::kHost;
  std::string address = "127.0.0.1";  // host: where to listen (docs/security.md); joiner: the host
  std::uint16_t port = 7350;          // host: 0 picks a free one
  std::string passphrase;
  double wait = 30.0;  // s for the other site to come
};

struct SitePeerStats {
  std::uint64_t ticks = 0, sent = 0, played = 0, missed = 0, visible_ticks = 0;
  std::string peer_site = "?";
};

class SitePeer {
 public:
  // Binds (host) or resolves (joiner) at once; throws deixis::Error when it cannot. `user`: the
  // user's calibration, sent in the hello.
  SitePeer(const SitePeerOptions& options, const SiteConfig& site, const BodyCalibration& user,
           const std::array<MoeNetworks, 2>& networks, const ik::AvatarSolver& solver, double now);

  std::uint16_t port() const { return net_.port(); }
  // The other site is there and the two stream (false before, and after it left).
  bool streaming() const { return net_.streaming(); }

  // One tick: services the link, sends the user's frame once streaming, plays the remote
  // person's frames that are due into their avatar. Throws deixis::Error when refused or when
  // nobody came within `wait` s. Allocates nothing once streaming.
  void tick(const TrackingFrame& user, double now, const LocalTargets& room);

  // The avatar to draw this tick; null while it must be hidden (no live stream, not yet ready).
  const presence::RemoteAvatar* visible_avatar() const;
  const SitePeerStats& stats() const { return stats_; }
  void close(double now) { net_.close(now); }

 private:
  void meet_remote_person(const net::Hello& hello);

  const SiteConfig& site_;
  const std::array<MoeNetworks, 2>& networks_;
  const ik::AvatarSolver& solver_;
  SiteSession net_;
  std::optional<presence::RemoteAvatar> avatar_;
  std::uint64_t stream_ = 0;  // the connection the avatar belongs to
  bool live_ = false;
  SitePeerStats stats_;
};

}  // namespace deixis::app
