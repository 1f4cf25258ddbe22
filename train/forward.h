#pragma once
// Runs deixis-train's libtorch networks on plain float arrays, without libtorch in the caller's
// headers: the tests compare these outputs with the C++ runtime's and with the authors'
// fixtures, which proves that the training models are the authors' architecture and that the
// exported weights mean the same thing in both places.

#include <cstdint>
#include <span>
#include <vector>

#include "core/io/safetensors.h"
#include "train/network_kind.h"

namespace deixis::train {

struct ForwardOutputs {
  std::vector<float> output;    // [count, outputs]; autoencoder: latent codes [count, 128]
  std::vector<float> preclamp;  // MPNet only: before the clamp
};

// `inputs`: count windows of [30, columns] (MPNet 11, UGNet 32, autoencoder 18). `noise`: the
// diffusion draws, count × [30, 24] as nn::Ugnet::run; empty means zeros. Runs in eval mode.
ForwardOutputs libtorch_forward(Network network, const SafetensorsFile& weights,
                                std::span<const float> inputs, std::int64_t count,
                                std::span<const float> noise = {});

// A freshly initialised network (libtorch's and the authors' initialisation, seeded), exported
// with the authors' tensor names.
SafetensorsWriter initial_weights(Network network, std::uint64_t seed);

}  // namespace deixis::train
