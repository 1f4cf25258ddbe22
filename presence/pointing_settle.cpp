#include "presence/pointing_settle.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "core/math/angles.h"
#include "core/math/smoothstep.h"

namespace deixis::presence {

Mat3 pointing_settle_rotation(const Vec3& index_tip, const Vec3& eyes, const Vec3* target,
                              float person_off_deg, float deictic_progression, float hand_weight,
                              const PointingSettleConfig& config) {
  if (target == nullptr || !index_tip.allFinite() || !eyes.allFinite() || !target->allFinite() ||
      !std::isfinite(person_off_deg) || !std::isfinite(deictic_progression) ||
      !std::isfinite(hand_weight)) {
    return Mat3::Identity();
  }
  const Vec3 to_tip = index_tip - eyes;
  const Vec3 to_target = *target - eyes;
  if (!(to_tip.norm() > 1e-6f) || !(to_target.norm() > 1e-6f)) {
    return Mat3::Identity();
  }
  const Vec3 from = to_tip.normalized();
  const Vec3 to = to_target.normalized();
  const Vec3 axis = from.cross(to);
  const float angle = std::atan2(axis.norm(), from.dot(to));
  const float on_target =
      1.0f - smoothstep((person_off_deg - config.full_deg) / (config.none_deg - config.full_deg));
  const float deictic = smoothstep((deictic_progression - config.onset) / (1.0f - config.onset));
  const float network = 1.0f - std::clamp(hand_weight, 0.0f, 1.0f);
  const float turn = std::min(angle, config.max_deg * kRadPerDeg) * on_target * deictic * network;
  if (!(turn > 0.0f) || !(axis.norm() > 1e-9f)) {
    return Mat3::Identity();  // nothing to do, or already on the target (or exactly away from it)
  }
  return Eigen::AngleAxisf(turn, axis.normalized()).toRotationMatrix();
}

}  // namespace deixis::presence
