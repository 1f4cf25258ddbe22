#include "render/mesh_cache.h"

namespace deixis::render {

SkinnedMeshCache::SkinnedMeshCache(Renderer& renderer, const SkinnedMesh& own)
    : renderer_(&renderer) {
  meshes_.reserve(kMaxMeshes);
  meshes_.emplace_back(&own, renderer_->add_skinned_mesh(own));
}

std::optional<SkinnedMeshId> SkinnedMeshCache::get(const SkinnedMesh* mesh) {
  if (mesh == nullptr) {
    return own();
  }
  for (const auto& [known, id] : meshes_) {
    if (known == mesh) {
      return id;
    }
  }
  if (meshes_.size() == kMaxMeshes) {
    return std::nullopt;
  }
  meshes_.emplace_back(mesh, renderer_->add_skinned_mesh(*mesh));
  return meshes_.back().second;
}

}  // namespace deixis::render
