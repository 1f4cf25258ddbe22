#pragma once
// Which joint of a skeleton plays which humanoid bone (ik::Bone): found from a VRM humanoid
// extension when the file has one, else from joint names (avatar/bone_names.h), then checked:
// every required bone present, each bone below the one it hangs from.

#include <array>
#include <optional>
#include <string>

#include "avatar/bone_names.h"
#include "ik/humanoid.h"

namespace deixis::avatar {

struct BoneMapping {
  std::array<int, ik::kBoneCount> joint;  // −1 when absent
  std::string source;                     // e.g. "joint names (Mixamo)", "VRM 1.0 (VRMC_vrm)"
  std::optional<NamingScheme> scheme;     // set when found by name

  BoneMapping() { joint.fill(-1); }
};

// Tries every naming scheme and keeps the one that finds the most required bones, then the most
// bones. Throws deixis::Error naming `file` when two joints give the same bone.
BoneMapping map_bones_by_name(const ik::Skeleton& skeleton, const std::string& file);

// Throws deixis::Error naming `file` and every missing required bone (with the name the scheme
// expects), or the first bone that is not below its parent bone (e.g. a lower arm outside its
// upper arm's subtree).
void check_bone_mapping(const BoneMapping& mapping, const ik::Skeleton& skeleton,
                        const std::string& file);

}  // namespace deixis::avatar
