#include "core/math/network_frame.h"

#include <algorithm>
#include <cmath>

namespace deixis {

TargetAngles target_angles(const Vec3& p) {
  return {std::atan2(-p.x(), p.z()), std::atan2(p.z(), p.y()),
          std::min(p.norm(), kTargetDistanceClamp)};
}

TargetFeature target_feature(const Vec3& head_target, const Vec3& hand_target) {
  const TargetAngles head = target_angles(head_target);
  const TargetAngles hand = target_angles(hand_target);
  return {head.theta, head.phi, hand.theta, hand.phi, hand.distance};
}

void mirror_end_effectors(std::span<float, kEndEffectorSize> x) {
  for (const int offset : ee::kAllVectors) {
    x[offset] = -x[offset];
  }
}

void mirror_target_feature(std::span<float, kTargetFeatureSize> t) {
  t[tf::kHeadTheta] = -t[tf::kHeadTheta];
  t[tf::kHandTheta] = -t[tf::kHandTheta];
}

}  // namespace deixis
