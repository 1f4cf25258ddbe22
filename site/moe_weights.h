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

// The networks for a person whose deictic hand is `hand`. Throws deixis::Error naming the missing
// file and the options that choose the directory.
MoeNetworks load_moe_networks(const std::filesystem::path& weights_dir, Hand hand);

}  // namespace deixis::site
