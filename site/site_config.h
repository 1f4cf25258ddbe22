#pragma once
// A site's configuration (docs/site-config.md): its name, its room's target map, where its user
// stands, where remote people's avatars stand (one spot each) and which avatar they wear, how the
// headless view is framed, and optionally a scripted virtual user (the demo's and tests' stand-in
// for a person in a headset). Read from versioned JSON; every error names the file and the path of
// the bad field, e.g. "sites/a.json: remote_avatar.floor[2]: not a finite number".

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/math/pose.h"
#include "core/script_step.h"
#include "core/target_map.h"
#include "mocap/bvh.h"
#include "mocap/recorded_person.h"

namespace deixis::site {

// A person's or avatar's place in a room: a point on the floor and a facing direction.
// yaw_degrees turns about +Y; 0 faces −Z, 180 faces +Z.
struct Placement {
  Vec3 floor = Vec3::Zero();
  float yaw_degrees = 0.0f;
  Pose T_world_floor() const;  // the placement as a pose (yaw only)
};

// One step of a virtual user's script (core/script_step.h, so that the capture performs it
// without depending on app/). Targets are ids of the target map (0: the other person), or a
// person by site name (script_person_target).

// A recorded person instead of a synthetic one (`virtual_user.bvh`, docs/bvh.md#driving-a-site):
// the file is read, its joints found and its body calibrated when the site file is parsed, so a
// bad recording is refused before anything connects.
struct RecordedUser {
  std::filesystem::path path;             // the .bvh, resolved against the site file's folder
  std::shared_ptr<const mocap::Bvh> bvh;  // the frames from `from` to `to` only
  mocap::LengthUnit unit = mocap::LengthUnit::kAuto;  // as resolved (never kAuto here)
  mocap::RecordingPlay play;
};

struct VirtualUser {
  std::string subject;  // a synthetic-capture subject, e.g. "173"; empty for a recording
  std::optional<RecordedUser> recording;  // exactly one of subject / recording
  std::uint64_t seed = 1;
  std::vector<ScriptStep> script;
  // The site names of the people the script looks or points at, in order of first mention:
  // people[k] is script_person_target(k) (core/script_step.h); at most one per avatar spot.
  std::vector<std::string> people;
};

struct Camera {
  Vec3 position = Vec3(0, 1.6f, 1.5f);
  Vec3 look_at = Vec3(0, 1.2f, -2.0f);
  float fov_degrees = 60.0f;
};

struct SiteConfig {
  static constexpr int kFormatVersion = 1;
  static constexpr std::size_t kMaxSpots = 64;  // remote people one site shows at once
  static constexpr float kMinSpotDistance =
      0.4f;            // m between two spots' floor points (errors say 0.4)
  std::string source;  // the file it was read from (errors about the site name it)
  std::string site;
  std::filesystem::path target_map_path;
  TargetMap target_map;
  Placement user;
  // Where remote people's avatars stand, in the order people take them (site/remote_people.h):
  // `remote_avatar.spots`, or the one spot of `remote_avatar`. Never empty.
  std::vector<Placement> spots;
  Placement remote_avatar;            // spots.front(): the direct two-site session's avatar
  std::filesystem::path avatar_path;  // what remote people's avatars wear (.glb)
  Camera camera;
  std::optional<VirtualUser> virtual_user;
};

// What stands behind an avatar on one of the site's spots: a target of the map, another spot (the
// person standing there) or the site's own user more than kBehindSpotDegrees to either side of
// where the spot faces (horizontally, from the spot's floor point). An avatar designating it
// turns its body away from the room (presence/body_turn.h; without the turn its pointing there
// ended far off, e.g. 94.5° for a target 96° to the side; docs/site-config.md). A layout check,
// not an error: the site still runs.
inline constexpr float kBehindSpotDegrees = 90.0f;
struct BehindSpot {
  std::size_t spot = 0;          // index into SiteConfig::spots
  std::string what;              // "TV (id 3)", "spot 2", "the site's user"
  float azimuth_degrees = 0.0f;  // from the spot's facing; positive to the avatar's left
};
std::vector<BehindSpot> behind_spots(const SiteConfig& site);
// One line for a log: the file, what, the angle, the spot (numbered from 1) and what it means.
std::string describe(const SiteConfig& site, const BehindSpot& b);

// Parses a site configuration; relative paths are resolved against `base_dir` and the target
// map is read. Throws deixis::Error naming `source` and the field.
SiteConfig parse_site_config(std::string_view json_text, std::string_view source,
                             const std::filesystem::path& base_dir);
SiteConfig read_site_config(const std::filesystem::path& path);

}  // namespace deixis::site
