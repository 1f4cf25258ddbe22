#pragma once
// A camera as OpenXR describes a view: the eye's pose in the world (T_world_eye; the eye looks
// along its −Z with +Y up, the world's own convention) and four field-of-view angles, so the
// OpenXR front end passes each eye's xrLocateViews pose and XrFovf as they are, and the desktop
// and headless front ends build a symmetric one.

#include <optional>

#include <Eigen/Core>

#include "core/math/pose.h"

namespace deixis::render {

using Mat4 = Eigen::Matrix4f;  // column-major, as OpenGL reads it
using Vec2 = Eigen::Vector2f;
using Vec4 = Eigen::Vector4f;

// Angles from the view direction to each edge, in radians (XrFovf): left and down are negative
// for a view that contains its own axis.
struct Fov {
  float angle_left = -0.785398f;
  float angle_right = 0.785398f;
  float angle_up = 0.785398f;
  float angle_down = -0.785398f;
};

struct Camera {
  Pose T_world_eye;
  Fov fov;
  float near_distance = 0.05f;  // m
  float far_distance = 100.0f;  // m
};

// The symmetric field of view of a `vertical` angle (radians) on an image of `aspect` = width /
// height.
Fov symmetric_fov(float vertical, float aspect);

// A camera at `eye` looking at `target` with the world's +Y as up (`target` must not be straight
// above or below `eye`).
Camera look_at(const Vec3& eye, const Vec3& target, const Fov& fov);

// World to eye (the inverse of T_world_eye) as a 4×4 matrix.
Mat4 view_matrix(const Camera& camera);

// Eye to OpenGL clip space (z in [−w, w]) for an asymmetric frustum, as OpenXR's xr_linear.h
// builds it for OpenGL.
Mat4 projection_matrix(const Fov& fov, float near_distance, float far_distance);

// Where a world point lands in a width × height image whose row 0 is the top (as Image stores
// it): pixel centres are at integer + 0.5. Empty when the point is behind the eye.
std::optional<Vec2> project_to_pixel(const Camera& camera, int width, int height,
                                     const Vec3& p_world);

// A half-line in the world: from `origin` along the unit `direction`.
struct Ray {
  Vec3 origin = Vec3::Zero();
  Vec3 direction = Vec3(0, 0, -1);
};

// The inverse of project_to_pixel: the ray from the eye through `pixel` (same image convention),
// e.g. to find what the mouse is over.
Ray pixel_ray(const Camera& camera, int width, int height, const Vec2& pixel);

}  // namespace deixis::render
