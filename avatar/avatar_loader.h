#pragma once
// Loads a glTF humanoid (.glb or .gltf) as Deixis drives and draws it: an ik::HumanoidRig (flat,
// depth-first skeleton with rest local transforms, humanoid bone map, measured H, fingertips,
// height and arm length) and a SkinnedMesh, both in Deixis' model frame (+Y up, facing −Z,
// metres). Conventions and the bone-name tables: docs/avatars.md.
//
// The skeleton is every joint of every skin (plus nodes a VRM humanoid names and nodes that
// connect them), in depth-first order of the file's hierarchy, whatever order the file lists its
// nodes in. Node scale is baked into positions: joints are rigid. The file is turned once about +Y
// so that the avatar faces −Z: 180° for glTF's +Z-facing assets, found from the shoulders so that
// −Z-facing files (VRM 0.x) load facing the same way.
//
// Every problem with the file is a deixis::Error naming it: not glTF, truncated, no skin, a
// missing required bone (named), non-finite transforms or vertices, skin weights summing to zero,
// out-of-range indices.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include "avatar/skinned_mesh.h"
#include "ik/humanoid.h"

namespace deixis::avatar {

struct Avatar {
  ik::HumanoidRig rig;
  SkinnedMesh mesh;          // joint indices into rig.skeleton; inverse_bind from its rest pose
  std::string bone_source;   // how the bones were found, e.g. "joint names (Mixamo)"
  float facing_turn = 0.0f;  // rad about +Y from the file's frame to Deixis' (π for glTF's +Z)
};

Avatar load_avatar(const std::filesystem::path& file);

// The same from bytes already in memory; `source` names them in errors. A .gltf's external
// buffers and images are looked up in `base_dir` and must lie inside it (no "..", no absolute
// paths, no scheme but data:); with an empty `base_dir` only data: URIs are read.
//
// The file is untrusted: its size, JSON depth and size, external bytes, and the vertices and
// indices of the mesh it describes (every node that places a mesh counted) are capped before
// anything is parsed or baked (avatar/gltf_limits.h, docs/avatars.md).
Avatar load_avatar(std::span<const std::uint8_t> bytes, const std::string& source,
                   const std::filesystem::path& base_dir = {});

}  // namespace deixis::avatar
