// A room's targets through the C API: a target map (read from a file or built by calls), the
// other person's head, and the heads of a room's people.
#include <algorithm>
#include <cmath>

#include "api/boundary.h"
#include "api/conversions.h"
#include "api/handles.h"

using namespace deixis;
using namespace deixis::api;

namespace {

TargetKind kind_from_c(std::int32_t kind) {
  switch (kind) {
    case DEIXIS_TARGET_SPHERE:
      return TargetKind::kSphere;
    case DEIXIS_TARGET_BOX:
      return TargetKind::kBox;
    case DEIXIS_TARGET_SCREEN:
      return TargetKind::kScreen;
    default:
      throw CallError(
          DEIXIS_ERROR_INVALID_ARGUMENT,
          "target kind " + std::to_string(kind) + " is not DEIXIS_TARGET_SPHERE, _BOX or _SCREEN");
  }
}

std::int32_t kind_to_c(TargetKind kind) {
  switch (kind) {
    case TargetKind::kSphere:
      return DEIXIS_TARGET_SPHERE;
    case TargetKind::kBox:
      return DEIXIS_TARGET_BOX;
    case TargetKind::kScreen:
      return DEIXIS_TARGET_SCREEN;
  }
  return DEIXIS_TARGET_SPHERE;
}

bool finite(const deixis_vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

void require_person(std::uint8_t person) {
  require(person >= 1 && person <= kMaxPersonId, "a person id is 1..254");
}

}  // namespace

extern "C" {

deixis_status deixis_room_create(uint32_t abi_version, const char* target_map_path,
                                 deixis_room** out, deixis_error* error) {
  return create_guarded(error, DEIXIS_ERROR_FILE, [&] {
    check_abi(abi_version);
    require(out != nullptr, "deixis_room_create: out is null");
    *out = nullptr;
    auto room = std::make_unique<deixis_room>();
    if (target_map_path != nullptr) {
      room->map = read_target_map(target_map_path);
    }
    *out = room.release();
  });
}

void deixis_room_destroy(deixis_room* room) {
  delete room;
}

const char* deixis_room_last_error(const deixis_room* room) {
  return room == nullptr ? "null room" : room->last_error.c_str();
}

deixis_status deixis_room_set_target(deixis_room* room, const deixis_target* target,
                                     const char* name) {
  if (room == nullptr) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  return handle_guarded(&room->last_error, [&] {
    require(target != nullptr, "deixis_room_set_target: target is null");
    require(target->id >= 1 && target->id <= kMaxObjectTarget,
            "deixis_room_set_target: an object's id is 1..1000000");
    require(finite(target->position) && finite(target->size) && target->size.x >= 0 &&
                target->size.y >= 0 && target->size.z >= 0,
            "deixis_room_set_target: position and size must be finite, sizes not negative");
    const TargetKind kind = kind_from_c(target->kind);
    auto it = std::find_if(room->map.objects.begin(), room->map.objects.end(),
                           [&](const TargetObject& o) { return o.id == target->id; });
    if (it == room->map.objects.end()) {
      room->map.objects.push_back({target->id, name != nullptr ? name : "", kind, {}, {}});
      it = room->map.objects.end() - 1;
    } else if (name != nullptr) {
      it->name = name;
    }
    it->kind = kind;
    it->position = from_c(target->position);
    it->size = from_c(target->size);
  });
}

deixis_status deixis_room_remove_target(deixis_room* room, int32_t id) {
  if (room == nullptr) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  return handle_guarded(&room->last_error, [&] {
    const auto removed =
        std::erase_if(room->map.objects, [&](const TargetObject& o) { return o.id == id; });
    require(removed > 0, "deixis_room_remove_target: no object has that id");
  });
}

size_t deixis_room_target_count(const deixis_room* room) {
  return room == nullptr ? 0 : room->map.objects.size();
}

deixis_status deixis_room_target(const deixis_room* room, size_t i, deixis_target* out) {
  if (room == nullptr || out == nullptr || i >= room->map.objects.size()) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  const TargetObject& o = room->map.objects[i];
  *out = {o.id, kind_to_c(o.kind), to_c(o.position), to_c(o.size)};
  return DEIXIS_OK;
}

void deixis_room_set_partner_head(deixis_room* room, deixis_vec3 head) {
  if (room != nullptr && finite(head)) {
    room->partner_head = from_c(head);
  }
}

deixis_status deixis_room_set_person(deixis_room* room, uint8_t person, deixis_vec3 head) {
  if (room == nullptr) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  return handle_guarded(&room->last_error, [&] {
    require_person(person);
    require(finite(head), "deixis_room_set_person: the head position is not finite");
    auto* begin = room->people.data();
    auto* end = begin + room->people_count;
    auto* it = std::find_if(begin, end, [&](const PersonTarget& p) { return p.id == person; });
    if (it == end) {
      ++room->people_count;  // at most 254 distinct ids: the array always has room
    }
    *it = {person, from_c(head)};
  });
}

deixis_status deixis_room_remove_person(deixis_room* room, uint8_t person) {
  if (room == nullptr) {
    return DEIXIS_ERROR_INVALID_ARGUMENT;
  }
  return handle_guarded(&room->last_error, [&] {
    require_person(person);
    auto* begin = room->people.data();
    auto* end = begin + room->people_count;
    auto* it = std::remove_if(begin, end, [&](const PersonTarget& p) { return p.id == person; });
    require(it != end, "deixis_room_remove_person: that person is not in the room");
    room->people_count = static_cast<std::size_t>(it - begin);
  });
}

}  // extern "C"
