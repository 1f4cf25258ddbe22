#include "render/camera.h"

#include <cmath>

namespace deixis::render {

Fov symmetric_fov(float vertical, float aspect) {
  const float half_height = std::tan(0.5f * vertical);
  const float half_width = std::atan(half_height * aspect);
  return {-half_width, half_width, 0.5f * vertical, -0.5f * vertical};
}

Camera look_at(const Vec3& eye, const Vec3& target, const Fov& fov) {
  const Vec3 back = (eye - target).normalized();  // the eye's +Z
  const Vec3 right = Vec3::UnitY().cross(back).normalized();
  const Vec3 up = back.cross(right);
  Camera camera;
  camera.T_world_eye.rotation.col(0) = right;
  camera.T_world_eye.rotation.col(1) = up;
  camera.T_world_eye.rotation.col(2) = back;
  camera.T_world_eye.translation = eye;
  camera.fov = fov;
  return camera;
}

Mat4 view_matrix(const Camera& camera) {
  const Pose T_eye_world = inverse(camera.T_world_eye);
  Mat4 view = Mat4::Identity();
  view.topLeftCorner<3, 3>() = T_eye_world.rotation;
  view.topRightCorner<3, 1>() = T_eye_world.translation;
  return view;
}

Mat4 projection_matrix(const Fov& fov, float near_distance, float far_distance) {
  const float tan_left = std::tan(fov.angle_left);
  const float tan_right = std::tan(fov.angle_right);
  const float tan_down = std::tan(fov.angle_down);
  const float tan_up = std::tan(fov.angle_up);
  const float width = tan_right - tan_left;
  const float height = tan_up - tan_down;
  const float depth = far_distance - near_distance;
  Mat4 p = Mat4::Zero();
  p(0, 0) = 2.0f / width;
  p(0, 2) = (tan_right + tan_left) / width;
  p(1, 1) = 2.0f / height;
  p(1, 2) = (tan_up + tan_down) / height;
  p(2, 2) = -(far_distance + near_distance) / depth;
  p(2, 3) = -2.0f * far_distance * near_distance / depth;
  p(3, 2) = -1.0f;
  return p;
}

std::optional<Vec2> project_to_pixel(const Camera& camera, int width, int height,
                                     const Vec3& p_world) {
  const Vec3 p_eye = transform_point(inverse(camera.T_world_eye), p_world);
  if (p_eye.z() >= 0.0f) {
    return std::nullopt;
  }
  const Vec4 clip = projection_matrix(camera.fov, camera.near_distance, camera.far_distance) *
                    p_eye.homogeneous();
  const float ndc_x = clip.x() / clip.w();
  const float ndc_y = clip.y() / clip.w();
  return Vec2(0.5f * (ndc_x + 1.0f) * static_cast<float>(width),
              0.5f * (1.0f - ndc_y) * static_cast<float>(height));
}

Ray pixel_ray(const Camera& camera, int width, int height, const Vec2& pixel) {
  // The pixel's point on the plane one metre in front of the eye, between the frustum's edges.
  const float u = pixel.x() / static_cast<float>(width);
  const float v = 1.0f - pixel.y() / static_cast<float>(height);
  const float tan_left = std::tan(camera.fov.angle_left);
  const float tan_down = std::tan(camera.fov.angle_down);
  const Vec3 p_eye(tan_left + u * (std::tan(camera.fov.angle_right) - tan_left),
                   tan_down + v * (std::tan(camera.fov.angle_up) - tan_down), -1.0f);
  return {camera.T_world_eye.translation, (camera.T_world_eye.rotation * p_eye).normalized()};
}

}  // namespace deixis::render
