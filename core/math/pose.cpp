#include "core/math/pose.h"

#include <cmath>

namespace deixis {

Mat3 yaw_rotation(float angle) {
  return Eigen::AngleAxisf(angle, Vec3::UnitY()).toRotationMatrix();
}

float yaw_of(const Mat3& rotation, const Vec3& forward_axis) {
  const Vec3 f = rotation * forward_axis;
  // Yaw is the rotation about +Y that carries the forward axis onto f's horizontal projection.
  // With R_y(a)·(0,0,s) = (s·sin a, 0, s·cos a) this is atan2(f.x·s, f.z·s) for s = forward_axis.z.
  const float s = forward_axis.z() >= 0.0f ? 1.0f : -1.0f;
  return std::atan2(s * f.x(), s * f.z());
}

}  // namespace deixis
