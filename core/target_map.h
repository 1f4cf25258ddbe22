#pragma once
// A site's target map: the named objects people look at, point at and touch, with their
// positions and sizes in that site's room. Objects correspond across sites by id.
// The file format is documented in docs/target-map.md (versioned JSON); every error names the
// file and the path of the bad field, e.g. "rooms/b.json: objects[3].position[1]: not a finite
// number".

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/math/pose.h"
#include "core/tracking.h"

namespace deixis {

// Id 0 is reserved for "the other person": in each room it is wherever that person's head (or
// avatar's head) currently is, so it is never listed in a file.
inline constexpr TargetId kPartnerTarget = 0;

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

// The nearest point of an object's surface to `p` (a sphere's surface, or a box's), used to
// place a touch on the object rather than at its centre.
Vec3 closest_surface_point(const TargetObject& object, const Vec3& p);

}  // namespace deixis
