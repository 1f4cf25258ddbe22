#include "sim/sim_pick.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace deixis::sim {

namespace {

std::optional<float> sphere_hit(const render::Ray& ray, const Vec3& centre, float radius) {
  const Vec3 to_centre = centre - ray.origin;
  const float along = to_centre.dot(ray.direction);
  const float miss_squared = to_centre.squaredNorm() - along * along;
  const float r_squared = radius * radius;
  if (miss_squared > r_squared) {
    return std::nullopt;
  }
  const float half_chord = std::sqrt(r_squared - miss_squared);
  const float entry = along - half_chord;
  const float exit = along + half_chord;
  if (exit < 0.0f) {
    return std::nullopt;
  }
  return std::max(entry, 0.0f);
}

// The slab method: the ray is inside the box between the latest entry and the earliest exit over
// the three axes.
std::optional<float> box_hit(const render::Ray& ray, const Vec3& centre, const Vec3& size) {
  float entry = 0.0f;
  float exit = std::numeric_limits<float>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const float lo = centre[axis] - 0.5f * size[axis];
    const float hi = centre[axis] + 0.5f * size[axis];
    const float o = ray.origin[axis];
    const float d = ray.direction[axis];
    if (std::abs(d) < 1e-9f) {
      if (o < lo || o > hi) {
        return std::nullopt;
      }
      continue;
    }
    float t0 = (lo - o) / d;
    float t1 = (hi - o) / d;
    if (t0 > t1) {
      std::swap(t0, t1);
    }
    entry = std::max(entry, t0);
    exit = std::min(exit, t1);
    if (entry > exit) {
      return std::nullopt;
    }
  }
  return entry;
}

}  // namespace

std::optional<float> ray_hit(const render::Ray& ray, const TargetObject& object) {
  if (object.kind == TargetKind::kSphere) {
    return sphere_hit(ray, object.position, 0.5f * object.size.x());
  }
  return box_hit(ray, object.position, object.size);
}

TargetId pick_object(const render::Ray& ray, const TargetMap& map) {
  TargetId nearest = kNoTarget;
  float best = std::numeric_limits<float>::infinity();
  for (const TargetObject& object : map.objects) {
    const std::optional<float> hit = ray_hit(ray, object);
    if (hit && *hit < best) {
      best = *hit;
      nearest = object.id;
    }
  }
  return nearest;
}

std::optional<Vec3> ray_at_height(const render::Ray& ray, float y, float max_distance) {
  if (std::abs(ray.direction.y()) < 1e-6f) {
    return std::nullopt;
  }
  const float t = (y - ray.origin.y()) / ray.direction.y();
  if (t <= 0.0f || t > max_distance) {
    return std::nullopt;
  }
  return ray.origin + t * ray.direction;
}

}  // namespace deixis::sim
