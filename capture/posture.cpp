#include "capture/posture.h"

#include <algorithm>
#include <cmath>

namespace deixis::capture {

Vec3 head_position(const Body& body, const Pose& T_world_torso, const Mat3& R_world_head) {
  return transform_point(T_world_torso, body.neck_in_torso) + R_world_head * body.eyes_in_head;
}

Vec3 eye_position(const Body& body, const Pose& T_world_torso, const Mat3& R_world_head, Eye eye) {
  const float side = eye == Eye::kRight ? 0.5f : -0.5f;
  return head_position(body, T_world_torso, R_world_head) +
         R_world_head * Vec3(side * body.eye_separation, 0, 0);
}

Vec3 shoulder_position(const Body& body, const Pose& T_world_torso, Hand hand) {
  return transform_point(T_world_torso, body.shoulder_in_torso[index(hand)]);
}

Vec3 fingertip(const Body& body, Hand hand, const Pose& T_world_wrist) {
  return transform_point(T_world_wrist, body.tip_in_wrist[index(hand)]);
}

Vec3 solve_elbow(const Vec3& shoulder, const Vec3& wrist, float upper, float fore,
                 const Vec3& pole) {
  const Vec3 to_wrist = wrist - shoulder;
  const float c = to_wrist.norm();
  const Vec3 axis = c > 1e-6f ? Vec3(to_wrist / c) : Vec3(0, -1, 0);
  // Law of cosines for the angle at the shoulder; a wrist out of reach straightens the arm (the
  // planner never asks for that, and the bone-length test would see it).
  const float cos_a =
      std::clamp((upper * upper + c * c - fore * fore) / (2 * upper * c), -1.0f, 1.0f);
  Vec3 bend = pole - pole.dot(axis) * axis;
  if (bend.norm() < 1e-6f) {
    bend = axis.unitOrthogonal();
  }
  return shoulder + upper * (cos_a * axis + std::sqrt(1 - cos_a * cos_a) * bend.normalized());
}

Joints solve_joints(const Body& body, const Posture& p) {
  Joints j;
  j.hip = p.T_world_torso.translation;
  j.neck = transform_point(p.T_world_torso, body.neck_in_torso);
  j.head = j.neck + p.R_world_head * body.eyes_in_head;
  for (const Eye e : {Eye::kLeft, Eye::kRight}) {
    j.eye[static_cast<int>(e)] = eye_position(body, p.T_world_torso, p.R_world_head, e);
  }
  for (const Hand h : {Hand::kLeft, Hand::kRight}) {
    const int i = index(h);
    const float side = h == Hand::kRight ? 1.0f : -1.0f;
    j.shoulder[i] = shoulder_position(body, p.T_world_torso, h);
    j.wrist[i] = p.T_world_wrist[i].translation;
    j.tip[i] = fingertip(body, h, p.T_world_wrist[i]);
    // Elbows hang down, a little out and back.
    const Vec3 pole = p.T_world_torso.rotation * Vec3(0.5f * side, -1.0f, 0.4f);
    j.elbow[i] = solve_elbow(j.shoulder[i], j.wrist[i], body.upper_arm, body.forearm, pole);
  }
  return j;
}

TrackingFrame track(const Posture& p, const Joints& j) {
  TrackingFrame f;
  f.T_world_head = Pose{p.R_world_head, j.head};
  f.gaze = p.gaze;
  f.T_world_wrist = p.T_world_wrist;
  f.index_tip = j.tip;
  f.valid = tracked::kAll;
  return f;
}

}  // namespace deixis::capture
