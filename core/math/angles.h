#pragma once
// Degrees and radians, and the angle between two directions: what the target selection, the
// site's gaze measures, gaze settling and the body turn share (the evaluation's metrics keep a
// double-precision one of their own, eval/metrics.cpp).
#include <cmath>

#include "core/math/pose.h"

namespace deixis {

inline constexpr float kDegPerRad = 57.2957795f;
inline constexpr float kRadPerDeg = 0.0174532925f;

// The angle between directions `a` and `b` (any non-zero length), degrees in [0, 180]. atan2 of
// |a × b| and a · b stays accurate near 0° and 180°, where acos of the normalised dot does not.
inline float angle_deg(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b)) * kDegPerRad;
}

}  // namespace deixis
