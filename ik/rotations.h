#pragma once
// Rotation helpers shared by the IK jobs. Every function returns a proper rotation (orthonormal,
// det +1) and never NaN for finite input: degenerate cases (zero vectors, antiparallel vectors,
// rotations by π) pick a documented fallback instead of dividing by zero.

#include "core/math/pose.h"

namespace deixis::ik {

inline constexpr float kPi = 3.14159265358979323846f;
inline constexpr float deg(float degrees) {
  return degrees * (kPi / 180.0f);
}

// Below this length a vector has no usable direction (1 µm, far below any bone or offset).
inline constexpr float kTinyLength = 1e-6f;

// `v` normalised (even when its squared norm would overflow), or `fallback` when v is (near)
// zero or not finite.
Vec3 normalized_or(const Vec3& v, const Vec3& fallback);

// |v| without overflow for huge finite vectors (scaled by the largest entry first).
float robust_norm(const Vec3& v);

// A unit vector perpendicular to unit `v` (deterministic: built from the axis least aligned).
Vec3 any_perpendicular(const Vec3& v);

// The rotation about unit `axis` by `angle` (right-handed).
Mat3 axis_angle(const Vec3& axis, float angle);

// The smallest rotation that carries unit `from` onto unit `to`. Antiparallel vectors rotate by
// π about any_perpendicular(from).
Mat3 rotation_between(const Vec3& from, const Vec3& to);

// The rotation angle of R in [0, π] (robust near 0 and π, unlike acos of the trace).
float rotation_angle(const Mat3& R);

// A proper rotation from any matrix: Gram–Schmidt on its first two columns (exact for a scaled
// rotation, close for a nearly orthonormal one, always det +1); identity when those columns are
// not finite or not independent.
Mat3 orthonormalized(const Mat3& R);

// A product of rotations made orthonormal again (Gram–Schmidt on the first two columns, no
// checks): for matrices already within float round-off of a rotation, where the products of many
// small turns would otherwise drift (5e-5 after a lean, 0.003° in where the eyes look).
inline Mat3 renormalized(const Mat3& R) {
  Mat3 Q;
  Q.col(0) = R.col(0).normalized();
  Q.col(1) = (R.col(1) - R.col(1).dot(Q.col(0)) * Q.col(0)).normalized();
  Q.col(2) = Q.col(0).cross(Q.col(1));
  return Q;
}

// R^t: the same axis, `t` times the angle (t in [0, 1] moves from identity to R along the
// shortest arc).
Mat3 scale_rotation(const Mat3& R, float t);

// R with its angle clamped to `max_angle` (same axis).
Mat3 clamp_rotation(const Mat3& R, float max_angle);

// R = swing · twist, twist about unit `axis`, swing about an axis perpendicular to it.
struct SwingTwist {
  Mat3 swing;
  float twist;  // signed angle about `axis`, in (−π, π]
};
SwingTwist swing_twist(const Mat3& R, const Vec3& axis);

// The orthonormal frame whose x column is unit `x` and whose y column is `y` made perpendicular
// to it (any perpendicular when y is parallel to x); z = x × y.
Mat3 frame_from(const Vec3& x, const Vec3& y);

}  // namespace deixis::ik
