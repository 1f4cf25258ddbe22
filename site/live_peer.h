#pragma once
// The site runtime a live user's front end drives (`deixis sim`, `deixis xr`): either the direct
// two-person session (site::SitePeer) or a room of several people through a relay
// (site::RoomPeer), chosen at run time (flags, or the simulator's panel) behind one shape, so each
// front end keeps one frame loop for both (docs/decisions.md 64). Like both runtimes it never
// blocks: a headset must keep submitting frames and a window must keep drawing.
//
// The scripted site of host/join picks its runtime at compile time instead (a template over the
// peer, site/scripted_site.cpp): its loop differs per runtime in what it measures, while a live
// front end only sends its user, shows everyone visible and lists who is there.

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/target_map.h"
#include "gesture/target_selection.h"
#include "site/link_health.h"
#include "site/room_peer.h"
#include "site/site_peer.h"

namespace deixis::site {

using LivePeerOptions = std::variant<SitePeerOptions, RoomPeerOptions>;

// What a front end's network flags ask for: the room `room` on the relay at address:port when a
// room is named, else a direct session as host (listening on address:port) or joiner.
LivePeerOptions live_peer_options(bool host, const std::string& address, std::uint16_t port,
                                  const std::string& room, const std::string& passphrase,
                                  double wait);

struct LivePeerStats {
  std::uint64_t ticks = 0, sent = 0, played = 0, missed = 0;
  std::uint64_t visible_ticks = 0;  // ticks at least one remote avatar was shown
  std::string peer_site = "?";      // the other site; in a room, everyone met, comma-separated
};

// A remote person as a front end lists them (the simulator's panel, the end-of-run summary).
// `site` points into the runtime's records: valid until its next tick.
struct LivePerson {
  std::string_view site;
  bool live = false;  // their avatar is shown (their stream is live and the avatar ready)
  std::uint64_t frames_played = 0;
  std::uint64_t visible_ticks = 0;
  std::string_view avatar = "default";  // what they wear here (avatar_source_name)
  int avatar_joints = 0;                // its skeleton's joints
  LinkFigures link{};                   // how their link is doing (site/link_health.h)
};

class LivePeer {
 public:
  // Starts the runtime `options` names (a direct host binds, a joiner or a room member sends its
  // first packet); throws deixis::Error as SitePeer's and RoomPeer's constructors do. The user
  // offers `worn.own_file` to the people they meet; everyone here wears `worn.override_avatar`
  // when set, else what they chose (fetched as host and join do).
  LivePeer(const LivePeerOptions& options, const SiteConfig& site, const BodyCalibration& user,
           const std::array<MoeNetworks, 2>& networks, const ik::AvatarSolver& solver,
           const WornAvatars& worn, double now);
  LivePeer(const LivePeer&) = delete;
  LivePeer& operator=(const LivePeer&) = delete;

  bool in_room() const { return std::holds_alternative<RoomPeer>(peer_); }
  // A direct host's bound port; 0 otherwise.
  std::uint16_t port() const;
  // The other site streams (direct), or this site is in the room (room; others come and go).
  bool connected() const;

  // One tick, as SitePeer::tick and RoomPeer::tick: sends `user` (sampled at `sampled`), plays
  // the remote people's due frames with `room`'s targets (a room adds its people). Throws
  // deixis::Error when refused, or when nobody came (direct) or the room was not entered within
  // the wait. Allocates nothing once streaming / once everyone in the room has met.
  void tick(const TrackingFrame& user, double sampled, double now, const LocalTargets& room);
  void poll(double now);
  // The user recalibrated (a button in the headset): the new calibration goes out in a new hello
  // (SitePeer::set_user, RoomPeer::set_user). Throws deixis::Error if it breaks a wire rule.
  void set_user(const SiteConfig& site, const BodyCalibration& user);
  // Says bye (at most 0.5 s); idempotent.
  void close(double now);

  // The live avatars this tick, in spot order.
  std::span<const presence::RemoteAvatar* const> visible() const;
  // What to draw this tick, in spot order: the live avatars and those fading in or out.
  std::span<const DrawnAvatar> drawn() const { return people().drawn(); }
  const RemotePeople& people() const;
  // What a live user may designate here (gesture/target_selection.h): this room's objects, and
  // the other person of a direct session at `partner_head` (their avatar's eyes when shown) or,
  // in a room, the room's people at their avatars' eyes. Valid until the next tick.
  SelectionCandidates candidates(const TargetMap& map, const Vec3& own_head,
                                 const Vec3& partner_head);
  // The remote people present now, into `out` (at most out.size()); returns how many. Allocates
  // nothing.
  std::size_t list_people(std::span<LivePerson> out) const;
  // Who stands on the site's avatar spot `spot` now (kNoPerson: nobody).
  PersonId person_on_spot(std::size_t spot) const;
  const LivePeerStats& stats() const { return stats_; }

 private:
  // The runtime's figures into stats_, the direct avatar shown, each person's link window.
  void refresh(double now);
  void watch_links(double now);
  // How the link of the person on `spot` is doing (`live`: their avatar is shown).
  LinkFigures link_of(std::size_t spot, bool live) const;

  // One per avatar spot: the link window of whoever stands there.
  struct SpotLink {
    PersonId person = kNoPerson;
    LinkWindow window;
  };

  std::variant<SitePeer, RoomPeer> peer_;
  bool host_ = false;  // a direct session's host
  LivePeerStats stats_;
  std::size_t sites_listed_ = 0;  // people present when stats_.peer_site was last listed
  const presence::RemoteAvatar* direct_visible_ = nullptr;  // the direct session's avatar, if shown
  std::vector<SpotLink> links_;                             // sized at construction
  Vec3 partner_head_ = Vec3::Zero();
  bool closed_ = false;
};

}  // namespace deixis::site
