#include "avatar/shapes.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "avatar/influences.h"

namespace deixis::avatar {

namespace {

// Angles come from double-precision trigonometry rounded to float, so that the generated file is
// the same on every build of the same library (decisions.md: deterministic avatar).
float cos_of(double angle) {
  return static_cast<float>(std::cos(angle));
}
float sin_of(double angle) {
  return static_cast<float>(std::sin(angle));
}

}  // namespace

SegmentWeights rigid(int joint) {
  SegmentWeights w;
  w.joint = joint;
  return w;
}

ShapeFrame segment_frame(const Vec3& from, const Vec3& to, const Vec3& side) {
  const Vec3 y = (to - from).normalized();
  Vec3 x = side - side.dot(y) * y;
  x.normalize();
  ShapeFrame frame;
  frame.axes.col(0) = x;
  frame.axes.col(1) = y;
  frame.axes.col(2) = x.cross(y);
  frame.origin = from;
  return frame;
}

int MeshBuilder::add_material(std::string name, const std::array<float, 4>& base_color) {
  SkinnedPrimitive primitive;
  primitive.name = std::move(name);
  primitive.base_color = base_color;
  mesh_.primitives.push_back(std::move(primitive));
  indices_.emplace_back();
  return static_cast<int>(indices_.size()) - 1;
}

std::uint32_t MeshBuilder::add_vertex(const Vec3& position, const Vec3& normal,
                                      const SegmentWeights& w) {
  const Vec3 segment = w.to - w.from;
  const float length2 = segment.squaredNorm();
  const float t = length2 > 0.0f ? (position - w.from).dot(segment) / length2 : 0.5f;
  float start = 0.0f;
  float end = 0.0f;
  if (w.start_joint >= 0 && w.blend > 0.0f) {
    start = std::clamp(0.5f * (1.0f - t / w.blend), 0.0f, 0.5f);
  }
  if (w.end_joint >= 0 && w.blend > 0.0f) {
    end = std::clamp(0.5f * (t - (1.0f - w.blend)) / w.blend, 0.0f, 0.5f);
  }
  std::array<Influence, 3> influences = {Influence{w.joint, 1.0f - start - end},
                                         Influence{w.start_joint, start},
                                         Influence{w.end_joint, end}};
  PackedInfluences packed;
  pack_influences(influences, packed);  // the main joint always keeps at least half
  mesh_.positions.push_back(position);
  mesh_.normals.push_back(normal.normalized());
  mesh_.joints.push_back(packed.joints);
  mesh_.weights.push_back(packed.weights);
  return static_cast<std::uint32_t>(mesh_.positions.size() - 1);
}

void MeshBuilder::add_triangle(int material, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  auto& indices = indices_[material];
  indices.push_back(a);
  indices.push_back(b);
  indices.push_back(c);
}

void MeshBuilder::add_lathe(int material, const ShapeFrame& frame,
                            const std::vector<ProfilePoint>& profile, const Vec3& scale,
                            int segments, const SegmentWeights& weights) {
  // Rows bottom to top; a row of radius 0 is a pole (one vertex). Around each ring the local
  // point is (r sin θ, y, r cos θ), so (a, b, c) below winds counter-clockwise seen from outside.
  std::vector<std::vector<std::uint32_t>> rows;
  for (const ProfilePoint& p : profile) {
    std::vector<std::uint32_t> row;
    const int count = p.radius == 0.0f ? 1 : segments;
    for (int j = 0; j < count; ++j) {
      const double theta = 2.0 * std::numbers::pi * j / segments;
      const Vec3 local(p.radius * sin_of(theta), p.y, p.radius * cos_of(theta));
      const Vec3 local_normal(p.normal_radial * sin_of(theta), p.normal_y,
                              p.normal_radial * cos_of(theta));
      const Vec3 position = frame.origin + frame.axes * local.cwiseProduct(scale);
      const Vec3 normal = frame.axes * local_normal.cwiseQuotient(scale);
      row.push_back(add_vertex(position, normal, weights));
    }
    rows.push_back(std::move(row));
  }
  for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
    const auto& lower = rows[i];
    const auto& upper = rows[i + 1];
    for (int j = 0; j < segments; ++j) {
      const int k = (j + 1) % segments;
      if (lower.size() == 1) {
        add_triangle(material, lower[0], upper[k], upper[j]);
      } else if (upper.size() == 1) {
        add_triangle(material, lower[j], lower[k], upper[0]);
      } else {
        add_triangle(material, lower[j], lower[k], upper[k]);
        add_triangle(material, lower[j], upper[k], upper[j]);
      }
    }
  }
}

