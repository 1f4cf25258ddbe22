#pragma once
// Room pairs nobody designed, for the live evaluation (`deixis eval --live-rooms`,
// docs/live-rooms.md): two rooms furnished at random under stated rules, each with a scripted user
// who looks at the other person, points at three objects and touches one, and the other person's
// avatar facing them. The same object (by id) stands elsewhere in each room, as the method
// expects. Generation is pure: the same rules, seed and index give the same pair, bit for bit.
//
// The people are plain data here (a subject's name, hand and size), so that this library stays
// free of the synthetic capture (eval/CMakeLists.txt); the caller looks the subjects up.

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "core/tracking.h"

namespace deixis::eval {

// Every range a generated room keeps to (metres, degrees; docs/live-rooms.md lists them). Room
// frame: the user stands at the origin facing −Z; the avatar's spot is on the user's line of sight,
// facing the user.
struct RoomRules {
  float spot_distance_min = 1.8f, spot_distance_max = 2.6f;  // user to avatar spot
  // Pointing targets: horizontal distance from the user, height above the floor, and between
  // the user and the avatar along the line of sight (at least `between_margin` from either).
  float point_distance_min = 1.2f, point_distance_max = 3.4f;
  float point_height_min = 0.9f, point_height_max = 2.2f;
  float between_margin = 0.3f;
  float point_azimuth_min_deg = 25.0f;  // from the user's forward: targets are to the sides
  float min_separation = 0.5f;          // between any two objects, and from either person's feet
  // Touch targets, relative to the person (or avatar) who touches them, on their deictic side:
  // sideways, forward, and height above the floor.
  float touch_side_min = 0.12f, touch_side_max = 0.32f;
  float touch_forward_min = 0.32f, touch_forward_max = 0.45f;
  float touch_height_min = 0.95f, touch_height_max = 1.15f;
};

// Who performs a room's script: a synthetic-capture subject (capture/subject.h) by name, with
// the hand they point and touch with.
struct ScriptedPerson {
  std::string subject;
  Hand hand = Hand::kRight;
};

// One object of a generated room (docs/target-map.md).
struct RoomObject {
  TargetId id = kNoTarget;
  std::string name;
  bool touch = false;  // a small box touched, else a sphere pointed at
  Vec3 position = Vec3::Zero();
};

// One room of a pair: its site name, where the user and the avatar stand, its objects and the
// user's script. The user touches `own_touch`; the remote person's avatar touches the other.
struct GeneratedRoom {
  std::string site;
  float spot_distance = 2.2f;  // the avatar's spot is at (0, 0, −spot_distance), facing +Z
  std::vector<RoomObject> objects;
  ScriptedPerson user;
  std::uint64_t performance_seed = 0;
  TargetId own_touch = kNoTarget;
};

struct RoomPair {
  int index = 0;
  std::array<GeneratedRoom, 2> rooms;  // A (the host), B (the joiner)
};

// Targets 1–3 are pointed at, 4 is touched by A's user (near A's user in room A, near the avatar
// in room B), 5 by B's user. Throws deixis::Error if the rules leave no room (e.g. a minimum above
// its maximum), naming the rule.
inline constexpr TargetId kPointTargets[] = {1, 2, 3};
inline constexpr TargetId kTouchOfA = 4;
inline constexpr TargetId kTouchOfB = 5;
RoomPair generate_room_pair(const RoomRules& rules, std::uint64_t seed, int index,
                            const ScriptedPerson& a, const ScriptedPerson& b);

// Writes `dir`/a.json and `dir`/b.json (sites, docs/site-config.md) with their target maps
// (`dir`/room-a.json, room-b.json), the avatar `avatar` (a .glb path) on each spot. Throws
// deixis::Error naming a file that cannot be written.
void write_room_pair(const RoomPair& pair, const std::filesystem::path& avatar,
                     const std::filesystem::path& dir);

// Where a target stands as seen from the avatar's spot of `room` (for the per-geometry tables):
// horizontal distance, elevation above the avatar's shoulder height (kAvatarShoulderHeight) and
// azimuth from where the avatar faces (positive to the avatar's right).
struct TargetGeometry {
  float distance = 0.0f;  // m
  float elevation_deg = 0.0f;
  float azimuth_deg = 0.0f;
};
inline constexpr float kAvatarShoulderHeight = 1.4f;  // m
TargetGeometry geometry_from_avatar(const GeneratedRoom& room, const Vec3& target);

}  // namespace deixis::eval
