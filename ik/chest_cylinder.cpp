#include "ik/chest_cylinder.h"

#include <cmath>

namespace deixis::ik {
namespace {

// (x/a)² + (z/b)²: below 1 inside the ellipse.
float ellipse_level(const ChestCylinder& c, const Vec3& p) {
  const float x = p.x() / c.half_width;
  const float z = p.z() / c.half_depth;
  return x * x + z * z;
}

}  // namespace

bool inside(const ChestCylinder& cylinder, const Vec3& p) {
  return p.y() > cylinder.bottom && p.y() < cylinder.top && ellipse_level(cylinder, p) < 1.0f;
}

Vec3 project_out(const ChestCylinder& cylinder, const Vec3& p, float side_x) {
  if (!inside(cylinder, p)) {
    return p;
  }
  const float level = ellipse_level(cylinder, p);
  if (level < 1e-8f) {
    return {side_x >= 0.0f ? cylinder.half_width : -cylinder.half_width, p.y(), 0.0f};
  }
  // Scaling (x, z) by 1/√level puts the point on the ellipse along the ray from the axis.
  const float s = 1.0f / std::sqrt(level);
  return {p.x() * s, p.y(), p.z() * s};
}

}  // namespace deixis::ik
