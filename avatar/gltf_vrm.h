#pragma once
// The humanoid bone table of a VRM avatar (internal to the avatar loader): VRM 1.0's
// "VRMC_vrm".humanoid.humanBones ({"leftHand": {"node": 12}, ...}) or VRM 0.x's
// "VRM".humanoid.humanBones ([{"bone": "leftHand", "node": 12}, ...]). Bones Deixis does not drive
// (toes, thumbs, upperChest, ...) are skipped.

#include <tiny_gltf.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ik/humanoid.h"

namespace deixis::avatar::gltf {

struct VrmHumanoid {
  std::string source;                           // "VRM 1.0 (VRMC_vrm)" or "VRM 0.x (VRM)"
  std::vector<std::pair<ik::Bone, int>> bones;  // bone, node
};

// nullopt when the file has neither extension; throws deixis::Error naming `source` and the entry
// when the table is malformed or names a node that does not exist.
std::optional<VrmHumanoid> read_vrm_humanoid(const tinygltf::Model& model,
                                             const std::string& source);

}  // namespace deixis::avatar::gltf
