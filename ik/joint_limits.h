#pragma once
// The range of motion of every joint IK drives, and how it is measured. All limits are relative
// to the joint's rest (bind) pose, which Deixis assumes is a T-pose or A-pose facing −Z with palms
// down (VRM and Mixamo rigs are; docs/ik.md). Angles are radians; the defaults are anatomical
// ranges rounded to 5°, chosen so that a pointing, looking, gesturing person stays inside them.
//
//   spine, chest, neck, head  ball joints: total rotation away from rest ≤ max angle
//   elbow                     hinge: flexion (0 = straight) in [min, max]
//   forearm                   twist about the elbow→wrist axis: pronation/supination from rest
//   wrist                     swing of the hand off the forearm axis ≤ cone; small residual twist
//   index finger joints       hinges: flexion toward the palm in [min, max]
//   eyes                      yaw and pitch of the line of sight relative to the face
//   shoulder (upper arm)      unlimited: pointing covers the whole sphere around the shoulder
//   clavicle, hips            not driven (stay at rest, so the legs never swing)

#include <array>
#include <string_view>

#include "ik/rotations.h"

namespace deixis::ik {

struct HingeRange {
  float min = 0.0f;  // rad
  float max = 0.0f;  // rad
};

struct EyeRange {
  float yaw = deg(35.0f);   // left and right of straight ahead
  float up = deg(25.0f);    // above straight ahead
  float down = deg(35.0f);  // below straight ahead
};

struct IkLimits {
  // Ball joints of the torso and neck: largest rotation away from rest.
  float spine = deg(20.0f);
  float chest = deg(25.0f);
  float neck = deg(40.0f);
  float head = deg(45.0f);
  HingeRange elbow{0.0f, deg(145.0f)};  // flexion
  float pronation = deg(45.0f);         // forearm twist beyond the palms-down rest
  float supination = deg(135.0f);       // forearm twist toward palm up (thumb up at 90°)
  float wrist_swing = deg(70.0f);       // flexion/extension and deviation, as one cone
  float wrist_twist = deg(10.0f);       // twist left to the hand after the forearm's share
  std::array<HingeRange, 3> index = {HingeRange{deg(-10.0f), deg(90.0f)},
                                     HingeRange{0.0f, deg(100.0f)}, HingeRange{0.0f, deg(80.0f)}};
  EyeRange eyes;
};

// Empty when the limits are usable (every angle in [0, π], every range ordered); otherwise the
// name of the first bad field.
std::string_view check(const IkLimits& limits);

// The rotation of a joint away from its rest pose, in its own rest frame: local = rest · D.
inline Mat3 rest_deviation(const Mat3& local, const Mat3& rest_local) {
  return rest_local.transpose() * local;
}

// `local` with its rest deviation clamped to `max_angle` (ball joint).
Mat3 clamp_to_rest(const Mat3& local, const Mat3& rest_local, float max_angle);

}  // namespace deixis::ik
