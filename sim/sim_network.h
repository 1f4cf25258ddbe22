#pragma once
// The simulator on the network (`deixis sim --host` / `--join` / `--connect --room`, or the panel's
// Start; docs/sim.md): the virtual user is this site's user, streamed through a site::LivePeer
// every tick with the targets they selected (a direct SitePeer session, or a RoomPeer in a room of
// several people); every other person comes back as a translated avatar in this room (site A), on
// its avatar spots. One SimNetwork is one session, started from the flags or from the panel. A
// failure — refused, nobody within --wait, a port that cannot be bound — must not take the window
// down: it is kept as the state the panel shows (with the form to try again), and the run ends with
// exit 1 when the person closes it unless a later session took its place.

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>

#include "sim/sim_panel.h"
#include "site/live_peer.h"
#include "site/moe_weights.h"
#include "site/site_config.h"
#include "site/site_session.h"

namespace deixis::sim {

class SimNetwork {
 public:
  // Starts hosting (prints "port N" on stdout), joining or entering the room at once. `site`,
  // `networks` and `solver` (the avatar the other people wear here) must outlive this. `worn`:
  // the user's chosen avatar, offered to the others, and the local override (site/live_peer.h).
  SimNetwork(const site::LivePeerOptions& options, const site::SiteConfig& site,
             const BodyCalibration& user, const std::array<site::MoeNetworks, 2>& networks,
             const ik::AvatarSolver& solver, const site::WornAvatars& worn);

  // One 30 Hz tick: `user` (with the targets they selected) goes out, the other people's frames
  // that are due play into their avatars, which look at this site's user in `room` (and, in a
  // room, at each other). Stops for good at the first failure. Allocates nothing once streaming.
  // `sim_seconds`: the tick's simulator time, when the user was sampled. Frames are stamped with
  // it on the wall clock, so ticks a slow frame catches up on are not sent bunched together.
  void tick(const TrackingFrame& user, const LocalTargets& room, double sim_seconds);

  // Whether the session is on: false once it failed or was left.
  bool running() const { return peer_.has_value(); }
  // The other people's live avatars in this room; none while hidden or once not running.
  std::span<const presence::RemoteAvatar* const> visible_avatars() const;
  // What to draw of them: the live avatars and those fading in or out (site/remote_people.h).
  std::span<const site::DrawnAvatar> drawn_avatars() const;
  const site::LivePeerStats& stats() const;
  bool in_room() const { return std::holds_alternative<site::RoomPeerOptions>(options_); }
  // The remote people of the running session (running() only).
  const site::RemotePeople& people_here() const { return peer_->people(); }
  // Who stands on A's avatar spot `spot` now; kNoPerson when nobody or not running.
  PersonId person_on_spot(std::size_t spot) const {
    return peer_ ? peer_->person_on_spot(spot) : kNoPerson;
  }
  // The people present now (as of the last tick), at most kPanelPeople.
  std::span<const site::LivePerson> people() const {
    return std::span(people_).first(people_count_);
  }
  const std::string& error() const { return error_; }
  // The panel's network section.
  PanelNetwork panel() const;
  // Says bye to the other site and ends the session (the person left, or the run ends). Waits
  // at most 0.5 s for ENet to deliver the bye, as `deixis host` does.
  void close();

 private:
  void fail(const char* what);
  void end_session();

  site::LivePeerOptions options_;
  std::string_view address_;  // the host's, or the relay's
  std::uint16_t port_ = 0;    // the host's bound port, or the host's / relay's a joiner joins
  site::SiteClock clock_;
  double wall_at_sim_zero_ = -1.0;  // set at the first tick         // the network's clock (ENet's
                                    // and the jitter buffer's): the wall clock
  std::optional<site::LivePeer> peer_;
  site::LivePeerStats stats_;  // the peer's, kept after a failure
  std::array<site::LivePerson, kPanelPeople> people_{};
  std::size_t people_count_ = 0;
  std::string error_;
  bool left_ = false;  // closed by the person (or the run's end), not failed
};

}  // namespace deixis::sim
