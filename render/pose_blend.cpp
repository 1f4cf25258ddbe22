#include "render/pose_blend.h"

#include <algorithm>

#include "core/error.h"

namespace deixis::render {

Pose blend(const Pose& from, const Pose& to, float t) {
  t = std::clamp(t, 0.0f, 1.0f);
  // Eigen's slerp flips the second quaternion when the dot product is negative: the shorter arc.
  const Quat q = Quat(from.rotation).slerp(t, Quat(to.rotation)).normalized();
  return {q.toRotationMatrix(), from.translation + t * (to.translation - from.translation)};
}

void blend_poses(std::span<const Pose> from, std::span<const Pose> to, float t,
                 std::span<Pose> out) {
  if (from.size() != to.size() || out.size() != from.size()) {
    throw Error("blend_poses: " + std::to_string(from.size()) + ", " + std::to_string(to.size()) +
                " and " + std::to_string(out.size()) + " poses (expected equal counts)");
  }
  for (std::size_t i = 0; i < from.size(); ++i) {
    out[i] = blend(from[i], to[i], t);
  }
}

}  // namespace deixis::render
