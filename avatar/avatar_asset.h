#pragma once
// A skinned humanoid in glTF's own conventions, as the .glb writer takes it: +Y up, facing +Z,
// the character's left at +X (the Deixis world turns this 180° about +Y at load).

#include <map>
#include <string>
#include <vector>

#include "avatar/skinned_mesh.h"
#include "ik/skeleton.h"

namespace deixis::avatar {

// A named point fixed in a joint's frame that is not a joint itself (e.g. an index fingertip);
// written as a child node without mesh.
struct EndSite {
  std::string name;
  int joint = 0;
  Vec3 offset = Vec3::Zero();  // in the joint's frame
};

struct AvatarAsset {
  ik::Skeleton skeleton;  // depth-first; rest_local = T_parent_joint in the glTF frame
  SkinnedMesh mesh;       // model frame (glTF), rest pose; inverse_bind per joint
  std::vector<EndSite> end_sites;
  std::string generator;                   // glTF asset.generator
  std::map<std::string, double> metadata;  // written to asset.extras.deixis
};

}  // namespace deixis::avatar
