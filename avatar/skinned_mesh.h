#pragma once
// The mesh of an avatar as the renderer draws it with linear blend skinning: one vertex array
// shared by every primitive, up to four joint influences per vertex, and one base colour per
// primitive.
//
// Loaded avatars (avatar/avatar_loader.h) hold it in Deixis' model frame (+Y up, facing −Z,
// metres) in the rest pose, with joint indices into the avatar's ik::Skeleton. A vertex is drawn
// at Σ_k weights[k] · T_model_joint(posed)[joints[k]] · inverse_bind[joints[k]] · position, so the
// rest pose reproduces `positions` exactly.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/math/pose.h"

namespace deixis::avatar {

inline constexpr int kMaxInfluences = 4;

// A range of `SkinnedMesh::indices` drawn with one material.
struct SkinnedPrimitive {
  std::string name;                                // the material's name, for debugging
  std::uint32_t first_index = 0;                   // into SkinnedMesh::indices
  std::uint32_t index_count = 0;                   // a multiple of 3 (triangle list)
  std::array<float, 4> base_color = {1, 1, 1, 1};  // linear RGBA, glTF's baseColorFactor
};

struct SkinnedMesh {
  // Per vertex.
  std::vector<Vec3> positions;                                    // m, rest pose
  std::vector<Vec3> normals;                                      // unit length, rest pose
  std::vector<std::array<std::uint16_t, kMaxInfluences>> joints;  // skeleton joint indices
  // Non-negative, in decreasing order, summing to 1 (renormalised at load); unused slots are 0
  // with joint 0.
  std::vector<std::array<float, kMaxInfluences>> weights;

  std::vector<std::uint32_t> indices;  // triangles, counter-clockwise seen from outside
  std::vector<SkinnedPrimitive> primitives;

  // Per skeleton joint: T_joint_model of the rest pose (the inverse bind matrix, rigid).
  std::vector<Pose> inverse_bind;

  std::size_t vertex_count() const { return positions.size(); }
  std::size_t triangle_count() const { return indices.size() / 3; }
};

}  // namespace deixis::avatar
