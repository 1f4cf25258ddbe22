#pragma once
// A site on the network, the one runtime every front end drives (docs/architecture.md): the
// user's tracking goes to the other site every 30 Hz tick; the other site's person comes back as
// a translated avatar in this room (presence::RemoteAvatar). `deixis xr` and `deixis sim` drive it
// from their frame loops, `deixis host` / `join` from the scripted site's 30 Hz loop
// (site/scripted_site.h). It never blocks: a headset's frame loop must keep submitting frames and
// a window must keep drawing, so connecting is polled tick by tick (SiteSession::start/poll); a
// driver with nothing else to do may wait() on the network between ticks.

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "presence/remote_avatar.h"
#include "site/moe_weights.h"
#include "site/remote_people.h"
#include "site/site_config.h"
#include "site/site_session.h"

namespace deixis::site {

struct SitePeerOptions {
  net::Role role = net::Role::kHost;
  std::string address = "127.0.0.1";  // host: where to listen (docs/security.md); joiner: the host
  std::uint16_t port = 7350;          // host: 0 picks a free one
  std::string passphrase;
  double wait = 30.0;  // s for the other site to come
  // What the remote person's record measures (RemotePeople::records(): completion states and
  // gazes); by default nothing (a driver that measures through a RemotePersonWatcher).
  RemotePeopleOptions people{};
  // The avatar file the user chose, offered to the other site by its hash (docs/avatars.md).
  std::shared_ptr<const std::vector<std::byte>> avatar_file{};
  // Whether the other site's chosen avatar is fetched and worn (site/avatar_cache.h,
  // ChosenAvatars): only for a driver that draws each person in what they wear (people().
  // wearing()); otherwise everyone wears the site's avatar. Kept on disk in `avatar_cache`
  // (empty: in memory only).
  bool chosen_avatars = false;
  std::filesystem::path avatar_cache{};
};

struct SitePeerStats {
  std::uint64_t ticks = 0, sent = 0, played = 0, missed = 0, visible_ticks = 0;
  std::string peer_site = "?";
};

// What a driver that measures the remote person (the scripted site, site/scripted_site.h) is told
// as they are played. Called from inside tick(); the avatar is the one just ticked.
class RemotePersonWatcher {
 public:
  virtual ~RemotePersonWatcher() = default;
  // A new stream began (the first, or after a reconnect): the person may have changed.
  virtual void on_new_person(const net::Hello& hello, const presence::RemoteAvatar& avatar) = 0;
  // One played frame (null: missed) and how long the translation and IK took.
  virtual void on_played(const net::Playout& playout, const presence::RemoteAvatar& avatar,
                         double translation_ms) = 0;
  // A tick without a live stream (before the first, or after the other site left).
  virtual void on_no_stream() = 0;
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

  // One tick: services the link, sends the user's frame once streaming (stamped `sampled`, when
  // it was sampled on this site's clock), plays the remote person's frames that are due into
  // their avatar. Throws deixis::Error when refused or when nobody came within `wait` s.
  // Allocates nothing once streaming (tests/site/site_peer_allocation_test.cpp).
  void tick(const TrackingFrame& user, double sampled, double now, const LocalTargets& room,
            RemotePersonWatcher* watcher = nullptr);
  void tick(const TrackingFrame& user, double now, const LocalTargets& room) {
    tick(user, now, now, room);
  }
  // Services the network without sending or playing (a driver waiting for the other site);
  // throws as tick() does.
  void poll(double now) { net_.poll(now); }
  // Waits on the network until `until` (services it meanwhile, so nothing is late), for a driver
  // whose loop has nothing else to do between ticks.
  void wait(const SiteClock& clock, double until);

  // The avatar to draw this tick; null while it must be hidden (no live stream, not yet ready).
  const presence::RemoteAvatar* visible_avatar() const;
  // The other site's person as one of the remote people (PersonId kDirectPerson, on the site's
  // first spot); in this direct session they stay "the other person" (target 0) for both sites.
  const RemotePeople& people() const { return people_; }
  static constexpr PersonId kDirectPerson = 1;
  const SitePeerStats& stats() const { return stats_; }
  const SiteSession& network() const { return net_; }
  // The user recalibrated: the new calibration goes to the other site in a new hello (at once
  // when connected, else with the next one); their avatar of us starts afresh from it. Throws
  // deixis::Error if it breaks a wire rule.
  void set_user(const SiteConfig& site, const BodyCalibration& user);
  void close(double now) { net_.close(now); }

 private:
  void meet_remote_person(const net::Hello& hello, RemotePersonWatcher* watcher);
  void take_chosen_avatar();
  void play_due_frames(double now, const LocalTargets& room, RemotePersonWatcher* watcher);

  SiteSession net_;
  RemotePeople people_;
  std::unique_ptr<ChosenAvatars> chosen_;  // null: everyone wears the site's avatar
  std::uint64_t hellos_ = 0;               // the peer's hello the avatar was made for
  bool live_ = false;
  SitePeerStats stats_;
};

}  // namespace deixis::site
