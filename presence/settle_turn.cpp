#include "presence/settle_turn.h"

#include <algorithm>
#include <cmath>

#include "core/math/angles.h"
#include "core/math/smoothstep.h"

namespace deixis::presence {

Eigen::AngleAxisf settle_turn(const Vec3& from, const Vec3& to, float person_off_deg,
                              const SettleBounds& bounds, float weight) {
  const Eigen::AngleAxisf none(0.0f, Vec3::UnitX());
  const float from_norm = from.norm();
  if (!(from_norm > 1e-6f) || !(to.norm() > 1e-6f)) {
    return none;
  }
  const Vec3 f = from / from_norm;
  const Vec3 t = to.normalized();
  const Vec3 axis = f.cross(t);
  const float angle = std::atan2(axis.norm(), f.dot(t));
  const float on_target =
      1.0f - smoothstep((person_off_deg - bounds.full_deg) / (bounds.none_deg - bounds.full_deg));
  const float turn = std::min(angle, bounds.max_deg * kRadPerDeg) * on_target * weight;
  if (!(turn > 0.0f) || !(axis.norm() > 1e-9f)) {
    return none;  // nothing to do, or already on the target (or exactly away from it)
  }
  return {turn, axis.normalized()};
}

}  // namespace deixis::presence
