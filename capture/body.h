#pragma once
// A subject's body as the motion model moves it: fixed bone lengths and the upright posture,
// derived from height, arm length and shoulder width with standard anthropometric proportions
// (Drillis & Contini 1966; Winter, Biomechanics and Motor Control of Human Movement, 2009).
//
// Frames (world axes as everywhere in Deixis: +Y up, −Z forward, metres):
//   stance — on the floor between the feet, yaw-only, facing −Z;
//   torso  — origin at the hip pivot; leans and twists about it; carries neck and shoulders;
//   head   — origin at the head pivot on top of the neck; H (the eyes' midpoint) is fixed in it;
//   wrist  — docs/decisions.md §7: x distal (right hand) / proximal (left), y dorsal, z ulnar.

#include <array>

#include "capture/subject.h"
#include "core/math/pose.h"

namespace deixis::capture {

struct Body {
  Subject subject;
  float hip_height = 0;                       // the torso pivot above the floor (m)
  Vec3 hip_in_stance = Vec3::Zero();          // the torso pivot in the upright posture
  Vec3 neck_in_torso = Vec3::Zero();          // the head pivot
  Vec3 eyes_in_head = Vec3::Zero();           // H relative to the head pivot
  float eye_separation = 0.063f;              // interpupillary distance (m)
  std::array<Vec3, 2> shoulder_in_torso{};    // by Hand
  float upper_arm = 0;                        // shoulder → elbow (m)
  float forearm = 0;                          // elbow → wrist (m)
  std::array<Vec3, 2> tip_in_wrist{};         // index fingertip, wrist frame, by Hand
  std::array<Pose, 2> rest_wrist_in_torso{};  // hands hanging in the upright posture

  float eye_height() const;                            // H above the floor in the upright posture
  float reach() const { return upper_arm + forearm; }  // shoulder → wrist, arm straight
};

// Validates the subject (deixis::Error on bad parameters) and derives the body.
Body make_body(const Subject& subject);

// A wrist rotation in the convention of docs/decisions.md §7 from the fingers' direction and the
// back of the hand's direction (world; need not be orthogonal).
Mat3 wrist_rotation(Hand hand, const Vec3& distal, const Vec3& dorsal);

// The wrist rotation that points the wrist → fingertip vector of `hand` along `finger` with the
// back of the hand as close to `dorsal` as that allows.
Mat3 wrist_rotation_for_finger(const Body& body, Hand hand, const Vec3& finger, const Vec3& dorsal);

}  // namespace deixis::capture
