// Meshes from parameters: closed, outward-facing target primitives and a skinned tube whose
// weights follow its bones.

#include <gtest/gtest.h>

#include <vector>

#include "core/error.h"
#include "render/primitives.h"
#include "render_fixtures.h"

namespace deixis::render {
namespace {

// Every triangle's winding normal points away from the origin (for a mesh centred on it).
template <typename Mesh>
void expect_outward(const Mesh& mesh) {
  for (std::size_t i = 0; i < mesh.indices.size(); i += 3) {
    const Vec3& a = mesh.positions[mesh.indices[i]];
    const Vec3& b = mesh.positions[mesh.indices[i + 1]];
    const Vec3& c = mesh.positions[mesh.indices[i + 2]];
    const Vec3 n = (b - a).cross(c - a);
    ASSERT_GT(n.norm(), 0.0f) << "degenerate triangle " << i / 3;
    ASSERT_GT(n.dot((a + b + c) / 3), 0.0f) << "triangle " << i / 3 << " faces inwards";
  }
}

TEST(PrimitivesTest, UnitSphereAndCubeAreClosedAndFaceOutwards) {
  const StaticMesh sphere = unit_sphere(8, 12);
  expect_outward(sphere);
  for (const Vec3& p : sphere.positions) {
    EXPECT_NEAR(p.norm(), 0.5f, 1e-5f);
  }
  const StaticMesh cube = unit_cube();
  EXPECT_EQ(cube.positions.size(), 24u);
  EXPECT_EQ(cube.indices.size(), 36u);
  expect_outward(cube);
  for (const Vec3& p : cube.positions) {
    EXPECT_FLOAT_EQ(p.cwiseAbs().maxCoeff(), 0.5f);
  }
}

TEST(PrimitivesTest, SkinnedTubeFollowsItsBonesAndPassesValidation) {
  using namespace deixis::render::testing;
  const ik::Skeleton skeleton = arm_skeleton();
  const SkinnedMesh mesh = arm_mesh(skeleton);
  EXPECT_NO_THROW(validate(mesh, 256, "tube"));
  ASSERT_EQ(mesh.inverse_bind.size(), 3u);
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Vec3 p = mesh.positions[v] - kShoulder;
    // Along +X from the shoulder, within a tube radius of the axis.
    EXPECT_LE(Eigen::Vector2f(p.y(), p.z()).norm(), kArmRadius + 1e-5f);
    // Upper-arm vertices follow the shoulder, forearm ones the elbow, blended near the elbow.
    const auto& j = mesh.joints[v];
    const auto& w = mesh.weights[v];
    if (p.x() < 0.5f * kUpperArm) {
      EXPECT_EQ(j[0], 0);
      EXPECT_FLOAT_EQ(w[0], 1.0f);
    } else if (p.x() > kUpperArm + 0.5f * kForearm) {
      EXPECT_EQ(j[0], 1);
      EXPECT_FLOAT_EQ(w[0], 1.0f);
    }
    EXPECT_NE(j[0], 2) << "the tip joint drives nothing";
  }
  // The rest pose maps the bind mesh onto itself.
  std::vector<Pose> rest(3);
  ik::local_to_model(skeleton, skeleton.rest_local, rest);
  for (std::size_t j = 0; j < 3; ++j) {
    const Pose identity = compose(rest[j], mesh.inverse_bind[j]);
    EXPECT_TRUE(identity.rotation.isIdentity(1e-6f));
    EXPECT_LT(identity.translation.norm(), 1e-6f);
  }
}

TEST(PrimitivesTest, BadChainsAreErrors) {
  const ik::Skeleton skeleton = testing::arm_skeleton();
  const int too_short[] = {0};
  const int out_of_range[] = {0, 5};
  EXPECT_THROW(skinned_tube(skeleton, too_short, {}), Error);
  EXPECT_THROW(skinned_tube(skeleton, out_of_range, {}), Error);
}

TEST(PrimitivesTest, AppendRebasesIndicesAndPrimitives) {
  const ik::Skeleton skeleton = testing::arm_skeleton();
  const SkinnedMesh part = testing::arm_mesh(skeleton);
  SkinnedMesh both = part;
  append(both, part);
  EXPECT_EQ(both.positions.size(), 2 * part.positions.size());
  EXPECT_EQ(both.primitives.size(), 2u);
  EXPECT_EQ(both.primitives[1].first_index, part.indices.size());
  EXPECT_EQ(both.indices[part.indices.size()], part.indices[0] + part.positions.size());
  EXPECT_NO_THROW(validate(both, 256, "two tubes"));
}

}  // namespace
}  // namespace deixis::render
