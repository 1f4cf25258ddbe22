// Cameras as OpenXR describes views: pose and four FOV angles, to view and projection matrices
// and to pixels.

#include <gtest/gtest.h>

#include <cmath>

#include "render/camera.h"

namespace deixis::render {
namespace {

constexpr float kPi = 3.14159265f;

TEST(CameraTest, LookAtLooksAlongMinusZOfTheEye) {
  const Camera camera = look_at(Vec3(1, 2, 3), Vec3(1, 2, 0), symmetric_fov(1.0f, 1.0f));
  EXPECT_TRUE(camera.T_world_eye.rotation.isIdentity(1e-6f));
  const Camera side = look_at(Vec3(0, 0, 0), Vec3(5, 0, 0), symmetric_fov(1.0f, 1.0f));
  EXPECT_TRUE((side.T_world_eye.rotation * -Vec3::UnitZ()).isApprox(Vec3::UnitX(), 1e-6f));
  EXPECT_TRUE((side.T_world_eye.rotation * Vec3::UnitY()).isApprox(Vec3::UnitY(), 1e-6f));
  EXPECT_NEAR(side.T_world_eye.rotation.determinant(), 1.0f, 1e-6f);
}

TEST(CameraTest, ViewMatrixIsTheInverseOfTheEyePose) {
  Camera camera;
  camera.T_world_eye = {Eigen::AngleAxisf(0.7f, Vec3(1, 2, 3).normalized()).toRotationMatrix(),
                        Vec3(0.3f, 1.6f, -2.0f)};
  const Vec3 p(0.5f, -0.2f, 4.0f);
  const Vec3 expected = transform_point(inverse(camera.T_world_eye), p);
  const Vec4 got = view_matrix(camera) * p.homogeneous();
  EXPECT_TRUE(got.head<3>().isApprox(expected, 1e-5f));
  EXPECT_FLOAT_EQ(got.w(), 1.0f);
}

TEST(CameraTest, ProjectionMapsTheFrustumEdgesToClipSpaceEdges) {
  const Fov fov{-0.6f, 0.3f, 0.5f, -0.4f};  // asymmetric, as an XR eye's
  const float near_distance = 0.1f;
  const float far_distance = 50.0f;
  const Mat4 p = projection_matrix(fov, near_distance, far_distance);
  const auto ndc = [&](const Vec3& v) {
    const Vec4 c = p * v.homogeneous();
    return Vec3(c.head<3>() / c.w());
  };
  const float d = 3.0f;
  EXPECT_NEAR(ndc(Vec3(d * std::tan(fov.angle_left), 0, -d)).x(), -1.0f, 1e-5f);
  EXPECT_NEAR(ndc(Vec3(d * std::tan(fov.angle_right), 0, -d)).x(), 1.0f, 1e-5f);
  EXPECT_NEAR(ndc(Vec3(0, d * std::tan(fov.angle_up), -d)).y(), 1.0f, 1e-5f);
  EXPECT_NEAR(ndc(Vec3(0, d * std::tan(fov.angle_down), -d)).y(), -1.0f, 1e-5f);
  EXPECT_NEAR(ndc(Vec3(0, 0, -near_distance)).z(), -1.0f, 1e-4f);
  EXPECT_NEAR(ndc(Vec3(0, 0, -far_distance)).z(), 1.0f, 1e-4f);
}

TEST(CameraTest, SymmetricFovKeepsTheAspect) {
  const Fov fov = symmetric_fov(kPi / 3, 16.0f / 9.0f);
  EXPECT_NEAR(fov.angle_up, kPi / 6, 1e-6f);
  EXPECT_NEAR(fov.angle_down, -kPi / 6, 1e-6f);
  EXPECT_NEAR(std::tan(fov.angle_right) / std::tan(fov.angle_up), 16.0f / 9.0f, 1e-5f);
  EXPECT_NEAR(fov.angle_left, -fov.angle_right, 1e-7f);
}

TEST(CameraTest, ProjectToPixelPutsRowZeroAtTheTop) {
  const Camera camera = look_at(Vec3(0, 1, 5), Vec3(0, 1, 0), symmetric_fov(kPi / 2, 2.0f));
  const auto centre = project_to_pixel(camera, 200, 100, Vec3(0, 1, 0));
  ASSERT_TRUE(centre.has_value());
  EXPECT_NEAR(centre->x(), 100.0f, 1e-3f);
  EXPECT_NEAR(centre->y(), 50.0f, 1e-3f);
  const auto up_right = project_to_pixel(camera, 200, 100, Vec3(1, 2, 0));
  ASSERT_TRUE(up_right.has_value());
  EXPECT_GT(up_right->x(), 100.0f);
  EXPECT_LT(up_right->y(), 50.0f);
  // tan(45°) · 5 m is the top edge at that distance.
  EXPECT_NEAR(project_to_pixel(camera, 200, 100, Vec3(0, 6, 0))->y(), 0.0f, 1e-3f);
  EXPECT_FALSE(project_to_pixel(camera, 200, 100, Vec3(0, 1, 6)).has_value());  // behind
}

TEST(CameraTest, PixelRayGoesBackThroughTheProjectedPoint) {
  Camera camera;  // asymmetric, turned and tilted, as an XR eye's
  camera.T_world_eye = {
      Eigen::AngleAxisf(0.5f, Vec3(0.2f, 1, 0.1f).normalized()).toRotationMatrix(),
      Vec3(0.4f, 1.6f, 2.0f)};
  camera.fov = Fov{-0.6f, 0.3f, 0.5f, -0.4f};
  for (const Vec3& p : {Vec3(0, 1, -2), Vec3(-1.5f, 0.2f, -4), Vec3(0.8f, 2.5f, -1)}) {
    const auto pixel = project_to_pixel(camera, 320, 240, p);
    ASSERT_TRUE(pixel.has_value());
    const Ray ray = pixel_ray(camera, 320, 240, *pixel);
    EXPECT_TRUE(ray.origin.isApprox(camera.T_world_eye.translation));
    EXPECT_NEAR(ray.direction.norm(), 1.0f, 1e-6f);
    EXPECT_TRUE(ray.direction.isApprox((p - ray.origin).normalized(), 1e-5f)) << p.transpose();
  }
}

}  // namespace
}  // namespace deixis::render
