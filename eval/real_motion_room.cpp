#include "eval/real_motion_room.h"

#include <cmath>
#include <string>

#include "core/math/angles.h"

namespace deixis::eval {

namespace {

// The avatar's eyes: 0.936 of a 1.70 m stature (gesture/upright_calibration.h's ratio).
constexpr float kAvatarEyeHeightM = 0.936f * 1.70f;
constexpr float kSphereM = 0.2f;

TargetMap room_of(const char* site, const Pose& T_world_root, bool moved) {
  TargetMap map;
  map.site = site;
  for (const TargetPlacement& p : kRealMotionTargets) {
    TargetObject o;
    o.id = p.id;
    o.name = "target " + std::to_string(p.id);
    o.kind = TargetKind::kSphere;
    o.position = placed(T_world_root, moved ? moved_copy(p) : p);
    o.size = Vec3::Constant(kSphereM);
    map.objects.push_back(o);
  }
  return map;
}

}  // namespace

TargetPlacement moved_copy(const TargetPlacement& p) {
  return {p.id, -p.azimuth_deg, p.elevation_deg + 10.0f, 1.25f * p.distance_m};
}

Vec3 placed(const Pose& T_world_root, const TargetPlacement& p) {
  const float az = p.azimuth_deg * kRadPerDeg;
  const float el = p.elevation_deg * kRadPerDeg;
  const Vec3 in_root(std::sin(az) * std::cos(el), std::sin(el), -std::cos(az) * std::cos(el));
  return transform_point(T_world_root, p.distance_m * in_root);
}

RealMotionRooms real_motion_rooms(const BodyCalibration& person) {
  RealMotionRooms rooms;
  rooms.T_world_avatar_root.translation = Vec3(0.0f, kAvatarEyeHeightM, 0.0f);
  rooms.person_room = room_of("recording", person.T_world_root, false);
  rooms.avatar_room = room_of("avatar", rooms.T_world_avatar_root, true);
  return rooms;
}

}  // namespace deixis::eval
