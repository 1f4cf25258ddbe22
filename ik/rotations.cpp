#include "ik/rotations.h"

#include <algorithm>
#include <cmath>

namespace deixis::ik {
namespace {

// q with w ≥ 0, so that its angle 2·atan2(|v|, w) lies in [0, π].
Quat canonical_quat(const Mat3& R) {
  Quat q(R);
  if (q.w() < 0.0f) {
    q.coeffs() = -q.coeffs();
  }
  return q;
}

float wrap_angle(float a) {
  if (a > kPi) {
    return a - 2.0f * kPi;
  }
  if (a <= -kPi) {
    return a + 2.0f * kPi;
  }
  return a;
}

}  // namespace

Vec3 normalized_or(const Vec3& v, const Vec3& fallback) {
  // Scaled by the largest entry first, so a huge (but finite) vector keeps its direction instead
  // of overflowing the squared norm.
  const float m = v.cwiseAbs().maxCoeff();
  if (!std::isfinite(m) || !(m > 0.0f)) {
    return fallback;
  }
  const Vec3 w = v / m;
  return m * w.norm() > kTinyLength ? Vec3(w.normalized()) : fallback;
}

float robust_norm(const Vec3& v) {
  const float m = v.cwiseAbs().maxCoeff();
  return std::isfinite(m) && m > 0.0f ? m * (v / m).norm() : (m == 0.0f ? 0.0f : m);
}

Vec3 any_perpendicular(const Vec3& v) {
  const Vec3 a = v.cwiseAbs();
  const Vec3 other = a.x() <= a.y() && a.x() <= a.z() ? Vec3::UnitX()
                     : a.y() <= a.z()                 ? Vec3::UnitY()
                                                      : Vec3::UnitZ();
  return v.cross(other).normalized();
}

Mat3 axis_angle(const Vec3& axis, float angle) {
  return Eigen::AngleAxisf(angle, axis).toRotationMatrix();
}

Mat3 rotation_between(const Vec3& from, const Vec3& to) {
  const float c = std::clamp(from.dot(to), -1.0f, 1.0f);
  const Vec3 axis = from.cross(to);
  const float s = axis.norm();
  if (s < 1e-7f) {
    return c > 0.0f ? Mat3::Identity() : axis_angle(any_perpendicular(from), kPi);
  }
  return axis_angle(axis / s, std::atan2(s, c));
}

float rotation_angle(const Mat3& R) {
  const Quat q = canonical_quat(R);
  return 2.0f * std::atan2(q.vec().norm(), q.w());
}

Mat3 orthonormalized(const Mat3& R) {
  const float scale = R.cwiseAbs().maxCoeff();
  if (!std::isfinite(scale) || !(scale > 0.0f)) {
    return Mat3::Identity();
  }
  const Vec3 x = R.col(0) / scale;
  const float n = x.norm();
  if (!(n > kTinyLength)) {
    return Mat3::Identity();
  }
  const Vec3 y1 = R.col(1) / scale;
  Vec3 y = y1 - y1.dot(x / n) * (x / n);
  const float m = y.norm();
  if (!(m > kTinyLength * n)) {
    return Mat3::Identity();
  }
  Mat3 Q;
  Q.col(0) = x / n;
  Q.col(1) = y / m;
  Q.col(2) = Q.col(0).cross(Q.col(1));
  return Q;
}

Mat3 scale_rotation(const Mat3& R, float t) {
  const Quat q = canonical_quat(R);
  const float s = q.vec().norm();
  if (s < 1e-7f) {
    return Mat3::Identity();
  }
  return axis_angle(q.vec() / s, t * 2.0f * std::atan2(s, q.w()));
}

Mat3 clamp_rotation(const Mat3& R, float max_angle) {
  const Quat q = canonical_quat(R);
  const float s = q.vec().norm();
  // Most rotations the IK clamps are well inside their limit, and the angle's atan2 was a tenth of
  // the IK's time. The angle 2·atan2(s, w) is at most 2·s/w (atan x ≤ x), so where 2·s is below
  // max_angle·w by more than the round-off of that product and of atan2 (a few 1e-7), the angle
  // is inside the limit however atan2 rounds: the same decision, and the same bits, as computing
  // it. Near the limit (within 1e-4 of it, relatively) or beyond, the angle is computed.
  constexpr float kSurelyInside = 0.9999f;
  if (2.0f * s <= kSurelyInside * max_angle * q.w()) {
    return R;
  }
  const float angle = 2.0f * std::atan2(s, q.w());
  if (angle <= max_angle || s < 1e-7f) {
    return R;
  }
  return axis_angle(q.vec() / s, max_angle);
}

SwingTwist swing_twist(const Mat3& R, const Vec3& axis) {
  const Quat q = canonical_quat(R);
  const float along = q.vec().dot(axis);
  const float n = std::sqrt(along * along + q.w() * q.w());
  if (n < 1e-7f) {
    // A swing by π: no twist component at all.
    return {R, 0.0f};
  }
  const Quat twist(q.w() / n, axis.x() * along / n, axis.y() * along / n, axis.z() * along / n);
  const Quat swing = q * twist.conjugate();
  return {swing.toRotationMatrix(), wrap_angle(2.0f * std::atan2(along, q.w()))};
}

Mat3 frame_from(const Vec3& x, const Vec3& y) {
  Vec3 y_perp = y - y.dot(x) * x;
  const float n = y_perp.norm();
  y_perp = std::isfinite(n) && n > kTinyLength ? Vec3(y_perp / n) : any_perpendicular(x);
  // Twice: when y is nearly parallel to x, one pass leaves round-off of order ε/n along x.
  y_perp = (y_perp - y_perp.dot(x) * x).normalized();
  Mat3 F;
  F.col(0) = x;
  F.col(1) = y_perp;
  F.col(2) = x.cross(y_perp);
  return F;
}

}  // namespace deixis::ik
