#pragma once
// What the renderer draws avatars from: the avatar library's SkinnedMesh (avatar/skinned_mesh.h,
// plain data shared by the loader, the generator and the renderer: rest-pose vertices in the
// model frame, up to four joint influences each, one rigid inverse bind pose per skeleton joint,
// index ranges with a base colour). Joint indices are the skeleton's own, so the pose drawn is
// T_model_joint for that skeleton (ik::local_to_model). Only that header is used; render does not
// link the avatar library (glTF loading stays out of it).

#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "avatar/skinned_mesh.h"

namespace deixis::render {

using avatar::SkinnedMesh;
using avatar::SkinnedPrimitive;

using Colour = Eigen::Vector4f;  // linear RGBA in [0, 1]

// Throws deixis::Error naming `source` and the first problem: mismatched array sizes, an index
// past the vertices, a weighted joint past inverse_bind, more than `max_joints` joints,
// negative or non-finite numbers, weights not summing to 1, or a primitive outside the indices.
void validate(const SkinnedMesh& mesh, int max_joints, std::string_view source);

// A rigid mesh (target objects): positions and normals in the object's unit frame.
struct StaticMesh {
  std::vector<Vec3> positions;
  std::vector<Vec3> normals;
  std::vector<std::uint32_t> indices;
};

}  // namespace deixis::render
