#include "render/primitives.h"

#include <cmath>
#include <numbers>
#include <string>

#include "core/error.h"

namespace deixis::render {
namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;

std::uint32_t u32(std::size_t i) {
  return static_cast<std::uint32_t>(i);
}

// Two triangles over the quad a, b, c, d (counter-clockwise seen from outside).
void add_quad(std::vector<std::uint32_t>& indices, std::uint32_t a, std::uint32_t b,
              std::uint32_t c, std::uint32_t d) {
  indices.insert(indices.end(), {a, b, c, a, c, d});
}

Vec3 any_perpendicular(const Vec3& d) {
  const Vec3 helper = std::abs(d.x()) < 0.9f ? Vec3::UnitX() : Vec3::UnitY();
  return (helper - helper.dot(d) * d).normalized();
}

void check_chain(const ik::Skeleton& skeleton, std::span<const int> chain) {
  if (chain.size() < 2) {
    throw Error("skinned_tube: a chain needs at least 2 joints, got " +
                std::to_string(chain.size()));
  }
  for (std::size_t k = 0; k < chain.size(); ++k) {
    if (chain[k] < 0 || chain[k] >= skeleton.joint_count()) {
      throw Error("skinned_tube: chain[" + std::to_string(k) + "] = " + std::to_string(chain[k]) +
                  " is not a joint of a " + std::to_string(skeleton.joint_count()) +
                  "-joint skeleton");
    }
  }
}

// One cross-section of the tube: where it is, which way the tube runs there, and its skin
// weights.
struct Ring {
  Vec3 centre;
  Vec3 direction;
  std::array<std::uint16_t, 4> joints{};
  std::array<float, 4> weights{};
};

std::vector<Ring> tube_rings(std::span<const Vec3> points, std::span<const int> chain,
                             const TubeOptions& options) {
  const std::size_t bones = points.size() - 1;
  const int per_bone = std::max(options.rings_per_bone, 1);
  const float blend = std::clamp(options.blend_fraction, 1e-3f, 0.5f);
  std::vector<Ring> rings;
  for (std::size_t b = 0; b < bones; ++b) {
    const Vec3 along = points[b + 1] - points[b];
    if (along.norm() < 1e-6f) {
      throw Error("skinned_tube: joints " + std::to_string(chain[b]) + " and " +
                  std::to_string(chain[b + 1]) + " are at the same place in the rest pose");
    }
    for (int r = (b == 0 ? 0 : 1); r <= per_bone; ++r) {
      const float f = static_cast<float>(r) / static_cast<float>(per_bone);
      Ring ring;
      ring.centre = points[b] + f * along;
      ring.direction = along.normalized();
      const auto own = static_cast<std::uint16_t>(chain[b]);
      ring.joints = {own, own, 0, 0};
      ring.weights = {1.0f, 0.0f, 0.0f, 0.0f};
      if (b > 0 && f < blend) {  // just past an inner joint: share with the previous bone
        const float x = f / blend;
        ring.joints[1] = static_cast<std::uint16_t>(chain[b - 1]);
        ring.weights = {0.5f + 0.5f * x, 0.5f - 0.5f * x, 0.0f, 0.0f};
      } else if (b + 1 < bones && f > 1.0f - blend) {  // approaching an inner joint
        const float x = (1.0f - f) / blend;
        ring.joints[1] = static_cast<std::uint16_t>(chain[b + 1]);
        ring.weights = {0.5f + 0.5f * x, 0.5f - 0.5f * x, 0.0f, 0.0f};
        if (r == per_bone) {  // the ring at the joint itself runs along both bones
          ring.direction = (along.normalized() + (points[b + 2] - points[b + 1]).normalized());
          ring.direction =
              ring.direction.norm() > 1e-6f ? ring.direction.normalized() : along.normalized();
        }
      }
      rings.push_back(ring);
    }
  }
  return rings;
}

void add_cap(SkinnedMesh& mesh, const Ring& ring, const std::vector<Vec3>& rim, const Vec3& normal,
             bool facing_forward) {
  const auto centre = u32(mesh.positions.size());
  mesh.positions.push_back(ring.centre);
  for (const Vec3& p : rim) {
    mesh.positions.push_back(p);
  }
  for (std::size_t i = 0; i <= rim.size(); ++i) {
    mesh.normals.push_back(normal);
    mesh.joints.push_back(ring.joints);
    mesh.weights.push_back(ring.weights);
  }
  const auto n = u32(rim.size());
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::uint32_t a = centre + 1 + k;
    const std::uint32_t b = centre + 1 + (k + 1) % n;
    mesh.indices.insert(mesh.indices.end(),
                        {centre, facing_forward ? a : b, facing_forward ? b : a});
  }
}

}  // namespace

StaticMesh unit_sphere(int rings, int segments) {
  rings = std::max(rings, 2);
  segments = std::max(segments, 3);
  StaticMesh mesh;
  for (int i = 0; i <= rings; ++i) {
    const float theta =
        std::numbers::pi_v<float> * static_cast<float>(i) / static_cast<float>(rings);
    for (int k = 0; k <= segments; ++k) {
      const float phi = kTwoPi * static_cast<float>(k) / static_cast<float>(segments);
      const Vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta),
                   std::sin(theta) * std::sin(phi));
      mesh.positions.push_back(0.5f * n);
      mesh.normals.push_back(n);
    }
  }
  const auto row = u32(segments + 1);
  for (int i = 0; i < rings; ++i) {
    for (int k = 0; k < segments; ++k) {
      const std::uint32_t a = u32(i) * row + u32(k);
      const std::uint32_t b = a + 1;
      const std::uint32_t c = b + row;
      const std::uint32_t d = a + row;
      if (i > 0) {  // the top band's first triangle has both corners on the pole
        mesh.indices.insert(mesh.indices.end(), {a, b, c});
      }
      if (i + 1 < rings) {  // and the bottom band's second one
        mesh.indices.insert(mesh.indices.end(), {a, c, d});
      }
    }
  }
  return mesh;
}

