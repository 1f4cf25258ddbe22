#include "ik/joint_limits.h"

namespace deixis::ik {
namespace {

bool angle_ok(float a) {
  return a >= 0.0f && a <= kPi;  // false for NaN
}

bool range_ok(const HingeRange& r) {
  return r.min >= -kPi && r.min <= r.max && r.max <= kPi;
}

}  // namespace

std::string_view check(const IkLimits& l) {
  if (!angle_ok(l.spine)) {
    return "spine: not an angle in [0, π]";
  }
  if (!angle_ok(l.chest)) {
    return "chest: not an angle in [0, π]";
  }
  if (!angle_ok(l.neck)) {
    return "neck: not an angle in [0, π]";
  }
  if (!angle_ok(l.head)) {
    return "head: not an angle in [0, π]";
  }
  if (!range_ok(l.elbow) || l.elbow.min < 0.0f) {
    return "elbow: flexion range not within [0, π] and ordered";
  }
  if (!angle_ok(l.pronation) || !angle_ok(l.supination)) {
    return "pronation/supination: not an angle in [0, π]";
  }
  if (!angle_ok(l.wrist_swing) || !angle_ok(l.wrist_twist)) {
    return "wrist_swing/wrist_twist: not an angle in [0, π]";
  }
  for (const HingeRange& r : l.index) {
    if (!range_ok(r)) {
      return "index: flexion range not within [−π, π] and ordered";
    }
  }
  if (!angle_ok(l.eyes.yaw) || !(l.eyes.up >= 0.0f && l.eyes.up < kPi / 2) ||
      !(l.eyes.down >= 0.0f && l.eyes.down < kPi / 2)) {
    return "eyes: yaw not in [0, π] or up/down not in [0, π/2)";
  }
  return {};
}

Mat3 clamp_to_rest(const Mat3& local, const Mat3& rest_local, float max_angle) {
  return rest_local * clamp_rotation(rest_deviation(local, rest_local), max_angle);
}

}  // namespace deixis::ik
