#include "site/site_config.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/io/json_reader.h"

namespace deixis::site {

namespace {

using json = JsonReader::json;

constexpr struct {
  ScriptStep::Action action;
  std::string_view name;
  bool needs_target;
} kActions[] = {{ScriptStep::Action::kLookAt, "look_at", true},
                {ScriptStep::Action::kPoint, "point", true},
                {ScriptStep::Action::kTouch, "touch", true},
                {ScriptStep::Action::kExplain, "explain", false},
                {ScriptStep::Action::kRest, "rest", false}};

Placement parse_placement(const JsonReader& r, const json& j, const std::string& path) {
  r.only_fields(j, path, {"floor", "yaw_degrees", "avatar"});
  Placement p;
  p.floor = r.vec3(r.member(j, path, "floor"), path + ".floor");
  p.yaw_degrees = r.number_in(r.member(j, path, "yaw_degrees"), path + ".yaw_degrees", -360, 360);
  return p;
}

Camera parse_camera(const JsonReader& r, const json& j, const std::string& path) {
  r.only_fields(j, path, {"position", "look_at", "fov_degrees"});
  Camera c;
  c.position = r.vec3(r.member(j, path, "position"), path + ".position");
  c.look_at = r.vec3(r.member(j, path, "look_at"), path + ".look_at");
  if ((c.look_at - c.position).norm() < 1e-3f) {
    r.fail(path + ".look_at", "must differ from the position");
  }
  c.fov_degrees = r.number_in(r.member(j, path, "fov_degrees"), path + ".fov_degrees", 10, 150);
  return c;
}

// A step's person (`"person": "B"`): the k-th distinct site name of the script, k in `people`.
TargetId parse_person(const JsonReader& r, const json& j, const std::string& path,
                      const SiteConfig& config, std::vector<std::string>& people) {
  const std::string name = r.name(j, path);
  if (name == config.site) {
    r.fail(path, "'" + name + "' is this site: its user cannot look or point at themselves");
  }
  auto at = std::find(people.begin(), people.end(), name);
  if (at == people.end()) {
    if (people.size() == config.spots.size()) {
      r.fail(path, "the script names more people than remote_avatar has spots (" +
                       std::to_string(config.spots.size()) + ")");
    }
    at = people.insert(people.end(), name);
  }
  return script_person_target(static_cast<std::size_t>(at - people.begin()));
}

ScriptStep parse_step(const JsonReader& r, const json& j, const std::string& path,
                      const SiteConfig& config, std::vector<std::string>& people) {
  const TargetMap& map = config.target_map;
  r.only_fields(j, path, {"action", "target", "person", "seconds"});
  ScriptStep step;
  const std::string name = r.string(r.member(j, path, "action"), path + ".action");
  bool needs_target = false;
  bool known = false;
  for (const auto& a : kActions) {
    if (a.name == name) {
      step.action = a.action;
      needs_target = a.needs_target;
      known = true;
    }
  }
  if (!known) {
    r.fail(path + ".action",
           "unknown action '" + name + "' (expected look_at, point, touch, explain or rest)");
  }
  const bool at_person =
      step.action == ScriptStep::Action::kLookAt || step.action == ScriptStep::Action::kPoint;
  if (j.contains("person")) {
    if (!at_person) {
      r.fail(path + ".person", "'" + name + "' takes no person (look_at and point do)");
    }
    if (j.contains("target")) {
      r.fail(path + ".person", "give either a target or a person, not both");
    }
    step.person = r.name(j["person"], path + ".person");
    step.target = parse_person(r, j["person"], path + ".person", config, people);
  } else if (needs_target) {
    step.target = static_cast<TargetId>(
        r.integer_in(r.member(j, path, "target"), path + ".target", 0, 1'000'000));
    if (step.target != kPartnerTarget && map.find(step.target) == nullptr) {
      r.fail(path + ".target", "no object with id " + std::to_string(step.target) +
                                   " in the target map (0 is the other person)");
    }
  } else if (j.contains("target")) {
    r.fail(path + ".target", "'" + name + "' takes no target");
  }
  if (j.contains("seconds")) {
    step.seconds = r.number_in(j["seconds"], path + ".seconds", 0, 600);
  }
  return step;
}

VirtualUser parse_virtual_user(const JsonReader& r, const json& j, const std::string& path,
                               const SiteConfig& config) {
  r.only_fields(j, path, {"subject", "seed", "script"});
  VirtualUser user;
  user.subject = r.string(r.member(j, path, "subject"), path + ".subject");
  if (j.contains("seed")) {
    user.seed = static_cast<std::uint64_t>(
        r.integer_in(j["seed"], path + ".seed", 0, std::int64_t{1} << 62));
  }
  const json& script = r.member(j, path, "script");
  if (!script.is_array() || script.empty() || script.size() > 1000) {
    r.fail(path + ".script", "expected an array of 1 to 1000 steps");
  }
  for (std::size_t i = 0; i < script.size(); ++i) {
    user.script.push_back(
        parse_step(r, script[i], path + ".script[" + std::to_string(i) + "]", config, user.people));
  }
  return user;
}

// `remote_avatar`: the avatar remote people wear and where they stand, either one spot (`floor`,
// `yaw_degrees`) or a list of them (`spots`), docs/site-config.md.
void parse_remote_avatars(const JsonReader& r, const json& j, const std::filesystem::path& base_dir,
                          SiteConfig& config) {
  const std::string path = "remote_avatar";
  const json& avatar = r.member(j, "", "remote_avatar");
  config.avatar_path = base_dir / r.string(r.member(avatar, path, "avatar"), path + ".avatar");
  if (!avatar.contains("spots")) {
    config.spots = {parse_placement(r, avatar, path)};
  } else {
    r.only_fields(avatar, path, {"avatar", "spots"});
    const json& spots = avatar["spots"];
    if (!spots.is_array() || spots.empty() || spots.size() > SiteConfig::kMaxSpots) {
      r.fail(path + ".spots",
             "expected an array of 1 to " + std::to_string(SiteConfig::kMaxSpots) + " spots");
    }
    for (std::size_t i = 0; i < spots.size(); ++i) {
      const std::string at = path + ".spots[" + std::to_string(i) + "]";
      if (!spots[i].is_object()) {
        r.fail(at, "expected an object");
      }
      if (spots[i].contains("avatar")) {
        r.fail(at + ".avatar", "every spot wears remote_avatar.avatar");
      }
      config.spots.push_back(parse_placement(r, spots[i], at));
    }
  }
  // Two avatars on one spot would stand inside each other.
  for (std::size_t i = 0; i < config.spots.size(); ++i) {
    for (std::size_t k = 0; k < i; ++k) {
      const float d = (config.spots[i].floor - config.spots[k].floor).norm();
      if (d < SiteConfig::kMinSpotDistance) {
        r.fail("remote_avatar.spots[" + std::to_string(i) + "].floor",
               "less than 0.4 m from spots[" + std::to_string(k) + "]: the avatars would overlap");
      }
    }
  }
  config.remote_avatar = config.spots.front();
}

}  // namespace

Pose Placement::T_world_floor() const {
  return {yaw_rotation(yaw_degrees * std::numbers::pi_v<float> / 180.0f), floor};
}

std::vector<BehindSpot> behind_spots(const SiteConfig& site) {
  std::vector<BehindSpot> out;
  for (std::size_t i = 0; i < site.spots.size(); ++i) {
    const Placement& spot = site.spots[i];
    const float yaw = spot.yaw_degrees * std::numbers::pi_v<float> / 180.0f;
    const float fx = -std::sin(yaw), fz = -std::cos(yaw);  // the spot's facing (yaw 0: −Z)
    const auto check = [&](const Vec3& at, std::string what) {
      const float dx = at.x() - spot.floor.x(), dz = at.z() - spot.floor.z();
      if (std::hypot(dx, dz) < 1e-3f) {
        return;
      }
      // The signed angle about +Y from the facing to the target: positive toward the avatar's
      // left (+Y turns −Z toward −X).
      const float azimuth =
          std::atan2(fz * dx - fx * dz, fx * dx + fz * dz) * 180.0f / std::numbers::pi_v<float>;
      if (std::abs(azimuth) > kBehindSpotDegrees) {
        out.push_back({i, std::move(what), azimuth});
      }
    };
    for (const TargetObject& o : site.target_map.objects) {
      check(o.position, o.name + " (id " + std::to_string(o.id) + ")");
    }
    for (std::size_t k = 0; k < site.spots.size(); ++k) {
      if (k != i) {
        check(site.spots[k].floor, "spot " + std::to_string(k + 1));
      }
    }
    check(site.user.floor, "the site's user");
  }
  return out;
}

std::string describe(const SiteConfig& site, const BehindSpot& b) {
  char angle[32];
  std::snprintf(angle, sizeof angle, "%.0f", static_cast<double>(std::abs(b.azimuth_degrees)));
  return site.source + ": " + b.what + " stands " + angle + "° to the " +
         (b.azimuth_degrees > 0.0f ? "left" : "right") + " of where avatar spot " +
         std::to_string(b.spot + 1) +
         " faces: an avatar there turns its body away from the room to look or point at it "
         "(docs/site-config.md)";
}

SiteConfig parse_site_config(std::string_view json_text, std::string_view source,
                             const std::filesystem::path& base_dir) {
  const JsonReader r(source);
  const json j = r.parse_object(json_text);
  r.only_fields(j, "",
                {"format", "version", "site", "target_map", "user", "remote_avatar", "camera",
                 "virtual_user"});
  const std::string format = r.string(r.member(j, "", "format"), "format");
  if (format != "deixis-site") {
    r.fail("format", "expected \"deixis-site\", found \"" + format + "\"");
  }
  if (r.integer_in(r.member(j, "", "version"), "version", 0, 1000) != SiteConfig::kFormatVersion) {
    r.fail("version", "this Deixis reads version " + std::to_string(SiteConfig::kFormatVersion));
  }
  SiteConfig config;
  config.source = std::string(source);
  config.site = r.name(r.member(j, "", "site"), "site");  // the hello carries it
  config.target_map_path = base_dir / r.string(r.member(j, "", "target_map"), "target_map");
  try {
    config.target_map = read_target_map(config.target_map_path);
  } catch (const Error& e) {
    r.fail("target_map", e.what());
  }
  config.user = parse_placement(r, r.member(j, "", "user"), "user");
  parse_remote_avatars(r, j, base_dir, config);
  if (j.contains("camera")) {
    config.camera = parse_camera(r, j["camera"], "camera");
  }
  if (j.contains("virtual_user")) {
    config.virtual_user = parse_virtual_user(r, j["virtual_user"], "virtual_user", config);
  }
  return config;
}

SiteConfig read_site_config(const std::filesystem::path& path) {
  return parse_site_config(JsonReader::read_file(path), path.string(), path.parent_path());
}

}  // namespace deixis::site
