#pragma once
// Low-poly shapes (capsules, ellipsoids, boxes) bound to joints, for the generated avatar. Each
// shape is built in its own frame and written into a SkinnedMesh with smooth normals and skin
// weights that blend across the joints at either end of the bone it covers.

#include <array>
#include <string>
#include <vector>

#include "avatar/skinned_mesh.h"

namespace deixis::avatar {

// How one shape's vertices are shared among joints. The shape follows `joint`; measured along the
// segment `from` → `to`, it blends into `start_joint` within `blend` (a fraction of the segment)
// of `from`, reaching half weight at `from`, and likewise into `end_joint` near `to`. −1: no blend.
struct SegmentWeights {
  int joint = 0;
  int start_joint = -1;
  int end_joint = -1;
  Vec3 from = Vec3::Zero();
  Vec3 to = Vec3::UnitY();
  float blend = 0.25f;
};
SegmentWeights rigid(int joint);

// A shape's frame in the model: the origin and the rotation whose columns are the shape's x, y
// (long axis) and z axes.
struct ShapeFrame {
  Mat3 axes = Mat3::Identity();
  Vec3 origin = Vec3::Zero();
};
// The frame whose y axis runs from `from` towards `to`, with x as close to `side` as possible.
ShapeFrame segment_frame(const Vec3& from, const Vec3& to, const Vec3& side);

// A capsule along the frame's y axis from the origin to `length`, cross-section radius `r0` at
// the start and `r1` at the end along x, scaled by `depth` along z; the end caps are half
// ellipsoids of height `cap` × radius.
struct Capsule {
  float length = 0.0f;
  float r0 = 0.0f;
  float r1 = 0.0f;
  float depth = 1.0f;
  float cap = 1.0f;
  int segments = 12;  // around the axis
  int cap_rings = 3;  // per cap
};

class MeshBuilder {
 public:
  // A material becomes one primitive of the finished mesh; primitives keep this order.
  int add_material(std::string name, const std::array<float, 4>& base_color);

  void add_capsule(int material, const ShapeFrame& frame, const Capsule& capsule,
                   const SegmentWeights& weights);
  // An ellipsoid with the given radii along the frame's axes, centred on its origin.
  void add_ellipsoid(int material, const ShapeFrame& frame, const Vec3& radii, int segments,
                     int rings, const SegmentWeights& weights);
  // A box with the given half extents along the frame's axes, centred on its origin.
  void add_box(int material, const ShapeFrame& frame, const Vec3& half_extents,
               const SegmentWeights& weights);

  // The mesh with one primitive per material; inverse_bind is left for the caller.
  SkinnedMesh finish() &&;

 private:
  struct ProfilePoint {  // one ring of a surface of revolution about the local y axis
    float radius;
    float y;
    float normal_radial;
    float normal_y;
  };
  void add_lathe(int material, const ShapeFrame& frame, const std::vector<ProfilePoint>& profile,
                 const Vec3& scale, int segments, const SegmentWeights& weights);
  std::uint32_t add_vertex(const Vec3& position, const Vec3& normal, const SegmentWeights& weights);
  void add_triangle(int material, std::uint32_t a, std::uint32_t b, std::uint32_t c);

  SkinnedMesh mesh_;
  std::vector<std::vector<std::uint32_t>> indices_;  // per material
};

}  // namespace deixis::avatar
