#pragma once
// Skinned meshes uploaded once and found again by address: for views that draw many people, each
// in the avatar they wear (site/remote_people.h), where most wear the same few. The meshes are
// the caller's and must live as long as the cache (a mesh freed and another made at its address
// would be drawn as the first: RemotePeople keeps every avatar it loaded for the session).
#include <optional>
#include <utility>
#include <vector>

#include "render/renderer.h"

namespace deixis::render {

class SkinnedMeshCache {
 public:
  static constexpr std::size_t kMaxMeshes = 64;

  // `own`: the view's own avatar (the site's, which people wear unless they wear their own),
  // uploaded here. Others are uploaded when first asked for; the list is reserved here, so
  // lookups never allocate (uploading a new mesh allocates on the GPU side).
  SkinnedMeshCache(Renderer& renderer, const SkinnedMesh& own);

  // The mesh's id in the renderer, uploading it the first time; null: the own mesh (what
  // site::DrawnAvatar::mesh holds for someone in the site's default). nullopt once
  // kMaxMeshes different meshes are uploaded (the caller draws something else or nothing).
  std::optional<SkinnedMeshId> get(const SkinnedMesh* mesh);
  SkinnedMeshId own() const { return meshes_.front().second; }
  std::size_t size() const { return meshes_.size(); }  // the own mesh included

 private:
  Renderer* renderer_;
  std::vector<std::pair<const SkinnedMesh*, SkinnedMeshId>> meshes_;
};

}  // namespace deixis::render
