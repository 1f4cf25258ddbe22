#pragma once
// Deixis' default avatar: a parametric, low-poly skinned humanoid generated from a height and an
// arm length (docs/avatars.md#the-default-avatar). Joints carry Deixis' bone names (VRM 1.0
// humanoid names, plus the thumbs and legs VRM names too; docs/avatars.md), the rest pose is a
// T-pose with every joint frame aligned with the model, and the index fingertips are end sites
// "leftIndexTip" and "rightIndexTip". Proportions other than the two parameters follow standard
// anthropometric ratios of stature (Drillis & Contini, as tabulated by Winter, "Biomechanics and
// Motor Control of Human Movement").

#include <cstdint>
#include <vector>

#include "avatar/avatar_asset.h"

namespace deixis::avatar {

struct AvatarParameters {
  float height = 1.70f;      // m, floor to the top of the head
  float arm_length = 0.74f;  // m, upper-arm joint to index fingertip, arm and finger straight
};

// Throws deixis::Error naming the parameter when one is not finite or outside what the body model
// can build: height 0.5–2.5 m, arm length 0.30–0.60 × height.
void validate(const AvatarParameters& parameters);

// The avatar in glTF's frame (+Y up, facing +Z, its left at +X), feet on y = 0.
AvatarAsset make_default_avatar(const AvatarParameters& parameters);

// make_default_avatar written as .glb: the same parameters give identical bytes.
std::vector<std::uint8_t> generate_default_avatar(const AvatarParameters& parameters);

}  // namespace deixis::avatar
