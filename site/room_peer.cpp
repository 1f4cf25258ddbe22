#include "site/room_peer.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <thread>

#include "core/error.h"

namespace deixis::site {

namespace {

net::RoomConfig room_config(const RoomPeerOptions& options, const SiteConfig& site,
                            const BodyCalibration& user) {
  net::RoomConfig c;
  c.hello = site_hello(site, user);
  c.target_map = site.target_map;
  c.passphrase = options.passphrase;
  c.avatar_file = options.avatar_file;
  return c;
}

}  // namespace

class RoomPeer::LossyTransport final : public net::RoomTransport {
 public:
  LossyTransport(net::RoomTransport& inner, double loss, std::uint32_t seed, RoomPeerStats& stats)
      : inner_(inner), loss_(loss), rng_(seed), stats_(stats) {}
  bool enter(std::span<const std::uint8_t> params,
             std::span<const std::uint8_t> announce) override {
    return inner_.enter(params, announce);
  }
  bool send(net::MemberId to, net::Channel channel,
            std::span<const std::uint8_t> payload) override {
    if (channel == net::Channel::kTracking && loss_ > 0.0 &&
        std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < loss_) {
      ++stats_.dropped_on_purpose;
      return true;  // lost on the way, as far as the sender can tell
    }
    return inner_.send(to, channel, payload);
  }

