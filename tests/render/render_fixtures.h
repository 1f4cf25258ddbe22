#pragma once
// Scenes and pixel checks shared by the render tests: a two-bone skinned arm (a capsule-like
// tube from shoulder through elbow to wrist), a camera that sees it, and counts of pixels that
// match a colour. Checks look for where things are, never for byte-equal images.

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "ik/skeleton.h"
#include "render/camera.h"
#include "render/image.h"
#include "render/primitives.h"
#include "render/scene.h"

namespace deixis::render::testing {

inline constexpr int kWidth = 320;
inline constexpr int kHeight = 240;
inline const Vec3 kShoulder(0.0f, 1.2f, 0.0f);
inline constexpr float kUpperArm = 0.35f;
inline constexpr float kForearm = 0.30f;
inline constexpr float kArmRadius = 0.06f;

// Shoulder (root) → elbow → wrist, the arm straight along +X in the rest pose.
inline ik::Skeleton arm_skeleton() {
  ik::Skeleton s;
  s.joint_names = {"shoulder", "elbow", "wrist"};
  s.parents = {ik::kNoParent, 0, 1};
  s.rest_local = {Pose{Mat3::Identity(), kShoulder}, Pose{Mat3::Identity(), Vec3(kUpperArm, 0, 0)},
                  Pose{Mat3::Identity(), Vec3(kForearm, 0, 0)}};
  return s;
}

inline SkinnedMesh arm_mesh(const ik::Skeleton& skeleton) {
  const int chain[] = {0, 1, 2};
  TubeOptions options;
  options.radius = kArmRadius;
  options.rings_per_bone = 6;
  options.segments = 12;
  options.colour = Colour(0.9f, 0.55f, 0.2f, 1.0f);
  return skinned_tube(skeleton, chain, options);
}

// T_model_joint with the shoulder and elbow turned by the given local rotations.
inline std::vector<Pose> arm_pose(const ik::Skeleton& skeleton, const Mat3& shoulder,
                                  const Mat3& elbow) {
  std::vector<Pose> local = skeleton.rest_local;
  local[0].rotation = shoulder;
  local[1].rotation = elbow;
  std::vector<Pose> model(local.size());
  ik::local_to_model(skeleton, local, model);
  return model;
}

inline Mat3 about_y(float angle) {
  return Eigen::AngleAxisf(angle, Vec3::UnitY()).toRotationMatrix();
}
inline Mat3 about_z(float angle) {
  return Eigen::AngleAxisf(angle, Vec3::UnitZ()).toRotationMatrix();
}

// 2.5 m in front of the shoulder, level with it, 60° vertical field of view.
inline Camera front_camera() {
  return look_at(Vec3(0.0f, 1.2f, 2.5f), kShoulder,
                 symmetric_fov(1.0471976f, static_cast<float>(kWidth) / kHeight));
}

using Rgb = std::array<std::uint8_t, 3>;

inline Rgb to_rgb(const Colour& c) {
  return {static_cast<std::uint8_t>(std::lround(c.x() * 255.0f)),
          static_cast<std::uint8_t>(std::lround(c.y() * 255.0f)),
          static_cast<std::uint8_t>(std::lround(c.z() * 255.0f))};
}

inline bool near(const Rgb& a, const Rgb& b, int tolerance) {
  for (int k = 0; k < 3; ++k) {
    if (std::abs(int{a[k]} - int{b[k]}) > tolerance) {
      return false;
    }
  }
  return true;
}

// True when the pixel's colour is `base` scaled by some brightness (white light keeps the hue):
// the angle between them as RGB vectors is small.
inline bool same_hue(const Rgb& pixel, const Colour& base, float min_cosine = 0.99f) {
  const Eigen::Vector3f p(pixel[0], pixel[1], pixel[2]);
  const Eigen::Vector3f b = base.head<3>();
  if (p.norm() < 20.0f) {
    return false;  // too dark to have a hue
  }
  return p.normalized().dot(b.normalized()) >= min_cosine;
}

struct Region {
  int x0, y0, x1, y1;  // [x0, x1) × [y0, y1), clipped to the image
};

inline int count_pixels(const Image& image, Region r, const std::function<bool(const Rgb&)>& test) {
  int n = 0;
  for (int y = std::max(r.y0, 0); y < std::min(r.y1, image.height); ++y) {
    for (int x = std::max(r.x0, 0); x < std::min(r.x1, image.width); ++x) {
      n += test(image.pixel(x, y)) ? 1 : 0;
    }
  }
  return n;
}

inline Region whole(const Image& image) {
  return {0, 0, image.width, image.height};
}

// The pixel under a world point (which must be in front of the camera).
inline Rgb pixel_at(const Image& image, const Camera& camera, const Vec3& p_world) {
  const auto p = project_to_pixel(camera, image.width, image.height, p_world);
  EXPECT_TRUE(p.has_value());
  const int x = std::clamp(static_cast<int>(p->x()), 0, image.width - 1);
  const int y = std::clamp(static_cast<int>(p->y()), 0, image.height - 1);
  return image.pixel(x, y);
}

}  // namespace deixis::render::testing
