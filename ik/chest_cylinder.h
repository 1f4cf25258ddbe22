#pragma once
// The elliptic cylinder around the chest that the non-deictic hand must stay out of (paper
// §IV.C: the hand keeps the user's azimuth, elevation and distance from the head, which alone
// lets it pass through the torso; it is projected to the cylinder's boundary instead).
//
// The cylinder's frame rides on the chest joint; in the rest pose its y axis is model +Y (the
// axis), x points to the avatar's right and z backward. Its cross-section is an ellipse with
// semi-axes half_width (x) and half_depth (z); it spans bottom ≤ y ≤ top.

#include "core/math/pose.h"

namespace deixis::ik {

struct ChestCylinder {
  Pose T_chest_cylinder;     // the cylinder's frame in the chest joint's frame
  float half_width = 0.17f;  // m
  float half_depth = 0.13f;  // m
  float bottom = -0.3f;      // m, along the axis from the frame's origin
  float top = 0.2f;          // m
};

// True when `p_cylinder` (a point in the cylinder's frame) is strictly inside.
bool inside(const ChestCylinder& cylinder, const Vec3& p_cylinder);

// `p_cylinder` moved radially (from the axis, keeping its height) onto the elliptic boundary when
// it is inside; unchanged otherwise. A point on the axis goes out toward `side_x` (+1 right, −1
// left).
Vec3 project_out(const ChestCylinder& cylinder, const Vec3& p_cylinder, float side_x);

}  // namespace deixis::ik
