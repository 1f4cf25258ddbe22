#include "eval/room_pairs.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>

#include "core/error.h"
#include "core/math/angles.h"

namespace deixis::eval {

namespace {

namespace fs = std::filesystem;
using ordered_json = nlohmann::ordered_json;

constexpr int kAttempts = 10'000;  // per object; the default rules need a handful

// Uniform in [lo, hi] from the generator's raw bits, so that a pair is the same on every
// standard library (std::uniform_real_distribution is not specified bit for bit).
class Draw {
 public:
  explicit Draw(std::uint64_t seed) : rng_(seed) {}
  float uniform(float lo, float hi) {
    const double u = static_cast<double>(rng_() >> 11) * 0x1.0p-53;
    return static_cast<float>(static_cast<double>(lo) + u * static_cast<double>(hi - lo));
  }
  bool coin() { return (rng_() >> 63) != 0; }
  std::uint64_t bits() { return rng_(); }

 private:
  std::mt19937_64 rng_;
};

void check_range(const char* name, float lo, float hi) {
  if (!(lo <= hi) || !std::isfinite(lo) || !std::isfinite(hi)) {
    throw Error(std::string("room rules: ") + name + ": minimum above maximum or not a number");
  }
}

void check(const RoomRules& r) {
  check_range("spot distance", r.spot_distance_min, r.spot_distance_max);
  check_range("point distance", r.point_distance_min, r.point_distance_max);
  check_range("point height", r.point_height_min, r.point_height_max);
  check_range("touch side", r.touch_side_min, r.touch_side_max);
  check_range("touch forward", r.touch_forward_min, r.touch_forward_max);
  check_range("touch height", r.touch_height_min, r.touch_height_max);
  if (r.spot_distance_min <= 2.0f * r.between_margin) {
    throw Error("room rules: the avatar's spot leaves no room between it and the user");
  }
}

float horizontal_gap(const Vec3& a, const Vec3& b) {
  return std::hypot(a.x() - b.x(), a.z() - b.z());
}

bool clear_of(const std::vector<RoomObject>& objects, const Vec3& p, float spot_distance,
              float min_separation) {
  if (horizontal_gap(p, Vec3::Zero()) < min_separation ||
      horizontal_gap(p, Vec3(0.0f, 0.0f, -spot_distance)) < min_separation) {
    return false;
  }
  for (const RoomObject& o : objects) {
    if ((o.position - p).norm() < min_separation) {
      return false;
    }
  }
  return true;
}

// A pointing target to the user's `side` (+1 right, −1 left): between the user and the avatar
// along the line of sight, at the rules' distance and height, clear of everything placed.
Vec3 pointing_position(const RoomRules& r, float spot_distance, float side,
                       const std::vector<RoomObject>& placed, Draw& draw) {
  const float min_cos = std::cos(r.point_azimuth_min_deg * kRadPerDeg);
  for (int attempt = 0; attempt < kAttempts; ++attempt) {
    const float distance = draw.uniform(r.point_distance_min, r.point_distance_max);
    // The farthest along the line of sight that keeps the azimuth at least its minimum.
    const float far = std::min(spot_distance - r.between_margin, distance * min_cos);
    if (far < r.between_margin) {
      continue;
    }
    const float along = draw.uniform(r.between_margin, far);
    const float across = std::sqrt(std::max(0.0f, distance * distance - along * along));
    const Vec3 p(side * across, draw.uniform(r.point_height_min, r.point_height_max), -along);
    if (clear_of(placed, p, spot_distance, r.min_separation)) {
      return p;
    }
  }
  throw Error("room rules: no pointing target fits after " + std::to_string(kAttempts) +
              " tries (distances, margins and separation leave no room)");
}

// Within reach on the deictic side of someone standing at `feet` facing `forward` (horizontal,
// unit); `right` is their right.
Vec3 touch_position(const RoomRules& r, const Vec3& feet, const Vec3& forward, const Vec3& right,
                    Hand hand, Draw& draw) {
  const float side = hand == Hand::kRight ? 1.0f : -1.0f;
  return feet + right * (side * draw.uniform(r.touch_side_min, r.touch_side_max)) +
         forward * draw.uniform(r.touch_forward_min, r.touch_forward_max) +
         Vec3(0.0f, draw.uniform(r.touch_height_min, r.touch_height_max), 0.0f);
}

GeneratedRoom generate_room(const RoomRules& r, const char* site, const ScriptedPerson& user,
                            const ScriptedPerson& remote, bool user_is_a, Draw& draw) {
  GeneratedRoom room;
  room.site = site;
  room.user = user;
  room.performance_seed = draw.bits() % 1'000'000;
  room.spot_distance = draw.uniform(r.spot_distance_min, r.spot_distance_max);
  // Both sides of the user get a pointing target at least once.
  const bool first_right = draw.coin();
  const bool second_right = draw.coin();
  const bool sides[3] = {first_right, second_right,
                         first_right == second_right ? !first_right : draw.coin()};
  for (int k = 0; k < 3; ++k) {
    const Vec3 p =
        pointing_position(r, room.spot_distance, sides[k] ? 1.0f : -1.0f, room.objects, draw);
    room.objects.push_back(
        {kPointTargets[k], "Target " + std::to_string(kPointTargets[k]), false, p});
  }
  // The user faces −Z (right is +X); the avatar on its spot faces +Z (right is −X).
  const Vec3 spot(0.0f, 0.0f, -room.spot_distance);
  const Vec3 by_user =
      touch_position(r, Vec3::Zero(), Vec3(0, 0, -1), Vec3(1, 0, 0), user.hand, draw);
  const Vec3 by_avatar = touch_position(r, spot, Vec3(0, 0, 1), Vec3(-1, 0, 0), remote.hand, draw);
  room.own_touch = user_is_a ? kTouchOfA : kTouchOfB;
  const TargetId remote_touch = user_is_a ? kTouchOfB : kTouchOfA;
  room.objects.push_back(
      {room.own_touch, "Touch " + std::to_string(room.own_touch), true, by_user});
  room.objects.push_back({remote_touch, "Touch " + std::to_string(remote_touch), true, by_avatar});
  return room;
}

ordered_json vec(const Vec3& v) {
  // Millimetres are enough, and keep the files readable.
  const auto mm = [](float x) { return std::round(static_cast<double>(x) * 1000.0) / 1000.0; };
  return ordered_json::array({mm(v.x()), mm(v.y()), mm(v.z())});
}

ordered_json target_map_json(const GeneratedRoom& room) {
  ordered_json objects = ordered_json::array();
  for (const RoomObject& o : room.objects) {
    const Vec3 size = o.touch ? Vec3(0.1f, 0.1f, 0.1f) : Vec3(0.3f, 0.3f, 0.3f);
    objects.push_back({{"id", o.id},
                       {"name", o.name},
                       {"kind", o.touch ? "box" : "sphere"},
                       {"position", vec(o.position)},
                       {"size", vec(size)}});
  }
  return {
      {"format", "deixis-target-map"}, {"version", 1}, {"site", room.site}, {"objects", objects}};
}

ordered_json script_json(const GeneratedRoom& room) {
  ordered_json steps = ordered_json::array();
  const auto step = [&](const char* action, TargetId target, double seconds) {
    ordered_json s = {{"action", action}};
    if (target != kNoTarget) {
      s["target"] = target;
    }
    s["seconds"] = seconds;
    steps.push_back(std::move(s));
  };
  step("look_at", 0, 1.5);  // the other person
  for (const TargetId t : kPointTargets) {
    step("point", t, 1.5);
    step("rest", kNoTarget, 1.0);
  }
  step("touch", room.own_touch, 1.5);
  step("rest", kNoTarget, 1.5);
  return steps;
}

ordered_json site_json(const GeneratedRoom& room, const fs::path& target_map,
                       const fs::path& avatar) {
  const double d = static_cast<double>(room.spot_distance);
  return {
      {"format", "deixis-site"},
      {"version", 1},
      {"site", room.site},
      {"target_map", target_map.filename().string()},
      {"user", {{"floor", {0, 0, 0}}, {"yaw_degrees", 0}}},
      {"remote_avatar", {{"avatar", avatar.string()}, {"floor", {0, 0, -d}}, {"yaw_degrees", 180}}},
      {"camera",
       {{"position", {1.8, 1.8, 1.2}}, {"look_at", {0, 1.1, -d / 2}}, {"fov_degrees", 60}}},
      {"virtual_user",
       {{"subject", room.user.subject},
        {"seed", room.performance_seed},
        {"script", script_json(room)}}}};
}

void write_json(const ordered_json& j, const fs::path& path) {
  std::ofstream out(path);
  out << j.dump(2) << '\n';
  if (!out) {
    throw Error(path.string() + ": cannot write");
  }
}

}  // namespace

RoomPair generate_room_pair(const RoomRules& rules, std::uint64_t seed, int index,
                            const ScriptedPerson& a, const ScriptedPerson& b) {
  check(rules);
  // One stream per pair, so that pair k is the same whatever the number of pairs asked for.
  Draw draw(seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(index) + 1);
  RoomPair pair;
  pair.index = index;
  pair.rooms[0] = generate_room(rules, "A", a, b, true, draw);
  pair.rooms[1] = generate_room(rules, "B", b, a, false, draw);
  return pair;
}

void write_room_pair(const RoomPair& pair, const fs::path& avatar, const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    throw Error(dir.string() + ": cannot create the directory (" + ec.message() + ")");
  }
  for (const GeneratedRoom& room : pair.rooms) {
    const std::string lower = room.site == "A" ? "a" : "b";
    const fs::path map = dir / ("room-" + lower + ".json");
    write_json(target_map_json(room), map);
    write_json(site_json(room, map, avatar), dir / (lower + ".json"));
  }
}

TargetGeometry geometry_from_avatar(const GeneratedRoom& room, const Vec3& target) {
  const Vec3 v = target - Vec3(0.0f, kAvatarShoulderHeight, -room.spot_distance);
  const float horizontal = std::hypot(v.x(), v.z());
  // The avatar faces +Z, its right is −X.
  return {horizontal, std::atan2(v.y(), horizontal) * kDegPerRad,
          std::atan2(-v.x(), v.z()) * kDegPerRad};
}

}  // namespace deixis::eval
