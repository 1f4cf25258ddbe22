#pragma once
// Bone-name schemes: how the joints of an avatar file are recognised as the humanoid bones IK
// drives (ik::Bone). docs/avatars.md lists every name.
//
//   kDeixis  Deixis' own names, which are the VRM 1.0 humanoid bone names ("hips", "leftUpperArm",
//            "leftIndexDistal", ...); VRM 0.x uses the same names for every bone Deixis drives, so
//            the humanBones tables of both VRM extensions are read through this scheme too.
//   kMixamo  Adobe Mixamo's names with or without their namespace ("mixamorig:LeftArm",
//            "mixamorig1_LeftArm", "LeftArm"); Spine → spine, Spine1 → chest.
//   kBcn     the rig of assimp's test model BCN_Epileptic (docs/avatars.md): "B_Neck" acts as
//            head, B_Finger1..3 is the index chain.

#include <optional>
#include <string_view>

#include "ik/humanoid.h"

namespace deixis::avatar {

enum class NamingScheme { kDeixis, kMixamo, kBcn };
inline constexpr int kNamingSchemeCount = 3;

std::string_view scheme_name(NamingScheme scheme);  // "Deixis/VRM", "Mixamo", "BCN"

// The bone a joint named `joint_name` is in `scheme`, if any. Matching is exact (case-sensitive)
// after the scheme's normalisation (Mixamo: the namespace prefix is dropped).
std::optional<ik::Bone> bone_for_name(NamingScheme scheme, std::string_view joint_name);

// The name `scheme` gives `bone` (without namespace), for error messages; empty when the scheme
// has no such bone.
std::string_view expected_name(NamingScheme scheme, ik::Bone bone);

}  // namespace deixis::avatar
