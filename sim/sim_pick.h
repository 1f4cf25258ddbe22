#pragma once
// What the mouse is over in a room view of `deixis sim` (docs/sim.md): the room's object a ray
// from the camera hits first, and where a ray meets the horizontal plane an object is dragged in.
// Geometry only (no GL), so it is tested on its own.

#include <optional>

#include "core/target_map.h"
#include "render/camera.h"

namespace deixis::sim {

// Distance along `ray` to where it enters `object` (a sphere of diameter size.x, or the box of
// `size` about its centre; a screen is a thin box), or empty when it misses or the object is
// behind the ray's origin.
std::optional<float> ray_hit(const render::Ray& ray, const TargetObject& object);

// The id of the nearest object `ray` hits, or kNoTarget.
TargetId pick_object(const render::Ray& ray, const TargetMap& map);

// Where `ray` crosses the horizontal plane at height `y`, or empty when it runs parallel to it,
// away from it, or meets it further than `max_distance` (the horizon: a drag stops there).
std::optional<Vec3> ray_at_height(const render::Ray& ray, float y, float max_distance = 30.0f);

}  // namespace deixis::sim
