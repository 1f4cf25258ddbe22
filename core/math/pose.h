#pragma once
// Rigid transforms named the way the whole code base names them: T_parent_child is the pose of
// frame `child` expressed in frame `parent`, so p_parent = T_parent_child * p_child and
// T_a_c = compose(T_a_b, T_b_c). Example: T_root_head, T_head_hand, T_hand_fingertip.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace deixis {

using Vec3 = Eigen::Vector3f;
using Mat3 = Eigen::Matrix3f;
using Quat = Eigen::Quaternionf;

struct Pose {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
};

// T_a_c from T_a_b and T_b_c.
inline Pose compose(const Pose& T_a_b, const Pose& T_b_c) {
  return {T_a_b.rotation * T_b_c.rotation, T_a_b.rotation * T_b_c.translation + T_a_b.translation};
}

// T_b_a from T_a_b (the rotation must be orthonormal).
inline Pose inverse(const Pose& T_a_b) {
  const Mat3 R_b_a = T_a_b.rotation.transpose();
  return {R_b_a, -(R_b_a * T_a_b.translation)};
}

// A point given in frame b, expressed in frame a.
inline Vec3 transform_point(const Pose& T_a_b, const Vec3& p_b) {
  return T_a_b.rotation * p_b + T_a_b.translation;
}

// A direction (free vector) given in frame b, expressed in frame a.
inline Vec3 transform_direction(const Pose& T_a_b, const Vec3& d_b) {
  return T_a_b.rotation * d_b;
}

// A rotation about +Y (yaw) by `angle` radians, right-handed.
Mat3 yaw_rotation(float angle);

// The yaw angle of a rotation's facing direction. `forward_axis` is the local axis that points
// forward (−Z in the world frame, +Z in the network frame).
float yaw_of(const Mat3& rotation, const Vec3& forward_axis);

// True when every entry is finite.
inline bool is_finite(const Pose& T) {
  return T.rotation.allFinite() && T.translation.allFinite();
}

}  // namespace deixis
