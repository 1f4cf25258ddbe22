#pragma once
// The flags of `deixis sim` as app/main.cpp parses them; the simulator's network form starts from
// them (sim/sim_network_form.h).

#include <cstdint>
#include <filesystem>
#include <string>

namespace deixis::sim {

// `deixis sim`: the desktop simulator (docs/sim.md). A window with the local room (site A) and
// its virtual user, driven by mouse and keys or by the site's script, and the remote room (site
// B) with the avatar translated from the user's tracking; B's objects are dragged with the mouse.
// Both sites run in this process; with `network` the simulator is site A of a real session
// (host or join, as `deixis host`/`join`/`xr`), or a member of a room on a relay: the user
// streams, the other sites' people come in as avatars in room A. Exit 0 when closed or done, 1 when
// the window, GL or the network session fails (refused, nobody came), 2 for bad flags or files.
struct SimOptions {
  std::filesystem::path site_a;
  std::filesystem::path site_b;
  std::filesystem::path weights_dir;
  // The avatar the user chose (.glb/.gltf): their avatar in B wears it, and a session offers it to
  // the sites met (they show the user wearing it); empty: site B's, and nothing offered.
  std::filesystem::path avatar;
  std::filesystem::path remote_avatar;  // what every other person wears in A; empty: their choice
  bool script = false;                  // the user performs site A's virtual_user script
  std::filesystem::path input;       // scripted events (JSON); fixed steps until a session starts
  bool fixed_step = false;           // every frame advances the simulator by one 30 Hz tick
  std::uint64_t frames = 0;          // quit after this many frames (0: no limit)
  double seconds = 0.0;              // quit after this much simulator time (0: no limit)
  std::filesystem::path screenshot;  // the last frame's window contents (PNG)
  std::filesystem::path report;      // JSON: B's objects, the avatar's eye and fingertip, timings
  int width = 1280;
  int height = 720;
  bool network = false;  // host or join another site, or enter a room
  bool host = true;
  std::string address = "127.0.0.1";  // host: where to listen (--bind); join: the host or relay
  // A room on the relay at address:port (--connect HOST:PORT --room NAME): every other member is
  // an avatar on site A's spots (docs/sim.md, "In a room").
  std::string room;
  std::uint16_t port = 7350;  // host: 0 picks a free one (printed as "port N")
  std::string passphrase;
  double wait = 30.0;  // s for the other site to come
};

// Runs the simulator (sim/sim_run.cpp): the window, its views, the ticks. Returns the exit code.
int run_sim(const SimOptions& options);

}  // namespace deixis::sim
