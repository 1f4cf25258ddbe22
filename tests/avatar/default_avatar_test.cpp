// The generated default avatar: parameters honoured (measured on load within 1 cm), a depth-first
// skeleton whose rest pose stands upright facing −Z, a closed outward-facing mesh with sensible
// skin weights, and byte-for-byte reproducible files.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "avatar/avatar_loader.h"
#include "avatar/default_avatar.h"
#include "avatar_test_support.h"
#include "core/error.h"
#include "test_support.h"

namespace deixis::avatar {
namespace {

using ik::Bone;
using testing::rest_model;

Avatar load_generated(const AvatarParameters& p) {
  return load_avatar(generate_default_avatar(p), "generated.glb");
}

class DefaultAvatarSizes : public ::testing::TestWithParam<AvatarParameters> {};

TEST_P(DefaultAvatarSizes, MeasuresAsAskedWithinOneCentimetre) {
  const AvatarParameters p = GetParam();
  const Avatar a = load_generated(p);
  EXPECT_NEAR(a.rig.height, p.height, 0.01f);
  EXPECT_NEAR(a.rig.arm_length, p.arm_length, 0.01f);
  // Also the straight-line definition: upper-arm joint to fingertip, both arms.
  const auto model = rest_model(a.rig);
  for (const auto& [upper, distal, hand] :
       {std::tuple{Bone::kLeftUpperArm, Bone::kLeftIndexDistal, 0},
        std::tuple{Bone::kRightUpperArm, Bone::kRightIndexDistal, 1}}) {
    const Vec3 tip = transform_point(model[a.rig[distal]], a.rig.index_tip_in_distal[hand]);
    EXPECT_NEAR((tip - model[a.rig[upper]].translation).norm(), p.arm_length, 0.01f);
  }
}

TEST_P(DefaultAvatarSizes, RestPoseStandsOnTheFloorFacingMinusZ) {
  const AvatarParameters p = GetParam();
  const Avatar a = load_generated(p);
  const auto model = rest_model(a.rig);
  const auto at = [&](Bone b) { return model[a.rig[b]].translation; };
  const Vec3 H = transform_point(model[a.rig[Bone::kHead]], a.rig.eye_midpoint_in_head);

  // Eyes at 0.936 of stature (Winter), head joint at the skull base, centred.
  EXPECT_NEAR(H.y(), 0.936f * p.height, 0.01f);
  EXPECT_NEAR(at(Bone::kHead).y(), 0.875f * p.height, 0.01f);
  EXPECT_NEAR(H.x(), 0.0f, 1e-5f);
  // Facing −Z: the eyes in front of the head joint; the avatar's left at −X.
  EXPECT_LT(H.z(), at(Bone::kHead).z() - 0.03f * p.height);
  EXPECT_LT(at(Bone::kLeftEye).x(), at(Bone::kRightEye).x());
  EXPECT_LT(at(Bone::kLeftHand).x(), -0.3f * p.height);
  EXPECT_GT(at(Bone::kRightHand).x(), 0.3f * p.height);
  // Feet on the floor, head at the top.
  float bottom = 1e9f;
  float top = -1e9f;
  for (const Vec3& v : a.mesh.positions) {
    bottom = std::min(bottom, v.y());
    top = std::max(top, v.y());
  }
  EXPECT_NEAR(bottom, 0.0f, 1e-4f);
  EXPECT_NEAR(top, p.height, 1e-4f);
  // T-pose: the index fingertips at shoulder height, straight out.
  EXPECT_NEAR(at(Bone::kLeftIndexDistal).y(), at(Bone::kLeftUpperArm).y(), 1e-4f);
}

INSTANTIATE_TEST_SUITE_P(Sizes, DefaultAvatarSizes,
                         ::testing::Values(AvatarParameters{1.70f, 0.74f},
                                           AvatarParameters{1.50f, 0.64f},
                                           AvatarParameters{1.95f, 0.86f},
                                           AvatarParameters{1.10f, 0.47f},
                                           AvatarParameters{1.70f, 0.60f}));

TEST(DefaultAvatar, SkeletonIsDepthFirstWithEveryDeixisBone) {
  const Avatar a = load_generated({});
  const ik::Skeleton& s = a.rig.skeleton;
  ASSERT_NO_THROW(ik::validate(s, "generated"));
  for (int j = 0; j < s.joint_count(); ++j) {
    EXPECT_LT(s.parents[j], j) << s.joint_names[j];
  }
  EXPECT_EQ(s.parents[0], ik::kNoParent);
  for (int b = 0; b < ik::kBoneCount; ++b) {
    const Bone bone = static_cast<Bone>(b);
    ASSERT_NE(a.rig[bone], -1) << ik::bone_name(bone);
    EXPECT_EQ(s.joint_names[a.rig[bone]], ik::bone_name(bone));
  }
  EXPECT_EQ(a.bone_source, "joint names (Deixis/VRM)");
  EXPECT_NEAR(a.facing_turn, std::acos(-1.0f), 1e-6f);
  // Thumbs and legs are there too (VRM names), for looks.
  EXPECT_NE(s.find("leftThumbDistal"), -1);
  EXPECT_NE(s.find("rightFoot"), -1);
}

TEST(DefaultAvatar, FingertipEndSiteIsTheEndOfTheFinger) {
  const AvatarParameters p{};
  const Avatar a = load_generated(p);
  const auto model = rest_model(a.rig);
  const Pose& distal = model[a.rig[Bone::kLeftIndexDistal]];
  const Vec3 tip = transform_point(distal, a.rig.index_tip_in_distal[0]);
  // The distal phalanx is 3.2 % of the arm, pointing out along −X for the left arm.
  EXPECT_NEAR((tip - distal.translation).norm(), 0.032f * p.arm_length, 1e-4f);
  EXPECT_LT(tip.x(), distal.translation.x());
  // The mesh reaches the fingertip and no further along the arm.
  float farthest = 0.0f;
  for (const Vec3& v : a.mesh.positions) {
    farthest = std::min(farthest, v.x());
  }
  EXPECT_NEAR(farthest, tip.x(), 1e-4f);
}

TEST(DefaultAvatar, TrianglesFaceOutwardAndNormalsAreUnit) {
  const Avatar a = load_generated({});
  const SkinnedMesh& m = a.mesh;
  ASSERT_EQ(m.indices.size() % 3, 0u);
  int inward = 0;
  for (std::size_t i = 0; i < m.indices.size(); i += 3) {
    const Vec3& p0 = m.positions[m.indices[i]];
    const Vec3 face =
        (m.positions[m.indices[i + 1]] - p0).cross(m.positions[m.indices[i + 2]] - p0);
    const Vec3 smooth =
        m.normals[m.indices[i]] + m.normals[m.indices[i + 1]] + m.normals[m.indices[i + 2]];
    if (face.dot(smooth) <= 0.0f) {
      ++inward;
    }
  }
  EXPECT_EQ(inward, 0) << "of " << m.triangle_count() << " triangles";
  for (const Vec3& n : m.normals) {
    ASSERT_NEAR(n.norm(), 1.0f, 1e-5f);
  }
  // One primitive per material, covering every index once.
  std::uint32_t covered = 0;
  for (const SkinnedPrimitive& p : m.primitives) {
    EXPECT_EQ(p.first_index, covered) << p.name;
    covered += p.index_count;
  }
  EXPECT_EQ(covered, m.indices.size());
  EXPECT_EQ(m.primitives.size(), 6u);
}

// Distance from p to the joint's bone: the segments from the joint to each child joint (or the
// joint itself for a leaf).
float distance_to_bone(const ik::Skeleton& s, const std::vector<Pose>& model, int joint,
                       const Vec3& p) {
  const Vec3 a = model[joint].translation;
  float best = (p - a).norm();
  for (int c = joint + 1; c < s.joint_count(); ++c) {
    if (s.parents[c] != joint) {
      continue;
    }
    const Vec3 ab = model[c].translation - a;
    const float t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0f, 1.0f);
    best = std::min(best, (p - (a + t * ab)).norm());
  }
  return best;
}

TEST(DefaultAvatar, SkinWeightsAreNormalisedAndFollowTheNearestBones) {
  const AvatarParameters p{};
  const Avatar a = load_generated(p);
  const SkinnedMesh& m = a.mesh;
  const auto model = rest_model(a.rig);
  for (std::size_t v = 0; v < m.vertex_count(); ++v) {
    double sum = 0.0;
    for (int k = 0; k < kMaxInfluences; ++k) {
      ASSERT_GE(m.weights[v][k], 0.0f);
      if (k > 0) {
        ASSERT_LE(m.weights[v][k], m.weights[v][k - 1]);
      }
      sum += static_cast<double>(m.weights[v][k]);
    }
    ASSERT_NEAR(sum, 1.0, 1e-6);
    // Every joint a vertex follows is close to it: no vertex is bound across the body (a hand
    // vertex bound to the hips would be half a body away).
    for (int k = 0; k < kMaxInfluences && m.weights[v][k] > 0.0f; ++k) {
      const int j = m.joints[v][k];
      ASSERT_LT(distance_to_bone(a.rig.skeleton, model, j, m.positions[v]), 0.15f * p.height)
          << "vertex " << v << " follows " << a.rig.skeleton.joint_names[j];
    }
  }
}

TEST(DefaultAvatar, BendingTheElbowMovesTheForearmAndHandOnly) {
  const Avatar a = load_generated({});
  const ik::Skeleton& s = a.rig.skeleton;
  const auto rest = rest_model(a.rig);
  // Rest pose: skinning reproduces the stored vertices (inverse binds match the skeleton).
  const std::vector<Vec3> at_rest = testing::skin(a.mesh, rest);
  for (std::size_t v = 0; v < at_rest.size(); ++v) {
    ASSERT_LT((at_rest[v] - a.mesh.positions[v]).norm(), 1e-5f);
  }
  // Bend the left elbow 90° about the vertical, so the forearm points forward (−Z).
  std::vector<Pose> local = s.rest_local;
  const int elbow = a.rig[Bone::kLeftLowerArm];
  const Mat3 bend_model = Eigen::AngleAxisf(-std::acos(0.0f), Vec3::UnitY()).toRotationMatrix();
  const Mat3 R_model_elbow = rest[elbow].rotation;
  local[elbow].rotation =
      local[elbow].rotation * (R_model_elbow.transpose() * bend_model * R_model_elbow);
  const auto posed = testing::model_poses(s, local);
  const std::vector<Vec3> skinned = testing::skin(a.mesh, posed);
  const Pose motion = compose(posed[elbow], inverse(rest[elbow]));
  const auto below_elbow = [&](int j) {
    for (int k = s.parents[j]; k != ik::kNoParent; k = s.parents[k]) {
      if (k == elbow) {
        return true;
      }
    }
    return false;
  };
  int moved = 0;
  int still = 0;
  for (std::size_t v = 0; v < skinned.size(); ++v) {
    bool all_below = true;
    bool none_moving = true;
    for (int k = 0; k < kMaxInfluences && a.mesh.weights[v][k] > 0.0f; ++k) {
      const int j = a.mesh.joints[v][k];
      all_below = all_below && below_elbow(j);
      none_moving = none_moving && j != elbow && !below_elbow(j);
    }
    if (all_below) {  // hand and fingers follow the forearm rigidly
      ASSERT_LT((skinned[v] - transform_point(motion, a.mesh.positions[v])).norm(), 1e-5f);
      ++moved;
    } else if (none_moving) {  // the rest of the body does not move
      ASSERT_LT((skinned[v] - a.mesh.positions[v]).norm(), 1e-6f);
      ++still;
    }
  }
  EXPECT_GT(moved, 200);
  EXPECT_GT(still, 1500);
  // The index fingertip now points forward (−Z) from the elbow.
  const int distal = a.rig[Bone::kLeftIndexDistal];
  const Vec3 tip = transform_point(posed[distal], a.rig.index_tip_in_distal[0]);
  const Vec3 from_elbow = tip - posed[elbow].translation;
  EXPECT_LT(from_elbow.z(), -0.9f * from_elbow.norm());
}

TEST(DefaultAvatar, SameParametersGiveIdenticalBytes) {
  const AvatarParameters p{1.62f, 0.70f};
  const std::vector<std::uint8_t> first = generate_default_avatar(p);
  EXPECT_EQ(first, generate_default_avatar(p));
  EXPECT_NE(first, generate_default_avatar({1.62f, 0.71f}));
  // A few hundred kilobytes at most.
  EXPECT_LT(first.size(), 300'000u);
}

TEST(DefaultAvatar, CommittedAssetIsTheGeneratorsOutput) {
  // assets/avatars/default.glb is `deixis avatar generate --height 1.70 --arm-length 0.74`; if the
  // generator changes, regenerate it with that command.
  const auto committed =
      testing::read_bytes(deixis::testing::source_dir() / "assets/avatars/default.glb");
  ASSERT_FALSE(committed.empty());
  EXPECT_TRUE(committed == generate_default_avatar({1.70f, 0.74f}))
      << "assets/avatars/default.glb is stale: run deixis avatar generate --height 1.70 "
         "--arm-length 0.74 -o assets/avatars/default.glb";
}

TEST(DefaultAvatar, RejectsParametersItCannotBuild) {
  const auto message = [](AvatarParameters p) {
    try {
      validate(p);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(message({3.0f, 1.3f}).find("height 3.000 m"), std::string::npos);
  EXPECT_NE(message({0.3f, 0.13f}).find("height"), std::string::npos);
  EXPECT_NE(message({std::nanf(""), 0.74f}).find("height"), std::string::npos);
  EXPECT_NE(message({1.70f, 0.20f}).find("arm length 0.200 m"), std::string::npos);
  EXPECT_NE(message({1.70f, 1.10f}).find("arm length"), std::string::npos);
  EXPECT_NE(message({1.70f, std::numeric_limits<float>::infinity()}).find("arm length"),
            std::string::npos);
  EXPECT_EQ(message({1.70f, 0.74f}), "");
  EXPECT_THROW(generate_default_avatar({1.70f, 0.1f}), Error);
}

}  // namespace
}  // namespace deixis::avatar
