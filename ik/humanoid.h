#pragma once
// The humanoid roles IK drives, mapped onto a skeleton's joints. Avatars of any size and any
// naming scheme (Deixis' own, VRM 0.x/1.0, Mixamo; avatar/bone_names.*) become a HumanoidRig.

#include <array>
#include <cstdint>
#include <string_view>

#include "ik/skeleton.h"

namespace deixis::ik {

enum class Bone : std::uint8_t {
  kHips,
  kSpine,
  kChest,
  kNeck,
  kHead,
  kLeftEye,
  kRightEye,
  kLeftShoulder,
  kLeftUpperArm,
  kLeftLowerArm,
  kLeftHand,
  kLeftIndexProximal,
  kLeftIndexIntermediate,
  kLeftIndexDistal,
  kRightShoulder,
  kRightUpperArm,
  kRightLowerArm,
  kRightHand,
  kRightIndexProximal,
  kRightIndexIntermediate,
  kRightIndexDistal,
  kCount
};
inline constexpr int kBoneCount = static_cast<int>(Bone::kCount);
std::string_view bone_name(Bone bone);  // "hips", "leftUpperArm", ... (VRM 1.0 names)

// Bones an avatar must have for Deixis to drive it; the rest are optional (-1 when absent).
bool is_required(Bone bone);

struct HumanoidRig {
  Skeleton skeleton;
  std::array<int, kBoneCount> joint{};  // joint index per bone, −1 when an optional bone is absent
  // The eye midpoint H in the head joint's frame (rest pose), and each index fingertip in its
  // last index joint's frame (the end site, which skeletons rarely have as a joint).
  Vec3 eye_midpoint_in_head = Vec3::Zero();
  std::array<Vec3, 2> index_tip_in_distal = {Vec3::Zero(), Vec3::Zero()};  // by deixis::Hand
  float height = 0.0f;      // m, rest pose, floor to top of head
  float arm_length = 0.0f;  // m, upper-arm joint to index fingertip, rest pose

  int operator[](Bone b) const { return joint[static_cast<int>(b)]; }
};

}  // namespace deixis::ik