StaticMesh unit_cube() {
  struct Face {
    Vec3 normal, s, t;  // s × t = normal, so s then t runs counter-clockwise seen from outside
  };
  const Face faces[] = {
      {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()}, {-Vec3::UnitX(), Vec3::UnitZ(), Vec3::UnitY()},
      {Vec3::UnitY(), Vec3::UnitZ(), Vec3::UnitX()}, {-Vec3::UnitY(), Vec3::UnitX(), Vec3::UnitZ()},
      {Vec3::UnitZ(), Vec3::UnitX(), Vec3::UnitY()}, {-Vec3::UnitZ(), Vec3::UnitY(), Vec3::UnitX()},
  };
  StaticMesh mesh;
  for (const Face& f : faces) {
    const auto first = u32(mesh.positions.size());
    for (const auto& [a, b] :
         {std::pair{-1.0f, -1.0f}, {1.0f, -1.0f}, {1.0f, 1.0f}, {-1.0f, 1.0f}}) {
      mesh.positions.push_back(0.5f * (f.normal + a * f.s + b * f.t));
      mesh.normals.push_back(f.normal);
    }
    add_quad(mesh.indices, first, first + 1, first + 2, first + 3);
  }
  return mesh;
}

SkinnedMesh skinned_tube(const ik::Skeleton& skeleton, std::span<const int> chain,
                         const TubeOptions& options) {
  check_chain(skeleton, chain);
  std::vector<Pose> rest_model(skeleton.parents.size());
  ik::local_to_model(skeleton, skeleton.rest_local, rest_model);
  std::vector<Vec3> points;
  for (const int j : chain) {
    points.push_back(rest_model[j].translation);
  }
  const std::vector<Ring> rings = tube_rings(points, chain, options);
  const int segments = std::max(options.segments, 3);

  SkinnedMesh mesh;
  Vec3 u = any_perpendicular(rings.front().direction);
  std::vector<Vec3> first_rim;
  std::vector<Vec3> last_rim;
  for (std::size_t i = 0; i < rings.size(); ++i) {
    const Ring& ring = rings[i];
    u = (u - u.dot(ring.direction) * ring.direction).normalized();  // parallel transport
    const Vec3 w = ring.direction.cross(u);
    std::vector<Vec3>& rim = i == 0 ? first_rim : last_rim;
    rim.clear();
    for (int k = 0; k < segments; ++k) {
      const float phi = kTwoPi * static_cast<float>(k) / static_cast<float>(segments);
      const Vec3 n = std::cos(phi) * u + std::sin(phi) * w;
      rim.push_back(ring.centre + options.radius * n);
      mesh.positions.push_back(rim.back());
      mesh.normals.push_back(n);
      mesh.joints.push_back(ring.joints);
      mesh.weights.push_back(ring.weights);
    }
  }
  const auto s = u32(segments);
  for (std::uint32_t i = 0; i + 1 < u32(rings.size()); ++i) {
    for (std::uint32_t k = 0; k < s; ++k) {
      add_quad(mesh.indices, i * s + k, i * s + (k + 1) % s, (i + 1) * s + (k + 1) % s,
               (i + 1) * s + k);
    }
  }
  add_cap(mesh, rings.front(), first_rim, -rings.front().direction, false);
  add_cap(mesh, rings.back(), last_rim, rings.back().direction, true);

  for (const Pose& T_model_joint : rest_model) {
    mesh.inverse_bind.push_back(inverse(T_model_joint));
  }
  SkinnedPrimitive tube;
  tube.name = "tube";
  tube.index_count = u32(mesh.indices.size());
  tube.base_color = {options.colour.x(), options.colour.y(), options.colour.z(),
                     options.colour.w()};
  mesh.primitives.push_back(tube);
  return mesh;
}

void append(SkinnedMesh& mesh, const SkinnedMesh& part) {
  const auto vertex_offset = u32(mesh.positions.size());
  const auto index_offset = u32(mesh.indices.size());
  mesh.positions.insert(mesh.positions.end(), part.positions.begin(), part.positions.end());
  mesh.normals.insert(mesh.normals.end(), part.normals.begin(), part.normals.end());
  mesh.joints.insert(mesh.joints.end(), part.joints.begin(), part.joints.end());
  mesh.weights.insert(mesh.weights.end(), part.weights.begin(), part.weights.end());
  for (const std::uint32_t i : part.indices) {
    mesh.indices.push_back(i + vertex_offset);
  }
  if (mesh.inverse_bind.empty()) {
    mesh.inverse_bind = part.inverse_bind;
  }
  if (part.primitives.empty()) {
    SkinnedPrimitive all;
    all.first_index = index_offset;
    all.index_count = u32(part.indices.size());
    mesh.primitives.push_back(all);
  }
  for (SkinnedPrimitive p : part.primitives) {
    p.first_index += index_offset;
    mesh.primitives.push_back(p);
  }
}

}  // namespace deixis::render
