#include "capture/motion.h"

#include <cmath>
#include <numbers>

namespace deixis::capture {

namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

Mat3 axis_angle(const Vec3& axis, float angle) {
  return Eigen::AngleAxisf(angle, axis).toRotationMatrix();
}

}  // namespace

Vec3 slerp_direction(const Vec3& a, const Vec3& b, float s) {
  const float d = std::clamp(a.dot(b), -1.0f, 1.0f);
  const float theta = std::acos(d);
  if (theta < 1e-4f) {
    return (a + s * (b - a)).normalized();
  }
  Vec3 axis = a.cross(b);
  if (axis.norm() < 1e-6f) {  // opposite: turn about any perpendicular axis
    axis = a.unitOrthogonal();
  }
  return axis_angle(axis.normalized(), s * theta) * a;
}

Mat3 look_rotation(const Vec3& forward, const Vec3& up) {
  const Vec3 z = -forward.normalized();
  Vec3 x = up.cross(z);
  if (x.norm() < 1e-4f) {  // looking straight up or down
    x = Vec3::UnitX();
  }
  x.normalize();
  Mat3 R;
  R.col(0) = x;
  R.col(1) = z.cross(x);
  R.col(2) = z;
  return R;
}

Motion::Motion(const Body& body, const Pose& T_world_stance, Random& rng)
    : torso(TorsoKey{}),
      head(HeadKey{}),
      gaze(GazeKey{}),
      hands{Track<HandKey>(HandKey{body.rest_wrist_in_torso[0]}),
            Track<HandKey>(HandKey{body.rest_wrist_in_torso[1]})},
      body_(&body),
      T_world_stance_(T_world_stance) {
  // Quiet standing sway: centre-of-pressure excursions of a few millimetres at 0.1–0.6 Hz
  // (Winter 1995), larger front–back than sideways; the head drifts by a fraction of a degree.
  const float sway = body.subject.style.sway;
  const std::array<float, 3> axis_amplitude = {0.0025f * sway, 0.0006f * sway, 0.0035f * sway};
  for (int axis = 0; axis < 3; ++axis) {
    for (Wave& w : sway_[axis]) {
      w = {axis_amplitude[axis] * rng.uniform(0.4f, 1.0f), kTwoPi * rng.uniform(0.08f, 0.6f),
           rng.uniform(0.0f, kTwoPi)};
    }
  }
  for (auto& waves : drift_) {
    for (Wave& w : waves) {
      w = {0.004f * rng.uniform(0.5f, 1.0f), kTwoPi * rng.uniform(0.1f, 0.5f),
           rng.uniform(0.0f, kTwoPi)};
    }
  }
}

Vec3 Motion::sway(double t) const {
  Vec3 out = Vec3::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    for (const Wave& w : sway_[axis]) {
      out[axis] += w.amplitude * std::sin(w.omega * static_cast<float>(t) + w.phase);
    }
  }
  return out;
}

Mat3 Motion::drift(double t) const {
  float yaw = 0;
  float pitch = 0;
  for (const Wave& w : drift_[0]) {
    yaw += w.amplitude * std::sin(w.omega * static_cast<float>(t) + w.phase);
  }
  for (const Wave& w : drift_[1]) {
    pitch += w.amplitude * std::sin(w.omega * static_cast<float>(t) + w.phase);
  }
  return axis_angle(Vec3::UnitY(), yaw) * axis_angle(Vec3::UnitX(), pitch);
}

Pose Motion::torso_pose(const TorsoKey& k) const {
  const Mat3 R = axis_angle(Vec3::UnitY(), k.twist) * axis_angle(Vec3::UnitX(), -k.lean) *
                 axis_angle(Vec3::UnitZ(), -k.side);
  return compose(T_world_stance_, Pose{R, body_->hip_in_stance});
}

Mat3 Motion::head_rotation(const HeadKey& k, const Pose& T_world_torso) const {
  const Mat3 R = k.rotation.toRotationMatrix();
  return k.torso_relative ? Mat3(T_world_torso.rotation * R) : R;
}

Pose Motion::wrist_pose(const HandKey& k, Hand hand, const Pose& T_world_torso,
                        const Vec3& dominant_eye) const {
  Pose p = k.torso_relative ? compose(T_world_torso, k.pose) : k.pose;
  if (k.servo) {
    const Vec3 ray = (k.servo_target - dominant_eye).normalized();
    p.translation += dominant_eye + k.servo_distance * ray - fingertip(*body_, hand, p);
  }
  return p;
}

Posture Motion::posture_at(double t) const {
  Posture p;
  {
    const auto s = torso.at(t);
    const Pose a = torso_pose(*s.from);
    const Pose b = torso_pose(*s.to);
    const float u = static_cast<float>(s.s);
    p.T_world_torso.rotation = Quat(a.rotation).slerp(u, Quat(b.rotation)).toRotationMatrix();
    p.T_world_torso.translation =
        a.translation + u * (b.translation - a.translation) + T_world_stance_.rotation * sway(t);
  }
  {
    const auto s = head.at(t);
    const Quat a(head_rotation(*s.from, p.T_world_torso));
    const Quat b(head_rotation(*s.to, p.T_world_torso));
    p.R_world_head = a.slerp(static_cast<float>(s.s), b).toRotationMatrix() * drift(t);
  }
  const Vec3 H = head_position(*body_, p.T_world_torso, p.R_world_head);
  {
    const auto s = gaze.at(t);
    auto resolve = [&](const GazeKey& k) {
      return k.head_relative ? Vec3((p.R_world_head * k.value).normalized())
                             : Vec3((k.value - H).normalized());
    };
    Vec3 g = slerp_direction(resolve(*s.from), resolve(*s.to), static_cast<float>(s.s));
    // The eyes cannot turn further than their range: beyond it gaze waits for the head.
    const Vec3 ahead = p.R_world_head * Vec3(0, 0, -1);
    const float off = std::acos(std::clamp(g.dot(ahead), -1.0f, 1.0f));
    if (off > kEyeRange) {
      g = slerp_direction(ahead, g, kEyeRange / off);
    }
    p.gaze = g;
  }
  const Vec3 eye = eye_position(*body_, p.T_world_torso, p.R_world_head, dominant_eye());
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const auto s = hands[index(h)].at(t);
    const Pose a = wrist_pose(*s.from, h, p.T_world_torso, eye);
    const Pose b = wrist_pose(*s.to, h, p.T_world_torso, eye);
    const float u = static_cast<float>(s.s);
    const float bend = std::sin(std::numbers::pi_v<float> * u);
    p.T_world_wrist[index(h)] =
        Pose{Quat(a.rotation).slerp(u, Quat(b.rotation)).toRotationMatrix(),
             a.translation + u * (b.translation - a.translation) + bend * s.to->bulge};
  }
  return p;
}

}  // namespace deixis::capture