 private:
  net::RoomTransport& inner_;
  double loss_;
  std::mt19937 rng_;
  RoomPeerStats& stats_;
};

RoomPeer::RoomPeer(const RoomPeerOptions& options, const SiteConfig& site,
                   const BodyCalibration& user, const std::array<MoeNetworks, 2>& networks,
                   const ik::AvatarSolver& solver, double now)
    : options_(options), people_(site, networks, solver, options.people), started_(now) {
  if (options_.room.empty()) {
    throw Error("room: a room name is needed (--room NAME)");
  }
  net::RelayClientOptions relay;
  relay.host = options_.relay_host;
  relay.port = options_.relay_port;
  relay.room = net::room_token(options_.room);
  client_ = std::make_unique<net::RelayClient>(relay, now);
  relay_transport_ = std::make_unique<net::RelayTransport>(*client_);
  transport_ = std::make_unique<LossyTransport>(*relay_transport_, options_.drop_tracking,
                                                options_.drop_seed, stats_);
  session_ = std::make_unique<net::RoomSession>(*transport_, room_config(options_, site, user));
  // At most one frame per person per round: sized once for every spot.
  batch_.reserve(people_.capacity());
  if (options_.chosen_avatars && !options_.people.override_avatar) {
    chosen_ = std::make_unique<ChosenAvatars>(options_.avatar_cache);
  }
}

RoomPeer::~RoomPeer() = default;

void RoomPeer::set_user(const SiteConfig& site, const BodyCalibration& user) {
  session_->set_hello(site_hello(site, user));
}

void RoomPeer::service(double now, std::uint32_t wait_ms) {
  session_->poll(now);
  client_->poll(now, *session_, wait_ms);
  take_events();
  check(now);
}

void RoomPeer::check(double now) const {
  if (session_->state() == net::RoomState::kRefused) {
    throw Error("room " + options_.room + " at " + options_.relay_host + ":" +
                std::to_string(options_.relay_port) + ": " + session_->refusal_text());
  }
  if (!entered_once_ && !in_room() && now - started_ > options_.wait) {
    throw Error(client_->connected()
                    ? "room " + options_.room + ": the relay at " + options_.relay_host + ":" +
                          std::to_string(options_.relay_port) +
                          " did not let this site in within " +
                          std::to_string(static_cast<int>(options_.wait)) + " s"
                    : "no relay answered at " + options_.relay_host + ":" +
                          std::to_string(options_.relay_port) + " within " +
                          std::to_string(static_cast<int>(options_.wait)) +
                          " s (is `deixis relay` running there?)");
  }
}

void RoomPeer::take_events() {
  entered_once_ = entered_once_ || in_room();
  net::RoomEvent e;
  while (session_->next_event(e)) {
    switch (e.kind) {
      case net::RoomEventKind::kArrived:
      case net::RoomEventKind::kHelloChanged:
        if (const net::Hello* hello = session_->hello(e.person); hello != nullptr) {
          try {
            people_.meet(e.person, *hello);
            spdlog::info("room {}: {} is here", options_.room, hello->site);
            if (chosen_) {
              chosen_->named(e.person, hello->site, session_->avatar_hash(e.person));
            }
          } catch (const Error& error) {
            // More people than spots: this person is not shown here; the others go on.
            ++stats_.people_refused;
            spdlog::error("room {}: {} is not shown: {}", options_.room, hello->site, error.what());
          }
        }
        break;
      case net::RoomEventKind::kLeft:
        if (const PersonStats* person = people_.stats(e.person); person != nullptr) {
          spdlog::info("room {}: {} left ({})", options_.room, person->site,
                       net::left_because_name(e.why));
        }
        people_.leave(e.person);
        if (chosen_) {
          chosen_->left(e.person);
        }
        break;
      case net::RoomEventKind::kTargetMapChanged:
        break;  // read with each played frame
      case net::RoomEventKind::kAvatarFile:
        avatar_download_ended(e.person);
        break;
    }
  }
  if (chosen_) {
    take_chosen_avatars();
  }
}

void RoomPeer::avatar_download_ended(net::MemberId person) {
  const net::AvatarReceiver* download = session_->avatar_download(person);
  if (!chosen_ || download == nullptr) {
    return;
  }
  if (download->status() == net::AvatarReceiveStatus::kComplete) {
    chosen_->downloaded(person, download->file());
  } else if (download->status() == net::AvatarReceiveStatus::kFailed) {
    chosen_->download_failed(person, download->failure());
  }
}

// What ChosenAvatars says is due: ask a person for their file; dress them in it. Loads run on
// their own thread, so this never waits.
void RoomPeer::take_chosen_avatars() {
  ChosenAvatars::Update update;
  while (chosen_->next(update)) {
    if (update.kind == ChosenAvatars::Update::Kind::kRequest) {
      if (!session_->request_avatar(update.person)) {
        chosen_->download_failed(update.person, "they could not be asked for it");
      }
    } else if (people_.wear(update.person, update.avatar)) {
      const PersonStats* person = people_.stats(update.person);
      spdlog::info("room {}: {} wears the avatar they chose ({} joints)", options_.room,
                   person != nullptr ? person->site : "?", update.avatar->solver.joint_count());
    }
  }
}

void RoomPeer::poll(double now) {
  service(now, 0);
}

void RoomPeer::tick(const TrackingFrame& user, double sampled, double now,
                    const LocalTargets& room) {
  ++stats_.ticks;
  service(now, 0);
  if (in_room()) {
    TrackingFrame frame = user;
    frame.time = sampled;  // the sampling time, not when a late loop got to it (as SitePeer)
    if (session_->send_tracking(frame, sampled)) {
      ++stats_.sent;
    }
  }
  LocalTargets with_people = room;
  with_people.people = people_.people_targets(session_->self(), user.T_world_head.translation);
  stats_.tick_translation_ms = -1.0;
  play_due_frames(now, with_people);
  people_.end_tick();
}

void RoomPeer::play_due_frames(double now, const LocalTargets& room) {
  // Rounds of at most one frame per person, so that the networks run batched across people
  // (RemotePeople::tick); a person who has more than one due frame (a late loop catching up)
  // plays them over several rounds, in order.
  for (bool more = true; more;) {
    more = false;
    batch_.clear();
    for (const net::MemberId person : session_->people()) {
      if (people_.avatar(person) == nullptr || batch_.size() == batch_.capacity()) {
        continue;
      }
      const net::Playout p = session_->next_playout(person, now);
      if (p.kind == net::PlayoutKind::kNoStream) {
        // Their stream stopped (or has not begun): hidden until frames come again.
        people_.set_live(person, false);
        people_.interrupt(person);
        continue;
      }
      if (p.kind == net::PlayoutKind::kPending) {
        continue;
      }
      const bool missed = p.kind == net::PlayoutKind::kMissed;
      people_.set_live(person, true);
      stats_.played += missed ? 0 : 1;
      stats_.missed += missed ? 1 : 0;
      batch_.push_back(PersonFrame{person, missed ? nullptr : p.frame, p.sequence,
                                   session_->target_map(person)});
      more = true;
    }
    if (!batch_.empty()) {
      const auto began = std::chrono::steady_clock::now();
      people_.tick(batch_, room, now - started_);
      const std::chrono::duration<double, std::milli> took =
          std::chrono::steady_clock::now() - began;
      stats_.tick_translation_ms = std::max(stats_.tick_translation_ms, 0.0) + took.count();
    }
  }
}

void RoomPeer::wait(const SiteClock& clock, double until) {
  double now = clock.now();
  while (now < until) {
    service(now, static_cast<std::uint32_t>(std::max(1.0, (until - now) * 1000.0)));
    now = clock.now();
  }
}

void RoomPeer::close(double now) {
  if (closed_) {
    return;
  }
  closed_ = true;
  session_->leave(now);
  client_->close(now);
  people_.finish();
}

}  // namespace deixis::site
