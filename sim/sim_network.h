#pragma once
// The simulator on the network (`deixis sim --host` / `--join`, or the panel's Start; docs/sim.md):
// the virtual user is this site's user, streamed through a site::SitePeer every tick with the
// targets they selected; the other site's person comes back as a translated avatar in this room
// (site A). One SimNetwork is one session, started from the flags or from the panel alike. A
// failure — refused, nobody within --wait, a port that cannot be bound — must not take the window
// down: it is kept as the state the panel shows (with the form to try again), and the run ends with
// exit 1 when the person closes it unless a later session took its place.

#include <array>
#include <optional>
#include <string>

#include "sim/sim_panel.h"
#include "site/moe_weights.h"
#include "site/site_config.h"
#include "site/site_peer.h"
#include "site/site_session.h"

namespace deixis::sim {

class SimNetwork {
 public:
  // Starts hosting (prints "port N" on stdout) or joining at once. `site`, `networks` and
  // `solver` (the avatar the other person wears here) must outlive this.
  SimNetwork(const site::SitePeerOptions& options, const site::SiteConfig& site,
             const BodyCalibration& user, const std::array<site::MoeNetworks, 2>& networks,
             const ik::AvatarSolver& solver);

  // One 30 Hz tick: `user` (with the targets they selected) goes out, the other person's frames
  // that are due play into their avatar, which looks at this site's user in `room`. Stops for
  // good at the first failure. Allocates nothing once streaming.
  // `sim_seconds`: the tick's simulator time, when the user was sampled. Frames are stamped with
  // it on the wall clock, so ticks a slow frame catches up on are not sent bunched together.
  void tick(const TrackingFrame& user, const LocalTargets& room, double sim_seconds);

  // Whether the session is on: false once it failed or was left.
  bool running() const { return peer_.has_value(); }
  // The other person's avatar to draw in this room; null while hidden or once not running.
  const presence::RemoteAvatar* visible_avatar() const;
  const site::SitePeerStats& stats() const;
  const std::string& error() const { return error_; }
  // The panel's network section.
  PanelNetwork panel() const;
  // Says bye to the other site and ends the session (the person left, or the run ends). Waits
  // at most 0.5 s for ENet to deliver the bye, as `deixis host` does.
  void close();

 private:
  void fail(const char* what);
  void end_session();

  site::SitePeerOptions options_;
  std::uint16_t port_ = 0;  // the host's bound port, or the host's a joiner joins
  site::SiteClock clock_;
  double wall_at_sim_zero_ = -1.0;  // set at the first tick         // the network's clock (ENet's
                                    // and the jitter buffer's): the wall clock
  std::optional<site::SitePeer> peer_;
  site::SitePeerStats stats_;  // the peer's, kept after a failure
  std::string error_;
  bool left_ = false;  // closed by the person (or the run's end), not failed
};

}  // namespace deixis::sim
