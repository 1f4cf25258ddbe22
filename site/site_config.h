#pragma once
// A site's configuration (docs/site-config.md): its name, its room's target map, where its user
// stands, where the remote person's avatar stands and which avatar it wears, how the headless
// view is framed, and optionally a scripted virtual user (the demo's and tests' stand-in for a
// person in a headset). Read from versioned JSON; every error names the file and the path of the
// bad field, e.g. "sites/a.json: remote_avatar.floor[2]: not a finite number".

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/math/pose.h"
#include "core/script_step.h"
#include "core/target_map.h"

namespace deixis::site {

// A person's or avatar's place in a room: a point on the floor and a facing direction.
// yaw_degrees turns about +Y; 0 faces −Z, 180 faces +Z.
struct Placement {
  Vec3 floor = Vec3::Zero();
  float yaw_degrees = 0.0f;
  Pose T_world_floor() const;  // the placement as a pose (yaw only)
};

// One step of a virtual user's script (core/script_step.h, so that the capture performs it
// without depending on app/). Targets are ids of the target map (0: the other person).

struct VirtualUser {
  std::string subject;  // a synthetic-capture subject, e.g. "173"
  std::uint64_t seed = 1;
  std::vector<ScriptStep> script;
};

struct Camera {
  Vec3 position = Vec3(0, 1.6f, 1.5f);
  Vec3 look_at = Vec3(0, 1.2f, -2.0f);
  float fov_degrees = 60.0f;
};

struct SiteConfig {
  static constexpr int kFormatVersion = 1;
  std::string site;
  std::filesystem::path target_map_path;
  TargetMap target_map;
  Placement user;
  Placement remote_avatar;
  std::filesystem::path avatar_path;  // the remote person's avatar (.glb)
  Camera camera;
  std::optional<VirtualUser> virtual_user;
};

// Parses a site configuration; relative paths are resolved against `base_dir` and the target
// map is read. Throws deixis::Error naming `source` and the field.
SiteConfig parse_site_config(std::string_view json_text, std::string_view source,
                             const std::filesystem::path& base_dir);
SiteConfig read_site_config(const std::filesystem::path& path);

}  // namespace deixis::site