void MeshBuilder::add_capsule(int material, const ShapeFrame& frame, const Capsule& c,
                              const SegmentWeights& weights) {
  std::vector<ProfilePoint> profile;
  const double quarter = std::numbers::pi / 2.0;
  // Bottom cap from its pole up to the equator (a half ellipse: x = r cos φ, y = cap r sin φ,
  // normal ∝ (cap cos φ, sin φ)).
  for (int k = 0; k <= c.cap_rings; ++k) {
    const double phi = -quarter + quarter * k / c.cap_rings;
    const float cs = k == 0 ? 0.0f : cos_of(phi);
    const float sn = k == c.cap_rings ? 0.0f : sin_of(phi);
    profile.push_back({c.r0 * cs, c.cap * c.r0 * sn, c.cap * cs, sn});
  }
  // Top cap from its equator up to the pole.
  for (int k = 0; k <= c.cap_rings; ++k) {
    const double phi = quarter * k / c.cap_rings;
    const float cs = k == c.cap_rings ? 0.0f : cos_of(phi);
    const float sn = k == 0 ? 0.0f : sin_of(phi);
    profile.push_back({c.r1 * cs, c.length + c.cap * c.r1 * sn, c.cap * cs, sn});
  }
  add_lathe(material, frame, profile, Vec3(1.0f, 1.0f, c.depth), c.segments, weights);
}

void MeshBuilder::add_ellipsoid(int material, const ShapeFrame& frame, const Vec3& radii,
                                int segments, int rings, const SegmentWeights& weights) {
  std::vector<ProfilePoint> profile;
  for (int k = 0; k <= rings; ++k) {
    const double phi = -std::numbers::pi / 2.0 + std::numbers::pi * k / rings;
    const float cs = k == 0 || k == rings ? 0.0f : cos_of(phi);
    const float sn = k == 0 ? -1.0f : (k == rings ? 1.0f : sin_of(phi));
    profile.push_back({cs, sn, cs, sn});
  }
  add_lathe(material, frame, profile, radii, segments, weights);
}

void MeshBuilder::add_box(int material, const ShapeFrame& frame, const Vec3& half,
                          const SegmentWeights& weights) {
  // Per face: outward normal n and tangents u, v with u × v = n, so the corners
  // (−u−v, +u−v, +u+v, −u+v) run counter-clockwise seen from outside.
  struct Face {
    int n, u, v;
    float sign;
  };
  constexpr std::array<Face, 6> kFaces = {Face{0, 1, 2, 1.0f}, Face{0, 2, 1, -1.0f},
                                          Face{1, 2, 0, 1.0f}, Face{1, 0, 2, -1.0f},
                                          Face{2, 0, 1, 1.0f}, Face{2, 1, 0, -1.0f}};
  constexpr std::array<std::array<float, 2>, 4> kCorners = {
      {{-1.0f, -1.0f}, {1.0f, -1.0f}, {1.0f, 1.0f}, {-1.0f, 1.0f}}};
  for (const Face& f : kFaces) {
    std::array<std::uint32_t, 4> corner{};
    for (std::size_t k = 0; k < 4; ++k) {
      Vec3 local = Vec3::Zero();
      local[f.n] = f.sign * half[f.n];
      local[f.u] = kCorners[k][0] * half[f.u];
      local[f.v] = kCorners[k][1] * half[f.v];
      Vec3 normal = Vec3::Zero();
      normal[f.n] = f.sign;
      corner[k] = add_vertex(frame.origin + frame.axes * local, frame.axes * normal, weights);
    }
    add_triangle(material, corner[0], corner[1], corner[2]);
    add_triangle(material, corner[0], corner[2], corner[3]);
  }
}

SkinnedMesh MeshBuilder::finish() && {
  SkinnedMesh mesh = std::move(mesh_);
  std::vector<SkinnedPrimitive> primitives;
  for (std::size_t m = 0; m < indices_.size(); ++m) {
    if (indices_[m].empty()) {
      continue;
    }
    SkinnedPrimitive primitive = std::move(mesh.primitives[m]);
    primitive.first_index = static_cast<std::uint32_t>(mesh.indices.size());
    primitive.index_count = static_cast<std::uint32_t>(indices_[m].size());
    mesh.indices.insert(mesh.indices.end(), indices_[m].begin(), indices_[m].end());
    primitives.push_back(std::move(primitive));
  }
  mesh.primitives = std::move(primitives);
  return mesh;
}

}  // namespace deixis::avatar
