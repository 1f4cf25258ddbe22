#pragma once
// Writes an AvatarAsset as binary glTF 2.0 (.glb) with tinygltf: one skinned mesh node at the
// scene root, one node per joint (named as the skeleton names them), end sites as leaf nodes, one
// material per primitive, and every array in one binary buffer. The bytes depend only on the
// asset (no time stamps), so equal assets give identical files.

#include <cstdint>
#include <filesystem>
#include <vector>

#include "avatar/avatar_asset.h"

namespace deixis::avatar {

std::vector<std::uint8_t> write_glb(const AvatarAsset& asset);

// Writes `bytes` to `file`; throws deixis::Error naming the file when it cannot.
void save_file(const std::filesystem::path& file, const std::vector<std::uint8_t>& bytes);

}  // namespace deixis::avatar
