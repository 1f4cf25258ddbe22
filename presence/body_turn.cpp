#include "presence/body_turn.h"

#include <algorithm>
#include <cmath>

#include "core/math/angles.h"

namespace deixis::presence {

float wanted_turn(const Pose& T_world_spot, const Vec3* target, float weight, bool pointing,
                  const BodyTurnConfig& config) {
  if (target == nullptr || !(weight > 0.0f)) {
    return 0.0f;
  }
  const Vec3 p = transform_point(inverse(T_world_spot), *target);
  if (p.x() * p.x() + p.z() * p.z() < 1e-6f) {
    return 0.0f;  // straight above or below: no direction to turn to
  }
  const float azimuth = std::atan2(-p.x(), -p.z());  // + to the left of the facing (−Z)
  const float comfort = pointing ? config.comfort_deg : config.gaze_comfort_deg;
  const float beyond = std::abs(azimuth) - comfort * kRadPerDeg;
  if (beyond <= 0.0f) {
    return 0.0f;
  }
  const float turn = std::min(beyond, config.max_turn_deg * kRadPerDeg);
  return std::copysign(turn, azimuth) * std::min(weight, 1.0f);
}

TurnDesignation turn_designation(const Vec3* hand, TargetId hand_target, float deictic,
                                 const Vec3* head, TargetId head_target, float gaze) {
  const bool by_hand =
      hand != nullptr && (deictic >= gaze || (hand_target == head_target && head != nullptr));
  const float progression = by_hand ? deictic : gaze;
  return {by_hand ? hand : head, std::min(1.0f, 2.0f * progression), by_hand};
}

float turned(float current, float wanted, float dt, const BodyTurnConfig& config) {
  const float step = config.speed_deg_per_s * kRadPerDeg * dt;
  return current + std::clamp(wanted - current, -step, step);
}

}  // namespace deixis::presence
