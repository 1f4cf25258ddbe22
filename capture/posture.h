#pragma once
// One instant of the motion model: where the torso, head, eyes and wrists are (the posture), the
// skeleton's joints it implies, and what a tracker reports of it (core/tracking.h).

#include <array>

#include "capture/body.h"
#include "core/tracking.h"

namespace deixis::capture {

struct Posture {
  Pose T_world_torso;  // the hip pivot
  Mat3 R_world_head = Mat3::Identity();
  Vec3 gaze = Vec3(0, 0, -1);         // combined gaze, unit, world
  std::array<Pose, 2> T_world_wrist;  // by Hand
};

// Joint positions (world) of the stick figure. Bone lengths are the body's by construction as
// long as the wrists are within reach (tests/capture/motion_test.cpp checks every frame).
struct Joints {
  Vec3 hip = Vec3::Zero();
  Vec3 neck = Vec3::Zero();   // head pivot
  Vec3 head = Vec3::Zero();   // H, the eyes' midpoint
  std::array<Vec3, 2> eye{};  // by Eye
  std::array<Vec3, 2> shoulder{};
  std::array<Vec3, 2> elbow{};
  std::array<Vec3, 2> wrist{};
  std::array<Vec3, 2> tip{};
};

Vec3 head_position(const Body& body, const Pose& T_world_torso, const Mat3& R_world_head);
Vec3 eye_position(const Body& body, const Pose& T_world_torso, const Mat3& R_world_head, Eye eye);
Vec3 shoulder_position(const Body& body, const Pose& T_world_torso, Hand hand);
Vec3 fingertip(const Body& body, Hand hand, const Pose& T_world_wrist);

// The elbow of a two-bone arm (shoulder → elbow → wrist) bent toward `pole` (world direction).
Vec3 solve_elbow(const Vec3& shoulder, const Vec3& wrist, float upper, float fore,
                 const Vec3& pole);

Joints solve_joints(const Body& body, const Posture& posture);

// What a perfect tracker reports: head pose at H, combined gaze, wrists and fingertips, all
// valid. Targets are filled in by the caller.
TrackingFrame track(const Posture& posture, const Joints& joints);

}  // namespace deixis::capture
