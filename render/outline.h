#pragma once
// A target object as lines rather than a solid (decision 85): in a see-through headset the real
// object is there to see, so setting the room up shows where its target stands without hiding
// the object behind it. A box (or screen) as its 12 edges; a sphere as three great circles.

#include <span>

#include "core/target_map.h"
#include "render/scene.h"

namespace deixis::render {

inline constexpr int kSphereOutlineSegments = 16;  // per circle
inline constexpr std::size_t kMaxOutlineLines = 3 * kSphereOutlineSegments;

// Writes the object's outline into `out` (at least kMaxOutlineLines long); returns how many
// lines it wrote. Allocates nothing.
std::size_t outline(const TargetObject& object, const Colour& colour, std::span<DebugLine> out);

}  // namespace deixis::render
