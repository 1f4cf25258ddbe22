#pragma once
// The rooms a recording of real motion is measured in (docs/eval.md#real-motion-bvh): targets
// placed around the calibrated person, and the avatar's room where every copy stands elsewhere, as
// the synthetic evaluation's avatar targets are not the user's (docs/eval.md, DIP).
//
// The person's room: eight spheres 0.2 m across, placed from the person's root O (at H, yaw-only,
// −Z forward): six at eye level 2.0 m away at azimuths ±20°, ±45° and ±75°, two on a table 1.2 m
// away and 20° below eye level at ±30°. None stands straight ahead, so a person looking ahead
// designates nothing. The avatar's room: the same ids around the avatar's root O, mirrored
// (azimuth −a), 10° higher and 1.25 times as far, so every copy is at least 40° of azimuth and 10°
// of elevation away from where the person's room has it.

#include <array>

#include "core/target_map.h"
#include "core/tracking.h"

namespace deixis::eval {

struct TargetPlacement {
  TargetId id = kNoTarget;
  float azimuth_deg = 0.0f;  // + to the person's right
  float elevation_deg = 0.0f;
  float distance_m = 0.0f;  // from O
};

inline constexpr std::array<TargetPlacement, 8> kRealMotionTargets = {{
    {1, -75.0f, 0.0f, 2.0f},
    {2, -45.0f, 0.0f, 2.0f},
    {3, -20.0f, 0.0f, 2.0f},
    {4, 20.0f, 0.0f, 2.0f},
    {5, 45.0f, 0.0f, 2.0f},
    {6, 75.0f, 0.0f, 2.0f},
    {7, -30.0f, -20.0f, 1.2f},
    {8, 30.0f, -20.0f, 1.2f},
}};

// Where the avatar's copy of a placement stands, seen from the avatar's root.
TargetPlacement moved_copy(const TargetPlacement& p);

// The world position of a placement around a root O (yaw-only, −Z forward, +X right).
Vec3 placed(const Pose& T_world_root, const TargetPlacement& p);

struct RealMotionRooms {
  TargetMap person_room;     // the recording's world frame
  TargetMap avatar_room;     // the avatar's room
  Pose T_world_avatar_root;  // the avatar's O there: 1.59 m up (eyes of a 1.70 m avatar), −Z ahead
};

RealMotionRooms real_motion_rooms(const BodyCalibration& person);

}  // namespace deixis::eval
