#pragma once
// Angles between rotations and between directions, accurate for the tiny angles that
// quantisation errors are (acos of a dot product loses them in float rounding).

#include <cmath>

#include "core/math/pose.h"

namespace deixis::net {

inline double angle_deg(const Mat3& a, const Mat3& b) {
  const Eigen::Quaterniond qa(a.cast<double>());
  const Eigen::Quaterniond qb(b.cast<double>());
  const Eigen::Quaterniond d = qa.conjugate() * qb;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w())) * 180.0 / M_PI;
}

inline double angle_deg(const Vec3& a, const Vec3& b) {
  const Eigen::Vector3d x = a.cast<double>();
  const Eigen::Vector3d y = b.cast<double>();
  return std::atan2(x.cross(y).norm(), x.dot(y)) * 180.0 / M_PI;
}

}  // namespace deixis::net
