#include "core/target_map.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <span>

#include "core/error.h"
#include "core/io/atomic_file.h"
#include "core/io/json_reader.h"

namespace deixis {

namespace {

using json = nlohmann::json;

struct Kind {
  TargetKind kind;
  std::string_view name;
};
constexpr Kind kKinds[] = {
    {TargetKind::kSphere, "sphere"}, {TargetKind::kBox, "box"}, {TargetKind::kScreen, "screen"}};

using Reader = JsonReader;

TargetObject parse_object(const Reader& r, const json& j, const std::string& path) {
  if (!j.is_object()) {
    r.fail(path, "expected an object");
  }
  r.only_fields(j, path, {"id", "name", "kind", "position", "size"});
  TargetObject object;
  object.id =
      static_cast<TargetId>(r.integer_in(r.member(j, path, "id"), path + ".id", 1, 1'000'000));
  object.name = r.name(r.member(j, path, "name"), path + ".name");  // sent in the target map
  const std::string kind = r.string(r.member(j, path, "kind"), path + ".kind");
  bool known = false;
  for (const Kind& k : kKinds) {
    if (k.name == kind) {
      object.kind = k.kind;
      known = true;
    }
  }
  if (!known) {
    r.fail(path + ".kind", "unknown kind '" + kind + "' (expected sphere, box or screen)");
  }
  object.position = r.vec3(r.member(j, path, "position"), path + ".position");
  object.size = r.vec3(r.member(j, path, "size"), path + ".size");
  for (int k = 0; k < 3; ++k) {
    if (!(object.size[k] > 0.0f) || object.size[k] > 100.0f) {
      r.fail(path + ".size[" + std::to_string(k) + "]", "expected a size in (0, 100] m");
    }
  }
  return object;
}

}  // namespace

std::string_view kind_name(TargetKind kind) {
  for (const Kind& k : kKinds) {
    if (k.kind == kind) {
      return k.name;
    }
  }
  return "?";
}

const TargetObject* TargetMap::find(TargetId id) const {
  for (const TargetObject& o : objects) {
    if (o.id == id) {
      return &o;
    }
  }
  return nullptr;
}

TargetMap parse_target_map(std::string_view json_text, std::string_view source) {
  const Reader r(source);
  const json j = r.parse_object(json_text);
  const std::string format = r.string(r.member(j, "", "format"), "format");
  if (format != "deixis-target-map") {
    r.fail("format", "expected \"deixis-target-map\", found \"" + format + "\"");
  }
  // Read as a range-checked integer first: a huge value must not wrap to the version number.
  const std::int64_t version = r.integer_in(r.member(j, "", "version"), "version", 0, 1000);
  if (version != TargetMap::kFormatVersion) {
    r.fail("version", "this Deixis reads version " + std::to_string(TargetMap::kFormatVersion) +
                          ", found " + std::to_string(version));
  }
  TargetMap map;
  map.site = r.name(r.member(j, "", "site"), "site", 0);  // the wire allows an empty site here
  const json& objects = r.member(j, "", "objects");
  if (!objects.is_array()) {
    r.fail("objects", "expected an array");
  }
  if (objects.size() > 256) {
    r.fail("objects", "more than 256 objects");
  }
  std::set<TargetId> ids;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const std::string path = "objects[" + std::to_string(i) + "]";
    TargetObject object = parse_object(r, objects[i], path);
    if (!ids.insert(object.id).second) {
      r.fail(path + ".id", "id " + std::to_string(object.id) + " is used twice");
    }
    map.objects.push_back(std::move(object));
  }
  return map;
}

TargetMap read_target_map(const std::filesystem::path& path) {
  return parse_target_map(JsonReader::read_file(path), path.string());
}

void write_target_map(const TargetMap& map, const std::filesystem::path& path) {
  const std::string text = to_json(map);
  write_file_atomically(path, std::as_bytes(std::span(text.data(), text.size())));
}

std::string to_json(const TargetMap& map) {
  json objects = json::array();
  for (const TargetObject& o : map.objects) {
    objects.push_back({{"id", o.id},
                       {"name", o.name},
                       {"kind", kind_name(o.kind)},
                       {"position", {o.position.x(), o.position.y(), o.position.z()}},
                       {"size", {o.size.x(), o.size.y(), o.size.z()}}});
  }
  const json j = {{"format", "deixis-target-map"},
                  {"version", TargetMap::kFormatVersion},
                  {"site", map.site},
                  {"objects", objects}};
  return j.dump(2) + "\n";
}

Vec3 closest_surface_point(const TargetObject& object, const Vec3& p) {
  const Vec3 offset = p - object.position;
  if (object.kind == TargetKind::kSphere) {
    const float radius = object.size.x() / 2.0f;
    const float n = offset.norm();
    return n > 1e-6f ? Vec3(object.position + offset * (radius / n))
                     : Vec3(object.position + Vec3(0, radius, 0));
  }
  const Vec3 half = object.size / 2.0f;
  const Vec3 inside = offset.cwiseMax(-half).cwiseMin(half);
  if (inside != offset) {
    return object.position + inside;  // p is outside: the clamped point is on the surface
  }
  // p is inside: push it out through the nearest face.
  int axis = 0;
  float best = half[0] - std::abs(offset[0]);
  for (int k = 1; k < 3; ++k) {
    const float gap = half[k] - std::abs(offset[k]);
    if (gap < best) {
      best = gap;
      axis = k;
    }
  }
  Vec3 surface = offset;
  surface[axis] = offset[axis] >= 0.0f ? half[axis] : -half[axis];
  return object.position + surface;
}

}  // namespace deixis
