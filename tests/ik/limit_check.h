#pragma once
// Measures a solved pose against the joint limits, independently of the code that enforces them:
// double precision, Eigen's own angle-axis, elbow flexion from joint positions. Returns the first
// violation as text (empty when every joint is within its limits), so a sweep can report which
// input broke which joint.

#include <cmath>
#include <span>
#include <sstream>
#include <string>

#include "ik/avatar_solver.h"

namespace deixis::ik::testing {

// Slack for float round-off in the solve (0.06°).
inline constexpr double kAngleSlack = 1e-3;

inline Eigen::Matrix3d to_double(const Mat3& R) {
  return R.cast<double>();
}

// The angle of a rotation, [0, π].
inline double angle_of(const Eigen::Matrix3d& R) {
  return Eigen::AngleAxisd(R).angle();
}

// A limit widened by the slack, in double.
inline double above(float limit) {
  return static_cast<double>(limit) + kAngleSlack;
}
inline double below(float limit) {
  return static_cast<double>(limit) - kAngleSlack;
}

// Signed twist of R about unit `axis`, and the swing angle that remains.
struct TwistSwing {
  double twist;
  double swing;
};
inline TwistSwing twist_swing(const Eigen::Matrix3d& R, const Eigen::Vector3d& axis) {
  Eigen::Quaterniond q(R);
  if (q.w() < 0) {
    q.coeffs() = -q.coeffs();
  }
  const double along = q.vec().dot(axis);
  const double twist = 2.0 * std::atan2(along, q.w());
  const Eigen::Matrix3d T(Eigen::AngleAxisd(twist, axis));
  return {std::remainder(twist, 2.0 * M_PI), angle_of(R * T.transpose())};
}

// (Each failure builds its own stream: constructing one per call would dominate a sweep under
// ASan.)
inline std::string check_limits(const AvatarSolver& s, std::span<const Pose> local,
                                std::span<const Pose> model) {
  const Skeleton& sk = s.rig.skeleton;
  const IkLimits& l = s.config.limits;
  const auto deviation = [&](int j) {
    return Eigen::Matrix3d(to_double(sk.rest_local[j].rotation).transpose() *
                           to_double(local[j].rotation));
  };
  const auto name = [&](int j) { return sk.joint_names[j]; };

  // Ball joints of the torso.
  const std::array<std::pair<Bone, float>, 4> balls = {std::pair{Bone::kSpine, l.spine},
                                                       {Bone::kChest, l.chest},
                                                       {Bone::kNeck, l.neck},
                                                       {Bone::kHead, l.head}};
  for (const auto& [bone, limit] : balls) {
    const int j = s.rig[bone];
    if (j >= 0 && angle_of(deviation(j)) > above(limit)) {
      std::ostringstream why;
      why << name(j) << " turned " << angle_of(deviation(j)) << " rad > " << limit;
      return why.str();
    }
  }
  // Joints IK never drives stay at rest.
  for (int j = 0; j < sk.joint_count(); ++j) {
    bool driven = false;
    for (int b = 0; b < kBoneCount; ++b) {
      const Bone bone = static_cast<Bone>(b);
      driven |= s.rig.joint[b] == j && bone != Bone::kHips && bone != Bone::kLeftShoulder &&
                bone != Bone::kRightShoulder;
    }
    if (!driven && angle_of(deviation(j)) > kAngleSlack) {
      std::ostringstream why;
      why << name(j) << " is not driven by IK but left its rest pose";
      return why.str();
    }
  }
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const ArmRig& a = s.arms[index(h)];
    const Vec3 S = model[a.upper].translation;
    const Vec3 E = model[a.lower].translation;
    const Vec3 W = model[a.hand].translation;
    // Elbow flexion from positions: the angle between the two bones.
    const double flexion = std::acos(std::clamp(
        (E - S).normalized().cast<double>().dot((W - E).normalized().cast<double>()), -1.0, 1.0));
    if (flexion < below(l.elbow.min) || flexion > above(l.elbow.max)) {
      std::ostringstream why;
      why << name(a.lower) << " flexion " << flexion << " rad outside [" << l.elbow.min << ", "
          << l.elbow.max << "]";
      return why.str();
    }
    // Forearm twist about its rest axis (its hinge swing is perpendicular to it).
    const Vec3 E0 = s.rest_model[a.lower].translation;
    const Vec3 W0 = s.rest_model[a.hand].translation;
    const Eigen::Vector3d distal = (W0 - E0).normalized().cast<double>();
    const Eigen::Vector3d forearm_axis =
        to_double(s.rest_model[a.lower].rotation).transpose() * distal;
    const double twist = twist_swing(deviation(a.lower), forearm_axis).twist;
    const double supination = h == Hand::kRight ? twist : -twist;
    if (supination > above(l.supination) || -supination > above(l.pronation)) {
      std::ostringstream why;
      why << name(a.lower) << " supination " << supination << " rad outside [-" << l.pronation
          << ", " << l.supination << "]";
      return why.str();
    }
    // Wrist: swing off the forearm axis and residual twist.
    const Eigen::Vector3d hand_axis = to_double(s.rest_model[a.hand].rotation).transpose() * distal;
    const TwistSwing wrist = twist_swing(deviation(a.hand), hand_axis);
    if (wrist.swing > above(l.wrist_swing) || std::abs(wrist.twist) > above(l.wrist_twist)) {
      std::ostringstream why;
      why << name(a.hand) << " swing " << wrist.swing << " twist " << wrist.twist
          << " rad beyond the wrist's limits";
      return why.str();
    }
    // Index joints: pure hinges within their flexion ranges.
    for (int k = 0; k < a.index_count; ++k) {
      const int j = a.index[k];
      const TwistSwing finger = twist_swing(deviation(j), a.index_axes[k].cast<double>());
      if (finger.swing > kAngleSlack || finger.twist < below(l.index[k].min) ||
          finger.twist > above(l.index[k].max)) {
        std::ostringstream why;
        why << name(j) << " flexion " << finger.twist << " swing " << finger.swing
            << " rad outside its hinge range";
        return why.str();
      }
    }
  }
  // Eyes: the line of sight in the face's frame.
  const int head = s.rig[Bone::kHead];
  const Eigen::Matrix3d face =
      to_double(model[head].rotation) * to_double(s.rest_model[head].rotation).transpose();
  for (int e = 0; e < s.eye_count; ++e) {
    const int j = s.eyes[e];
    const Eigen::Vector3d forward_local =
        to_double(s.rest_model[j].rotation).transpose() * Eigen::Vector3d(0, 0, -1);
    const Eigen::Vector3d g = face.transpose() * to_double(model[j].rotation) * forward_local;
    const double yaw = std::atan2(-g.x(), -g.z());
    const double pitch = std::atan2(g.y(), std::hypot(g.x(), g.z()));
    if (std::abs(yaw) > above(l.eyes.yaw) || pitch > above(l.eyes.up) ||
        -pitch > above(l.eyes.down)) {
      std::ostringstream why;
      why << name(j) << " yaw " << yaw << " pitch " << pitch << " rad outside the eyes' range";
      return why.str();
    }
  }
  return {};
}

}  // namespace deixis::ik::testing
