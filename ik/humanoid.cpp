#include "ik/humanoid.h"

namespace deixis::ik {

std::string_view bone_name(Bone bone) {
  static constexpr std::array<std::string_view, kBoneCount> kNames = {"hips",
                                                                      "spine",
                                                                      "chest",
                                                                      "neck",
                                                                      "head",
                                                                      "leftEye",
                                                                      "rightEye",
                                                                      "leftShoulder",
                                                                      "leftUpperArm",
                                                                      "leftLowerArm",
                                                                      "leftHand",
                                                                      "leftIndexProximal",
                                                                      "leftIndexIntermediate",
                                                                      "leftIndexDistal",
                                                                      "rightShoulder",
                                                                      "rightUpperArm",
                                                                      "rightLowerArm",
                                                                      "rightHand",
                                                                      "rightIndexProximal",
                                                                      "rightIndexIntermediate",
                                                                      "rightIndexDistal"};
  const int i = static_cast<int>(bone);
  return i >= 0 && i < kBoneCount ? kNames[i] : "?";
}

bool is_required(Bone bone) {
  switch (bone) {
    case Bone::kHips:
    case Bone::kSpine:
    case Bone::kHead:
    case Bone::kLeftUpperArm:
    case Bone::kLeftLowerArm:
    case Bone::kLeftHand:
    case Bone::kRightUpperArm:
    case Bone::kRightLowerArm:
    case Bone::kRightHand:
      return true;
    default:
      return false;
  }
}

}  // namespace deixis::ik
