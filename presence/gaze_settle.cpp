#include "presence/gaze_settle.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "core/math/angles.h"
#include "core/math/smoothstep.h"

namespace deixis::presence {

Vec3 settled_gaze(const Vec3& gaze, const Vec3& eyes, const Vec3* target, float person_off_deg,
                  float head_weight, const GazeSettleConfig& config) {
  if (target == nullptr || !gaze.allFinite() || !eyes.allFinite() || !target->allFinite() ||
      !std::isfinite(person_off_deg) || !std::isfinite(head_weight)) {
    return gaze;
  }
  const float norm = gaze.norm();
  const Vec3 to_target = *target - eyes;
  if (!(norm > 1e-6f) || !(to_target.norm() > 1e-6f)) {
    return gaze;
  }
  const Vec3 from = gaze / norm;
  const Vec3 to = to_target.normalized();
  const Vec3 axis = from.cross(to);
  const float angle = std::atan2(axis.norm(), from.dot(to));
  const float on_target =
      1.0f - smoothstep((person_off_deg - config.full_deg) / (config.none_deg - config.full_deg));
  const float network = 1.0f - std::clamp(head_weight, 0.0f, 1.0f);
  const float turn = std::min(angle, config.max_deg * kRadPerDeg) * on_target * network;
  if (!(turn > 0.0f) || !(axis.norm() > 1e-9f)) {
    return gaze;  // nothing to do, or already on the target (or exactly away from it)
  }
  return Eigen::AngleAxisf(turn, axis.normalized()) * from;
}

}  // namespace deixis::presence
