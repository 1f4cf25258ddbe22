#pragma once
// What a site run measured (docs/demo.md, "session.json"): ticks, network counters, translation
// and render times, its own user's completion states and the remote avatar's pointing and
// touching errors at the remote person's completion states next to the copy-paste baseline.
// Written as JSON and printed as a short table.

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "core/script_step.h"
#include "eval/deictic_observer.h"
#include "net/enet_link.h"
#include "net/session.h"

namespace deixis::site {

// What a site reports about one remote site's person over a run (session.json `people`):
// counters summed over their stays (a person who leaves and comes back, with a fresh id, is the
// same site) and the completion states observed of them (eval/deictic_observer.h).
// Where a remote person's avatar looked when the person's eyes had settled on a target (the last
// frame of a hold, site/remote_people.cpp): the angle between the avatar's gaze and the ray from
// its head to this room's copy of the target (an object, the other person, a person of the room),
// for the avatar's eyes as posed (their line of sight after gaze settling, presence/gaze_settle.h,
// and IK, within the eyes' range) and for the networks' own gaze.
struct GazeSample {
  TargetId target = kNoTarget;
  double error_deg = 0.0;
  double network_error_deg = 0.0;
};

// What a remote person's avatar was at the end of their last stay (session.json
// people[].avatar; docs/avatars.md): "default" (the site's own), "chosen" (their file) or
// "override" (this site's --remote-avatar); the file's hash (64 hex digits, empty for the
// default) and the rig's joint count.
struct PersonAvatarRecord {
  std::string source = "default";
  std::string hash;
  int joints = 0;
};

struct PersonRecord {
  std::string site;
  PersonAvatarRecord avatar;
  std::uint64_t frames_played = 0;
  std::uint64_t frames_missed = 0;
  std::uint64_t visible_ticks = 0;
  std::uint64_t stays = 0;  // how many times they arrived
  // The body their last hello described (a headset user recalibrates with a button: xr).
  double height_m = 0.0;
  double arm_length_m = 0.0;
  std::vector<eval::DeicticSample> completions;
  std::uint64_t completions_dropped = 0;
  std::vector<GazeSample> gazes;
};

struct SiteRecord {
  std::string site;
  std::string role;       // "host" or "join"
  std::string peer_site;  // a room: the people's sites, comma-separated
  bool room = false;      // a room of several people (their completions are per person)
  double seconds = 0.0;   // wall time of the 30 Hz loop
  std::uint64_t ticks = 0;
  std::uint64_t late_ticks = 0;        // started more than one tick after they were due
  std::uint64_t visible_ticks = 0;     // the remote avatar was shown
  std::vector<double> translation_ms;  // per remote frame: translator + whole-avatar IK
  std::vector<double> render_ms;       // per tick: both views drawn and read back
  std::vector<StepTiming> own_steps;
  std::vector<eval::DeicticSample> remote_completions;
  std::uint64_t completions_dropped = 0;
  // Network, at the end of the run.
  net::SessionStats net;
  net::JitterStats jitter;
  std::uint64_t rejected = 0;       // packets dropped by the decoder or the session
  net::StrangerStats strangers;     // host: what became of connections it did not serve
  std::uint64_t auth_failures = 0;  // proofs that did not verify
  bool sealed = false;
  net::EnetLink::Traffic traffic;
  std::string video;  // file name in the output directory, or empty
  // One entry per remote site's person; a direct session's is its one other person.
  std::vector<PersonRecord> people;
};

// The p-th percentile (0–100) by nearest rank; NaN for no values.
double percentile(std::vector<double> values, double p);

void write_site_report(const SiteRecord& record, const std::filesystem::path& path);
void print_site_summary(const SiteRecord& record, std::FILE* out);

}  // namespace deixis::site
