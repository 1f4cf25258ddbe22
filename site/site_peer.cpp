#include "site/site_peer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>

namespace deixis::site {

SitePeer::SitePeer(const SitePeerOptions& options, const SiteConfig& site,
                   const BodyCalibration& user, const std::array<MoeNetworks, 2>& networks,
                   const ik::AvatarSolver& solver, double now)
    : net_(SiteSessionOptions{options.role, options.address, options.port, options.passphrase,
                              options.avatar_file},
           site_hello(site, user), site.target_map),
      people_(site, networks, solver, options.people) {
  if (options.chosen_avatars && !options.people.override_avatar) {
    chosen_ = std::make_unique<ChosenAvatars>(options.avatar_cache);
  }
  net_.start(now, options.wait);
}

void SitePeer::meet_remote_person(const net::Hello& hello, RemotePersonWatcher* watcher) {
  // A new connection (the first, or after a reconnect) or a new hello in this one (they
  // recalibrated): the person may have changed, and gets a fresh avatar on the first spot.
  const presence::RemoteAvatar& avatar = people_.meet(kDirectPerson, hello);
  hellos_ = net_.session().status().hellos;
  stats_.peer_site = hello.site;
  spdlog::info("streaming with site {}", hello.site);
  if (chosen_) {
    chosen_->named(kDirectPerson, hello.site, net::parse_avatar_hash(hello.avatar.model));
  }
  if (watcher != nullptr) {
    watcher->on_new_person(hello, avatar);
  }
}

void SitePeer::set_user(const SiteConfig& site, const BodyCalibration& user) {
  net_.session().set_hello(site_hello(site, user));
}

void SitePeer::tick(const TrackingFrame& user, double sampled, double now, const LocalTargets& room,
                    RemotePersonWatcher* watcher) {
  ++stats_.ticks;
  net_.poll(now);
  live_ = false;
  if (net_.streaming()) {
    net::Session& session = net_.session();
    if (const net::Hello* hello = session.remote_hello();
        hello != nullptr && session.status().hellos != hellos_) {
      meet_remote_person(*hello, watcher);
    }
    TrackingFrame frame = user;
    // Stamped with its sampling time on the sender's clock, not with when a late loop got to it:
    // ticks caught up after a stall must not go out bunched, or the other site's jitter buffer
    // plays them as a jerk.
    frame.time = sampled;
    stats_.sent += session.send_tracking(frame) ? 1 : 0;
    play_due_frames(now, room, watcher);
  }
  if (chosen_) {
    take_chosen_avatar();
  }
  if (!live_ && watcher != nullptr) {
    watcher->on_no_stream();
  }
  if (!live_) {
    people_.interrupt(kDirectPerson);  // a hold being measured ends with the stream
  }
  people_.set_live(kDirectPerson, live_);
  people_.end_tick();
  stats_.visible_ticks += visible_avatar() != nullptr ? 1 : 0;
}

// The other person's chosen avatar: their download as it ends, then what ChosenAvatars says is
// due (ask for the file; wear it). Loads run on their own thread, so this never waits.
void SitePeer::take_chosen_avatar() {
  net::Session& session = net_.session();
  if (chosen_->awaiting(kDirectPerson)) {
    const net::AvatarReceiver& download = session.avatar_download();
    switch (download.status()) {
      case net::AvatarReceiveStatus::kComplete:
        chosen_->downloaded(kDirectPerson, download.file());
        break;
      case net::AvatarReceiveStatus::kFailed:
        chosen_->download_failed(kDirectPerson, download.failure());
        break;
      case net::AvatarReceiveStatus::kIdle:
        chosen_->download_failed(kDirectPerson, "the connection ended first");
        break;
      case net::AvatarReceiveStatus::kReceiving:
        break;
    }
  }
  ChosenAvatars::Update update;
  while (chosen_->next(update)) {
    if (update.kind == ChosenAvatars::Update::Kind::kRequest) {
      if (!session.request_avatar()) {
        chosen_->download_failed(kDirectPerson, "the other site could not be asked for it");
      }
    } else if (people_.wear(kDirectPerson, update.avatar)) {
      spdlog::info("site {} wears the avatar they chose ({} joints)", stats_.peer_site,
                   update.avatar->solver.joint_count());
    }
  }
}

void SitePeer::play_due_frames(double now, const LocalTargets& room, RemotePersonWatcher* watcher) {
  net::Session& session = net_.session();
  net::Playout p = session.next_frame(now);
  for (; p.kind == net::PlayoutKind::kFrame || p.kind == net::PlayoutKind::kMissed;
       p = session.next_frame(now)) {
    const presence::RemoteAvatar* avatar = people_.avatar(kDirectPerson);
    if (avatar == nullptr) {
      continue;
    }
    const bool missed = p.kind == net::PlayoutKind::kMissed;
    const auto t0 = std::chrono::steady_clock::now();
    people_.play(PersonFrame{kDirectPerson, missed ? nullptr : p.frame, p.sequence,
                             net_.session().remote_target_map()},
                 room, now);
    const std::chrono::duration<double, std::milli> took = std::chrono::steady_clock::now() - t0;
    stats_.played += missed ? 0 : 1;
    stats_.missed += missed ? 1 : 0;
    if (watcher != nullptr) {
      watcher->on_played(p, *avatar, took.count());
    }
  }
  live_ = p.kind != net::PlayoutKind::kNoStream;
}

void SitePeer::wait(const SiteClock& clock, double until) {
  double now = clock.now();
  while (now < until) {
    net_.session().service(now, static_cast<std::uint32_t>(std::max(1.0, (until - now) * 1000.0)));
    now = clock.now();
  }
}

const presence::RemoteAvatar* SitePeer::visible_avatar() const {
  const presence::RemoteAvatar* avatar = people_.avatar(kDirectPerson);
  return live_ && avatar != nullptr && avatar->visible() ? avatar : nullptr;
}

}  // namespace deixis::site
