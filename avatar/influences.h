#pragma once
// Joint influences of one vertex: how many a vertex may have (4, glTF's JOINTS_0/WEIGHTS_0) and
// how a longer or unnormalised list is packed into them.

#include <array>
#include <cstdint>
#include <span>

#include "avatar/skinned_mesh.h"

namespace deixis::avatar {

struct Influence {
  int joint = 0;
  float weight = 0.0f;
};

struct PackedInfluences {
  std::array<std::uint16_t, kMaxInfluences> joints{};
  std::array<float, kMaxInfluences> weights{};
};

// Merges influences of the same joint, keeps the kMaxInfluences largest (ties: lower joint first),
// renormalises them to sum to 1 and orders them by decreasing weight; unused slots get joint 0
// and weight 0. The largest weight absorbs the rounding, so the float weights sum to 1 within
// 6e-8 (glTF validators check the sum). Returns false when no weight is positive. Weights must be
// finite and non-negative, joints in [0, 65535] (the caller validates).
bool pack_influences(std::span<Influence> influences, PackedInfluences& packed);

}  // namespace deixis::avatar
