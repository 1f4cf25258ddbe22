#include "site/live_peer.h"

#include <algorithm>

namespace deixis::site {

namespace {

using Peer = std::variant<SitePeer, RoomPeer>;

// Neither runtime moves (they own sockets and are pointed at), so the variant is built in place
// and returned as a prvalue (no move needed).
// The front ends draw each person in what they wear (render/mesh_cache.h), so people's chosen
// avatars are fetched and worn, as host and join do, and the user's own is offered.
template <class Options>
Options wearing(Options options, const WornAvatars& worn) {
  options.chosen_avatars = true;
  options.avatar_file = worn.own_file;
  options.people.override_avatar = worn.override_avatar;
  return options;
}

Peer make_peer(const LivePeerOptions& options, const SiteConfig& site, const BodyCalibration& user,
               const std::array<MoeNetworks, 2>& networks, const ik::AvatarSolver& solver,
               const WornAvatars& worn, double now) {
  if (const RoomPeerOptions* room = std::get_if<RoomPeerOptions>(&options)) {
    return Peer(std::in_place_type<RoomPeer>, wearing(*room, worn), site, user, networks, solver,
                now);
  }
  return Peer(std::in_place_type<SitePeer>, wearing(std::get<SitePeerOptions>(options), worn), site,
              user, networks, solver, now);
}

constexpr std::size_t kSitesReserved = 256;  // bytes: "B,C,…" for a full room without allocating

}  // namespace

LivePeerOptions live_peer_options(bool host, const std::string& address, std::uint16_t port,
                                  const std::string& room, const std::string& passphrase,
                                  double wait) {
  if (!room.empty()) {
    RoomPeerOptions o;
    o.relay_host = address;
    o.relay_port = port;
    o.room = room;
    o.passphrase = passphrase;
    o.wait = wait;
    return o;
  }
  return SitePeerOptions{host ? net::Role::kHost : net::Role::kJoiner, address, port, passphrase,
                         wait};
}

LivePeer::LivePeer(const LivePeerOptions& options, const SiteConfig& site,
                   const BodyCalibration& user, const std::array<MoeNetworks, 2>& networks,
                   const ik::AvatarSolver& solver, const WornAvatars& worn, double now)
    : peer_(make_peer(options, site, user, networks, solver, worn, now)),
      host_(std::holds_alternative<SitePeerOptions>(options) &&
            std::get<SitePeerOptions>(options).role == net::Role::kHost) {
  stats_.peer_site.reserve(kSitesReserved);
  links_.resize(people().capacity());
}

std::uint16_t LivePeer::port() const {
  const SitePeer* direct = std::get_if<SitePeer>(&peer_);
  return direct != nullptr && host_ ? direct->port() : 0;
}

bool LivePeer::connected() const {
  if (const SitePeer* direct = std::get_if<SitePeer>(&peer_)) {
    return direct->streaming();
  }
  return std::get<RoomPeer>(peer_).in_room();
}

void LivePeer::tick(const TrackingFrame& user, double sampled, double now,
                    const LocalTargets& room) {
  std::visit([&](auto& peer) { peer.tick(user, sampled, now, room); }, peer_);
  refresh(now);
  stats_.visible_ticks += visible().empty() ? 0 : 1;
}

void LivePeer::poll(double now) {
  std::visit([&](auto& peer) { peer.poll(now); }, peer_);
  refresh(now);
}

void LivePeer::set_user(const SiteConfig& site, const BodyCalibration& user) {
  std::visit([&](auto& peer) { peer.set_user(site, user); }, peer_);
}

void LivePeer::close(double now) {
  if (closed_) {
    return;
  }
  closed_ = true;
  std::visit([&](auto& peer) { peer.close(now); }, peer_);
}

std::span<const presence::RemoteAvatar* const> LivePeer::visible() const {
  if (const RoomPeer* room = std::get_if<RoomPeer>(&peer_)) {
    return room->people().visible();
  }
  return direct_visible_ != nullptr ? std::span(&direct_visible_, 1)
                                    : std::span<const presence::RemoteAvatar* const>();
}

const RemotePeople& LivePeer::people() const {
  return std::visit([](const auto& peer) -> const RemotePeople& { return peer.people(); }, peer_);
}

SelectionCandidates LivePeer::candidates(const TargetMap& map, const Vec3& own_head,
                                         const Vec3& partner_head) {
  if (RoomPeer* room = std::get_if<RoomPeer>(&peer_)) {
    // Nobody is "the other person" in a room: the people are candidates at their avatars' eyes.
    return SelectionCandidates{&map, nullptr, room->people().people_targets(room->self(), own_head),
                               room->self()};
  }
  partner_head_ = direct_visible_ != nullptr ? direct_visible_->eye_midpoint() : partner_head;
  return SelectionCandidates{&map, &partner_head_, {}, kNoPerson};
}

std::size_t LivePeer::list_people(std::span<LivePerson> out) const {
  const RemotePeople& people = this->people();
  const std::span<const presence::RemoteAvatar* const> shown = visible();
  std::size_t n = 0;
  const auto add = [&](PersonId id) {
    const PersonStats* s = people.stats(id);
    if (s == nullptr || n == out.size()) {
      return;
    }
    const presence::RemoteAvatar* avatar = people.avatar(id);
    const bool live = std::find(shown.begin(), shown.end(), avatar) != shown.end();
    const PersonAvatar* worn = people.wearing(id);
    out[n++] = LivePerson{s->site,
                          live,
                          s->frames_played,
                          s->visible_ticks,
                          worn != nullptr ? avatar_source_name(worn->source) : "default",
                          avatar != nullptr ? avatar->solver().joint_count() : 0,
                          link_of(s->spot, live)};
  };
  if (const RoomPeer* room = std::get_if<RoomPeer>(&peer_)) {
    for (const net::MemberId id : room->session().people()) {
      add(id);
    }
  } else {
    add(SitePeer::kDirectPerson);
  }
  return n;
}

PersonId LivePeer::person_on_spot(std::size_t spot) const {
  const RemotePeople& people = this->people();
  const auto on_spot = [&](PersonId id) {
    const PersonStats* s = people.stats(id);
    return s != nullptr && s->spot == spot;
  };
  if (const RoomPeer* room = std::get_if<RoomPeer>(&peer_)) {
    for (const net::MemberId id : room->session().people()) {
      if (on_spot(id)) {
        return id;
      }
    }
    return kNoPerson;
  }
  return on_spot(SitePeer::kDirectPerson) ? SitePeer::kDirectPerson : kNoPerson;
}

void LivePeer::refresh(double now) {
  watch_links(now);
  if (const SitePeer* direct = std::get_if<SitePeer>(&peer_)) {
    direct_visible_ = direct->visible_avatar();
    const SitePeerStats& s = direct->stats();
    stats_.ticks = s.ticks;
    stats_.sent = s.sent;
    stats_.played = s.played;
    stats_.missed = s.missed;
    stats_.peer_site = s.peer_site;  // within the reserved capacity: no allocation
    return;
  }
  const RoomPeer& room = std::get<RoomPeer>(peer_);
  const RoomPeerStats& s = room.stats();
  stats_.ticks = s.ticks;
  stats_.sent = s.sent;
  stats_.played = s.played;
  stats_.missed = s.missed;
  // Everyone here now, in arrival order; rebuilt only when someone came or went.
  if (room.people().size() != sites_listed_) {
    sites_listed_ = room.people().size();
    std::string& sites = stats_.peer_site;
    sites.clear();
    for (const net::MemberId id : room.session().people()) {
      if (const PersonStats* p = room.people().stats(id)) {
        if (!sites.empty()) {
          sites.push_back(',');
        }
        sites.append(p->site);
      }
    }
    if (sites.empty()) {
      sites.push_back('?');
    }
  }
}

// Each spot's window follows whoever stands there; another person (or nobody) starts it over.
void LivePeer::watch_links(double now) {
  for (std::size_t spot = 0; spot < links_.size(); ++spot) {
    SpotLink& link = links_[spot];
    const PersonId person = person_on_spot(spot);
    if (person != link.person) {
      link.person = person;
      link.window.reset();
    }
    if (person == kNoPerson) {
      continue;
    }
    const net::JitterStats* jitter = nullptr;
    if (const RoomPeer* room = std::get_if<RoomPeer>(&peer_)) {
      jitter = room->session().jitter(person);
    } else {
      jitter = &std::get<SitePeer>(peer_).network().session().jitter();
    }
    if (jitter != nullptr) {
      link.window.update(now, *jitter);
    }
  }
}

LinkFigures LivePeer::link_of(std::size_t spot, bool live) const {
  LinkFigures f = spot < links_.size() ? links_[spot].window.figures() : LinkFigures{};
  const PersonStats* s = spot < links_.size() ? people().stats(links_[spot].person) : nullptr;
  f.state = live                                   ? LinkState::kLive
            : s != nullptr && s->frames_played > 0 ? LinkState::kStalled
                                                   : LinkState::kWaiting;
  if (const RoomPeer* room = std::get_if<RoomPeer>(&peer_)) {
    f.via_relay = true;
    if (room->relay().connected()) {
      f.round_trip_ms = room->relay().round_trip_ms();
    }
  } else if (const SitePeer& direct = std::get<SitePeer>(peer_); direct.streaming()) {
    f.round_trip_ms = direct.network().session().status().round_trip_ms;
  }
  return f;
}

}  // namespace deixis::site
