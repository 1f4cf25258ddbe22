#pragma once
// Every mesh of a glTF avatar baked into one SkinnedMesh in its rest pose (internal to the avatar
// loader). A skinned primitive's vertices are placed as the file shows them, Σ w · T_file_joint ·
// inverse bind · v, with their weights packed to four and renormalised; a mesh without skin is
// bound rigidly to its nearest joint ancestor. Everything is then turned into the model frame by
// R_model_file. Joint indices are the skeleton's; inverse_bind is left for the caller.

#include <tiny_gltf.h>

#include <string>

#include "avatar/gltf_nodes.h"
#include "avatar/skinned_mesh.h"

namespace deixis::avatar::gltf {

// Throws deixis::Error naming `source`, the mesh, primitive and (for weights) vertex on malformed
// data: out-of-range indices or joints, non-finite numbers, weights summing to zero.
SkinnedMesh bake_rest_mesh(const tinygltf::Model& model, const NodeTree& tree,
                           const JointNodes& joints, const Eigen::Matrix3d& R_model_file,
                           const std::string& source);

}  // namespace deixis::avatar::gltf
