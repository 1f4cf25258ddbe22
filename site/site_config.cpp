#include "site/site_config.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/error.h"
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

// One of `names` (e.g. "loop", "once") as its index; `fallback` when the field is absent.
std::size_t parse_choice(const JsonReader& r, const json& j, const std::string& path,
                         const char* key, std::initializer_list<std::string_view> names,
                         std::size_t fallback) {
  if (!j.contains(key)) {
    return fallback;
  }
  const std::string at = path + "." + key;
  const std::string value = r.string(j[key], at);
  std::string expected;
  std::size_t i = 0;
  for (const std::string_view name : names) {
    if (value == name) {
      return i;
    }
    expected += (i++ == 0 ? "" : " or ") + std::string(name);
  }
  r.fail(at, "expected " + expected + ", found '" + value + "'");
}

// The frames of `bvh` that `from` and `to` (s, optional) name, rounded to the nearest frame.
mocap::Bvh played_frames(const JsonReader& r, const json& j, const std::string& path,
                         const mocap::Bvh& bvh) {
  const double duration = static_cast<double>(bvh.frames() - 1) * bvh.frame_time;
  const double from = j.contains("from")
                          ? static_cast<double>(r.number_in(j["from"], path + ".from", 0, 1e6))
                          : 0.0;
  const double to =
      j.contains("to") ? static_cast<double>(r.number_in(j["to"], path + ".to", 0, 1e6)) : duration;
  char range[96];
  std::snprintf(range, sizeof range, "the recording runs from 0 to %.3f s", duration);
  if (from > duration) {
    r.fail(path + ".from", std::string("beyond the end: ") + range);
  }
  if (to > duration + 0.5 * bvh.frame_time) {
    r.fail(path + ".to", std::string("beyond the end: ") + range);
  }
  const auto first = static_cast<std::size_t>(std::lround(from / bvh.frame_time));
  const auto last =
      std::min(bvh.frames() - 1, static_cast<std::size_t>(std::lround(to / bvh.frame_time)));
  if (last <= first) {
    r.fail(path + ".to", "must come after from (at least one frame time later)");
  }
  return mocap::slice(bvh, first, last + 1);
}

// `virtual_user` with a `bvh` (docs/bvh.md#driving-a-site): the recording is read and checked
// here, its errors under virtual_user.bvh, so a site never starts with a recording it cannot play.
RecordedUser parse_recorded_user(const JsonReader& r, const json& j, const std::string& path,
                                 const std::filesystem::path& base_dir) {
  for (const char* key : {"script", "seed"}) {
    if (j.contains(key)) {
      r.fail(path + "." + key,
             "a recording (bvh) plays what was recorded: it takes no script or seed");
    }
  }
  RecordedUser user;
  user.path = base_dir / r.string(j["bvh"], path + ".bvh");
  mocap::Bvh bvh;
  try {
    bvh = mocap::read_bvh(user.path);
  } catch (const Error& e) {
    r.fail(path + ".bvh", e.what());
  }
  if (j.contains("unit")) {
    const std::string unit = r.string(j["unit"], path + ".unit");
    try {
      user.unit = mocap::parse_length_unit(unit);
    } catch (const Error& e) {
      r.fail(path + ".unit", e.what());
    }
  }
  if (user.unit == mocap::LengthUnit::kAuto) {
    try {
      user.unit = mocap::infer_unit(bvh);
    } catch (const Error& e) {
      r.fail(path + ".unit", e.what());
    }
  }
  user.play.metres_per_unit = mocap::metres_per_unit(user.unit);
  user.play.playback = parse_choice(r, j, path, "playback", {"loop", "once"}, 0) == 0
                           ? mocap::Playback::kLoop
                           : mocap::Playback::kOnce;
  user.play.deictic_hand = parse_choice(r, j, path, "deictic_hand", {"right", "left"}, 0) == 0
                               ? Hand::kRight
                               : Hand::kLeft;
  if (j.contains("body")) {
    const json& body = j["body"];
    const std::string at = path + ".body";
    if (!body.is_object()) {
      r.fail(at, "expected an object with height and arm_length (m)");
    }
    r.only_fields(body, at, {"height", "arm_length"});
    user.play.body = mocap::StatedBody{
        r.number_in(r.member(body, at, "height"), at + ".height", 1.0f, 2.5f),
        r.number_in(r.member(body, at, "arm_length"), at + ".arm_length", 0.3f, 1.2f)};
  }
  user.bvh = std::make_shared<const mocap::Bvh>(played_frames(r, j, path, bvh));
  // The joints and, unless stated, the body: what playing needs, checked now.
  try {
    mocap::SkeletonTracking tracking(*user.bvh, user.play.metres_per_unit);
    if (!user.play.body) {
      tracking.calibrate(user.play.deictic_hand);
    }
  } catch (const Error& e) {
    r.fail(path + ".bvh", std::string(e.what()) +
                              (user.play.body ? "" : " (or state the body: virtual_user.body)"));
  }
  return user;
}

VirtualUser parse_virtual_user(const JsonReader& r, const json& j, const std::string& path,
                               const SiteConfig& config, const std::filesystem::path& base_dir) {
  r.only_fields(j, path,
                {"subject", "seed", "script", "bvh", "playback", "unit", "from", "to", "body",
                 "deictic_hand"});
  VirtualUser user;
  if (j.contains("subject") == j.contains("bvh")) {
    r.fail(path, "give either a subject (the synthetic capture) or a bvh (a recording), not " +
                     std::string(j.contains("bvh") ? "both" : "neither"));
  }
  if (j.contains("bvh")) {
    user.recording = parse_recorded_user(r, j, path, base_dir);
    return user;
  }
  for (const char* key : {"playback", "unit", "from", "to", "body", "deictic_hand"}) {
    if (j.contains(key)) {
      r.fail(path + "." + key, "only a recording (bvh) takes it");
    }
  }
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
    config.virtual_user =
        parse_virtual_user(r, j["virtual_user"], "virtual_user", config, base_dir);
  }
  return config;
}

SiteConfig read_site_config(const std::filesystem::path& path) {
  return parse_site_config(JsonReader::read_file(path), path.string(), path.parent_path());
}

}  // namespace deixis::site
