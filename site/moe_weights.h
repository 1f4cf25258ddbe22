#pragma once
// The MPNet MoE and UGNet MoE a runtime command drives, from a weights directory with `right/`
// and `left/` (the authors' file names, e.g. `MPNet(MoE)(AC)80.safetensors`).

#include <filesystem>

#include "core/tracking.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"

namespace deixis::site {

struct MoeNetworks {
  nn::Mpnet mpnet;
  nn::Ugnet ugnet;
};

// Whether a person whose deictic hand is `hand` is translated through the right-hand weights on
// their mirror image (presence::RemoteAvatarConfig::mirrored): left-handed people are, since the
// authors' left-hand weights stop the avatar's gaze short (docs/decisions.md §68).
constexpr bool translated_mirrored(Hand hand) {
  return hand == Hand::kLeft;
}
// The weights that translate a person whose deictic hand is `hand` (the right hand's for both).
constexpr Hand translating_weights(Hand hand) {
  return translated_mirrored(hand) ? Hand::kRight : hand;
}

// The networks for a person whose deictic hand is `hand`. Throws deixis::Error naming the missing
// file and the options that choose the directory.
MoeNetworks load_moe_networks(const std::filesystem::path& weights_dir, Hand hand);

}  // namespace deixis::site
