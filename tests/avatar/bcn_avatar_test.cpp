// A third-party rig: BCN_Epileptic.X from Debian's assimp-testmodels (docs/avatars.md#bone-names),
// converted at test time with `assimp export … -fglb2`. Its weights do not sum to 1 (the glTF
// validator reports 12 such vertices), it has eyes and one finger chain, and B_Neck acts as its
// head. It must load through the BCN name table, stand upright facing −Z, and keep its bone lengths
// when posed.

#include <gtest/gtest.h>

#include <filesystem>

#include "avatar/avatar_loader.h"
#include "avatar_test_support.h"
#include "bcn_rig.h"
#include "core/tracking.h"
#include "test_support.h"

namespace deixis::avatar {
namespace {

using ik::Bone;

using deixis::testing::bcn_glb;

TEST(BcnAvatar, LoadsThroughTheBcnNameTable) {
  const Avatar a = load_avatar(bcn_glb());
  const ik::HumanoidRig& rig = a.rig;
  EXPECT_EQ(a.bone_source, "joint names (BCN)");
  const auto name = [&](Bone b) { return rig.skeleton.joint_names[rig[b]]; };
  EXPECT_EQ(name(Bone::kHead), "B_Neck");
  EXPECT_EQ(name(Bone::kLeftEye), "B_Eye_Left");
  EXPECT_EQ(name(Bone::kRightIndexDistal), "B_Finger3_Right");
  for (int b = 0; b < ik::kBoneCount; ++b) {
    EXPECT_NE(rig.joint[b], -1) << ik::bone_name(static_cast<Bone>(b));
  }
  // Depth-first although the file's skin lists its joints in another order.
  ASSERT_NO_THROW(ik::validate(rig.skeleton, "bcn"));
  for (int j = 0; j < rig.skeleton.joint_count(); ++j) {
    EXPECT_LT(rig.skeleton.parents[j], j);
  }
  EXPECT_EQ(rig.skeleton.joint_count(), 54);  // the skin's 54 joints; no extra nodes
}

TEST(BcnAvatar, WeightsAreRenormalised) {
  const Avatar a = load_avatar(bcn_glb());
  ASSERT_GT(a.mesh.vertex_count(), 2000u);
  for (std::size_t v = 0; v < a.mesh.vertex_count(); ++v) {
    double sum = 0.0;
    for (const float w : a.mesh.weights[v]) {
      sum += static_cast<double>(w);
    }
    ASSERT_NEAR(sum, 1.0, 1e-7) << "vertex " << v;
  }
}

TEST(BcnAvatar, StandsUprightFacingMinusZWithPlausibleSize) {
  const Avatar a = load_avatar(bcn_glb());
  const ik::HumanoidRig& rig = a.rig;
  EXPECT_NEAR(a.facing_turn, std::acos(-1.0f), 1e-6f);
  const auto model = testing::rest_model(rig);
  const auto at = [&](Bone b) { return model[rig[b]].translation; };
  const Vec3 H = transform_point(model[rig[Bone::kHead]], rig.eye_midpoint_in_head);
  EXPECT_GT(rig.height, 1.5f);
  EXPECT_LT(rig.height, 2.0f);
  EXPECT_GT(rig.arm_length, 0.5f);
  EXPECT_LT(rig.arm_length, 0.9f);
  EXPECT_LT(H.z(), at(Bone::kHead).z());  // eyes in front
  EXPECT_GT(H.y(), at(Bone::kHead).y());
  EXPECT_GT(H.y(), at(Bone::kLeftUpperArm).y());
  EXPECT_LT(at(Bone::kLeftUpperArm).x(), at(Bone::kRightUpperArm).x());  // its left at −X
  // The fingertip (estimated from the mesh: the file has no end site) lies beyond the distal
  // joint, a finger segment's length away.
  const Vec3 tip = rig.index_tip_in_distal[index(Hand::kLeft)];
  EXPECT_GT(tip.norm(), 0.01f);
  EXPECT_LT(tip.norm(), 0.05f);
}

TEST(BcnAvatar, PosedSkeletonStaysFiniteAndKeepsBoneLengths) {
  const Avatar a = load_avatar(bcn_glb());
  const ik::HumanoidRig& rig = a.rig;
  const ik::Skeleton& s = rig.skeleton;
  std::vector<Pose> local = s.rest_local;
  const auto turn = [&](Bone b, const Vec3& axis, float angle) {
    Pose& T = local[rig[b]];
    T.rotation = T.rotation * Eigen::AngleAxisf(angle, axis.normalized()).toRotationMatrix();
  };
  turn(Bone::kSpine, Vec3(1, 0, 0), 0.3f);
  turn(Bone::kNeck, Vec3(0, 1, 0), -0.5f);
  turn(Bone::kHead, Vec3(0, 0, 1), 0.4f);
  turn(Bone::kLeftUpperArm, Vec3(1, 1, 0), 1.2f);
  turn(Bone::kRightLowerArm, Vec3(0, 0, 1), 1.5f);
  turn(Bone::kRightIndexProximal, Vec3(0, 0, 1), 0.8f);
  turn(Bone::kLeftEye, Vec3(0, 1, 0), 0.2f);
  const auto rest = testing::rest_model(rig);
  const auto posed = testing::model_poses(s, local);
  for (int j = 0; j < s.joint_count(); ++j) {
    ASSERT_TRUE(is_finite(posed[j])) << s.joint_names[j];
    const int p = s.parents[j];
    if (p == ik::kNoParent) {
      continue;
    }
    const float rest_length = (rest[j].translation - rest[p].translation).norm();
    const float posed_length = (posed[j].translation - posed[p].translation).norm();
    EXPECT_NEAR(posed_length, rest_length, 1e-5f) << s.joint_names[j];
  }
  // The arm really moved, and the skinned mesh follows without non-finite vertices.
  EXPECT_GT(
      (posed[rig[Bone::kLeftHand]].translation - rest[rig[Bone::kLeftHand]].translation).norm(),
      0.2f);
  for (const Vec3& v : testing::skin(a.mesh, posed)) {
    ASSERT_TRUE(v.allFinite());
  }
}

}  // namespace
}  // namespace deixis::avatar
