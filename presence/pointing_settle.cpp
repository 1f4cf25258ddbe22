#include "presence/pointing_settle.h"

#include <algorithm>
#include <cmath>

#include "core/math/smoothstep.h"
#include "presence/settle_turn.h"

namespace deixis::presence {

Mat3 pointing_settle_rotation(const Vec3& index_tip, const Vec3& eyes, const Vec3* target,
                              float person_off_deg, float deictic_progression, float hand_weight,
                              const PointingSettleConfig& config) {
  if (target == nullptr || !index_tip.allFinite() || !eyes.allFinite() || !target->allFinite() ||
      !std::isfinite(person_off_deg) || !std::isfinite(deictic_progression) ||
      !std::isfinite(hand_weight)) {
    return Mat3::Identity();
  }
  const float deictic = smoothstep((deictic_progression - config.onset) / (1.0f - config.onset));
  const float network = 1.0f - std::clamp(hand_weight, 0.0f, 1.0f);
  return settle_turn(index_tip - eyes, *target - eyes, person_off_deg,
                     {config.full_deg, config.none_deg, config.max_deg}, deictic * network)
      .toRotationMatrix();
}

}  // namespace deixis::presence
