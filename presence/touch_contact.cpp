#include "presence/touch_contact.h"

#include <algorithm>
#include <cmath>

#include "core/math/smoothstep.h"

namespace deixis::presence {

Vec3 touch_contact_offset(const Vec3& index_tip, const TargetObject* object,
                          float deictic_progression, float hand_weight, float radius,
                          const TouchContactConfig& config) {
  if (object == nullptr || object->id == kPartnerTarget || !(radius > 0.0f) ||
      !index_tip.allFinite() || !std::isfinite(deictic_progression) ||
      !std::isfinite(hand_weight)) {
    return Vec3::Zero();
  }
  const Vec3 offset = closest_surface_point(*object, index_tip) - index_tip;
  const float distance = offset.norm();
  if (!(distance < radius)) {
    return Vec3::Zero();
  }
  // Full weight up to half the radius, fading to none at the radius, so the hand never jumps.
  const float near = 1.0f - smoothstep((distance - 0.5f * radius) / (0.5f * radius));
  const float complete = smoothstep((deictic_progression - config.onset) / (1.0f - config.onset));
  const float network = 1.0f - std::clamp(hand_weight, 0.0f, 1.0f);
  return (near * complete * network) * offset;
}

}  // namespace deixis::presence
