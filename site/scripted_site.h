#pragma once
// The scripted site of `deixis host` and `deixis join` (docs/demo.md): a site whose user is a
// scripted person (the capture's virtual user, performed by app/site_command.cpp and handed over
// as plain data), driven at 30 Hz on the steady clock through the one site runtime
// (site/site_peer.h). Every tick sends the user's frame, plays the remote person into their
// avatar, solves the user's own copy and draws both headless views; meanwhile it measures the
// remote person at their completion states (eval/deictic_observer.h) for session.json.

#include <array>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "avatar/avatar_loader.h"
#include "core/script_step.h"
#include "core/tracking.h"
#include "ik/avatar_solver.h"
#include "site/avatar_cache.h"
#include "site/moe_weights.h"
#include "site/site_config.h"
#include "site/site_report.h"

namespace deixis::site {

// `deixis host` and `deixis join`: one site (docs/demo.md). The site's virtual user performs its
// script; tracking goes to the other site and the other's avatar is translated into this room
// and rendered headlessly. Exit 0 after the run, 1 when the session fails (refused, nobody came),
// 2 for bad files.
struct SiteRunOptions {
  bool host = true;
  std::filesystem::path site;
  std::string address = "127.0.0.1";  // host: where to listen (--bind); join: the host
  std::uint16_t port = 7350;          // host: 0 picks a free one (printed as "port N")
  std::string passphrase;
  // A room on a relay (address and port are then the relay's): many people, not one host.
  std::string room;
  double drop_tracking = 0.0;  // rehearsing a bad link: this share of outgoing frames not sent
  double seconds = 0.0;        // 0: as long as the virtual user's script
  double wait = 30.0;          // s to wait for the other site
  std::filesystem::path out_dir;
  std::filesystem::path weights_dir;  // holds right/ and left/ with the MoE weights
  // The avatar this site's user chose (docs/avatars.md, "A person's own avatar"): offered to the
  // other sites by its hash. Empty: none, the others show the person in their own default.
  std::filesystem::path avatar;
  // Every remote person wears this avatar here, whatever they chose (a local override). Empty:
  // people wear what they chose, or the site's own avatar until theirs arrived.
  std::filesystem::path remote_avatar;
  int view_width = 640;
  int view_height = 360;
  bool video = true;
};

// What a site reads and computes before it connects. Any error here is a bad input.
struct SiteAssets {
  SiteConfig site;
  avatar::Avatar avatar;
  ik::AvatarSolver solver;
  std::array<MoeNetworks, 2> networks;  // by the remote person's deictic hand
  Pose T_world_user_origin;             // the user's copy stands where the user does
  Pose T_world_remote_origin;           // the remote person's avatar
  // The user's chosen avatar file (--avatar), offered to the others, and what every remote
  // person wears here (--remote-avatar); null: none, and what they chose.
  WornAvatars worn;
};
// Throws deixis::Error naming the file for a bad avatar or weights.
SiteAssets load_site_assets(SiteConfig site, const std::filesystem::path& weights_dir);
// Loads the avatars SiteRunOptions names (--avatar, --remote-avatar) into `assets`, before
// anything connects; throws deixis::Error naming a file that is no usable avatar.
void load_run_avatars(SiteAssets& assets, const SiteRunOptions& options);

// The site's scripted user, as performed: 30 Hz frames (frames[i].time = i / 30), the deictic
// progression per frame (rays are drawn above 0.5), when each step completed, and the body.
struct ScriptedUser {
  BodyCalibration body;
  std::vector<TrackingFrame> frames;
  std::vector<float> deictic;
  std::vector<StepTiming> steps;
};

// Connects (host: prints "port N" first), runs the 30 Hz loop for `options.seconds` (0: as long
// as the script), writes session.json and the views' video into `options.out_dir` and prints the
// summary. Throws deixis::Error when the session fails (refused, nobody came).
SiteRecord run_scripted_site(const SiteRunOptions& options, const SiteAssets& assets,
                             const ScriptedUser& user);

}  // namespace deixis::site
