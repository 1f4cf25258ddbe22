#include "presence/gaze_settle.h"

#include <algorithm>
#include <cmath>

#include "presence/settle_turn.h"

namespace deixis::presence {

Vec3 settled_gaze(const Vec3& gaze, const Vec3& eyes, const Vec3* target, float person_off_deg,
                  float head_weight, const GazeSettleConfig& config) {
  if (target == nullptr || !gaze.allFinite() || !eyes.allFinite() || !target->allFinite() ||
      !std::isfinite(person_off_deg) || !std::isfinite(head_weight)) {
    return gaze;
  }
  const float network = 1.0f - std::clamp(head_weight, 0.0f, 1.0f);
  const Eigen::AngleAxisf turn =
      settle_turn(gaze, *target - eyes, person_off_deg,
                  {config.full_deg, config.none_deg, config.max_deg}, network);
  if (turn.angle() == 0.0f) {
    return gaze;
  }
  return turn * gaze.normalized();
}

}  // namespace deixis::presence
