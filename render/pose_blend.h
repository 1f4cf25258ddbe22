#pragma once
// Display-rate interpolation between two 30 Hz ticks (docs/conventions.md#rates-and-windows): the
// caller keeps the last two skeleton poses and the time since the older one; this blends them.
// Works joint by joint on whatever frame the poses are in: model poses (T_model_joint, what the
// renderer draws) as well as local ones. Blending local poses keeps bone lengths exact; between two
// ticks 33 ms apart the difference from blending model poses is far below a pixel.

#include <span>

#include "core/math/pose.h"

namespace deixis::render {

// `from` at t = 0, `to` at t = 1: rotations by slerp along the shorter arc, translations by lerp.
// t is clamped to [0, 1]: a late tick holds the newest pose instead of extrapolating past it.
Pose blend(const Pose& from, const Pose& to, float t);

// blend() for every joint; all three spans must have the same size. No allocation.
void blend_poses(std::span<const Pose> from, std::span<const Pose> to, float t,
                 std::span<Pose> out);

}  // namespace deixis::render
