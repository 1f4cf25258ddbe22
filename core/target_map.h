#pragma once
// A site's target map: the named objects people look at, point at and touch, with their
// positions and sizes in that site's room. Objects correspond across sites by id.
// The file format is documented in docs/target-map.md (versioned JSON); every error names the
// file and the path of the bad field, e.g. "rooms/b.json: objects[3].position[1]: not a finite
// number".

#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/math/pose.h"
#include "core/tracking.h"

namespace deixis {

// Id 0 is reserved for "the other person": in each room it is wherever that person's head (or
// avatar's head) currently is, so it is never listed in a file.
inline constexpr TargetId kPartnerTarget = 0;

// What a person designates when nothing is designated (kNoTarget, e.g. a headset user in a room
// before their eyes rest on anything): a point this far along their head's forward. The point is
// defined by the person's own tracking, so it never travels on the wire (docs/protocol.md §4.8):
// the sender's selection and every room's translator compute it alike, and the avatar looks and
// points where the person's head faces, as copying the pose would (docs/decisions.md 72).
inline constexpr float kNothingAheadM = 2.0f;
inline Vec3 nothing_designated_point(const Pose& T_world_head) {
  return transform_point(T_world_head, Vec3(0, 0, -kNothingAheadM));
}

// A person of a room of several people (docs/target-map.md, "People"): the number the relay gives
// each member (1–254, net::MemberId), seen from a site. People are targets too, above every
// object id: person_target(Y) is, in each room, wherever Y's head is there (Y's avatar's head, or
// the room's own user's when Y is that user), so a gaze or point at Y lands on Y in every room.
using PersonId = std::uint8_t;
inline constexpr PersonId kNoPerson = 0;
inline constexpr PersonId kMaxPersonId = 254;
inline constexpr TargetId kMaxObjectTarget = 1'000'000;
inline constexpr TargetId kPersonTargetBase = kMaxObjectTarget;
constexpr TargetId person_target(PersonId p) {
  return kPersonTargetBase + static_cast<TargetId>(p);  // 1,000,001–1,000,254
}
constexpr bool is_person_target(TargetId id) {
  return id > kPersonTargetBase && id <= kPersonTargetBase + kMaxPersonId;
}
// The person a person target designates; kNoPerson for any other id.
constexpr PersonId target_person(TargetId id) {
  return is_person_target(id) ? static_cast<PersonId>(id - kPersonTargetBase) : kNoPerson;
}

// A person of a room and where their head is in this room: a remote person's avatar's head, or
// this room's own user's (the translator's LocalTargets and the target selection read these).
struct PersonTarget {
  PersonId id = kNoPerson;
  Vec3 head = Vec3::Zero();
};
inline const PersonTarget* find_person(std::span<const PersonTarget> people, PersonId id) {
  for (const PersonTarget& p : people) {
    if (p.id == id) {
      return &p;
    }
  }
  return nullptr;
}

enum class TargetKind { kSphere, kBox, kScreen };
std::string_view kind_name(TargetKind kind);

struct TargetObject {
  TargetId id = kNoTarget;
  std::string name;
  TargetKind kind = TargetKind::kSphere;
  Vec3 position = Vec3::Zero();  // centre, world frame of the site (m)
  Vec3 size = Vec3::Zero();      // extent along x, y, z (m); a sphere's diameter in all three
};

struct TargetMap {
  static constexpr int kFormatVersion = 1;
  std::string site;  // e.g. "A"
  std::vector<TargetObject> objects;

  const TargetObject* find(TargetId id) const;
};

// Parses a target map from JSON text; `source` names it in errors. Throws deixis::Error.
TargetMap parse_target_map(std::string_view json_text, std::string_view source);
TargetMap read_target_map(const std::filesystem::path& path);
std::string to_json(const TargetMap& map);  // what parse_target_map reads back
// Writes to_json(map) atomically (core/io/atomic_file.h). Throws deixis::Error naming the file.
void write_target_map(const TargetMap& map, const std::filesystem::path& path);

// The nearest point of an object's surface to `p` (a sphere's surface, or a box's), used to
// place a touch on the object rather than at its centre.
Vec3 closest_surface_point(const TargetObject& object, const Vec3& p);

}  // namespace deixis
