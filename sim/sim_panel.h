#pragma once
// The simulator's Dear ImGui panel (docs/sim.md): live plots of the remote avatar's three
// progressions (MPNet) and blend weights, per-tick timings, the virtual user's commands and
// status, the network (a form to host or join a session, or the session's state) and the avatar
// choice. Drawing it reports what the person clicked (PanelActions) and where each widget was
// (PanelWidgets: the smoke test checks they are there, scripted input aims at them). Needs an
// ImGui frame begun; allocates nothing of its own.

#include <array>
#include <span>
#include <string_view>

#include "sim/sim_history.h"
#include "sim/sim_network_form.h"
#include "sim/sim_views.h"
#include "site/live_peer.h"

namespace deixis::sim {

// People listed in a room's network section, at most (a relay's default room holds 8).
inline constexpr std::size_t kPanelPeople = 8;

// The network section when the simulator hosts or joins another site, or is in a room
// (sim/sim_network.h).
struct PanelNetwork {
  std::string_view role;     // "host", "join" or "room"
  std::string_view address;  // host: where it listens; joiner: the host; room: the relay
  unsigned port = 0;         // host: the port bound (0 picks one, shown here)
  bool passphrase = false;   // set or not (never shown)
  std::string_view peer_site = "?";
  std::uint64_t sent = 0;    // tracking frames sent
  std::uint64_t played = 0;  // the other person's frames played into their avatar
  std::string_view state;  // "waiting for the other site", "streaming", "in the room", or the error
  bool failed = false;
  bool running = false;   // false once it failed or was left: the form is shown again
  std::string_view room;  // the room's name (role "room"; else empty)
  std::span<const site::LivePerson> people;  // in a room: who is here now, live or not
};

// What the panel shows, read-only.
struct PanelStatus {
  const SimHistory* history = nullptr;
  bool scripted_user = false;  // --script: the user's commands are disabled
  bool avatar_visible = false;
  std::span<const TargetObject> local_objects;  // the user's room, for point/touch buttons
  std::string_view status;                      // the last command's outcome
  const PanelNetwork* network = nullptr;        // the last session; null: none was started
  std::string_view start_disabled;              // why Start is off (--fixed-step); empty: on
  std::string_view form_problem;                // what the last Start found wrong in the form
  std::string_view avatar;                      // the remote avatar's .glb
  std::string_view avatar_note;                 // the last avatar load's error, if any
  double seconds = 0.0;                         // simulator time
  std::uint64_t ticks = 0;
};

// What the person edits in the panel; kept by the caller between frames.
struct PanelEdits {
  std::array<char, 512> avatar_path{};
  TargetId selected = 1;  // the object the Point and Touch buttons act on
  NetworkForm network;    // host or join, address or port, passphrase
};

struct PanelActions {
  TargetId point = kNoTarget;
  TargetId touch = kNoTarget;
  bool look_at_partner = false;
  bool explain = false;
  bool rest = false;
  bool reset_objects = false;
  bool load_avatar = false;    // from PanelEdits::avatar_path (empty: the default avatar)
  bool start_network = false;  // the session PanelEdits::network asks for
  bool leave_network = false;  // says bye and ends the session
};

struct PanelWidgets {
  struct Item {
    std::string_view label;
    float x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // window pixels
  };
  std::array<Item, 48> items{};
  std::size_t count = 0;
  const Item* find(std::string_view label) const;
};

// The panel fills `rect`; `widgets` (optional) receives where each widget was drawn.
PanelActions draw_panel(const ViewRect& rect, const PanelStatus& status, PanelEdits& edits,
                        PanelWidgets* widgets);

}  // namespace deixis::sim
