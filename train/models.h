#pragma once
// The networks of the paper in libtorch, with the authors' module structure so that
// named_parameters() and named_buffers() are the authors' state_dict names and shapes
// (docs/conventions.md#authors-checkpoints). Exported weights therefore load in the C++ runtime
// unchanged (nn::Mpnet::load, nn::Ugnet::load, nn::MotionEncoder::load), and the authors' own
// checkpoints load here.
//
// This header includes libtorch: only models.cpp, trainer.cpp and the torch tests include it.

#include <torch/nn/module.h>
#include <torch/types.h>

#include <memory>

#include "core/io/safetensors.h"
#include "train/autoencoder_step.h"
#include "train/moe_step.h"
#include "train/network_kind.h"

namespace deixis::train {

class TrainableNetwork : public torch::nn::Module {
 public:
  // The authors' forward: window [batch, 30, columns] → [batch, outputs] (MPNet clamped to
  // [0, 1]); for the autoencoder, segments [batch, 30, 18] → their reconstruction.
  virtual torch::Tensor forward(const torch::Tensor& window) = 0;

  // What the L1 loss is taken on during training. Only the diffusion model differs: it denoises
  // the target after noising it to a random step (model.py UGNet_Diffusion.forward).
  virtual torch::Tensor training_prediction(const torch::Tensor& window,
                                            const torch::Tensor& target,
                                            torch::Generator& generator) {
    (void)target;
    (void)generator;
    return forward(window);
  }
};

std::shared_ptr<TrainableNetwork> make_network(Network network);

// The MPNet output before the clamp (MPNet architectures only).
torch::Tensor mpnet_preclamp(TrainableNetwork& mpnet, const torch::Tensor& window);
// Diffusion sampling with given draws: noise [batch, 30, 24], row 0 the initial sample, row i
// the noise added after step t = 30 − i (as nn::Ugnet::run).
torch::Tensor diffusion_sample(TrainableNetwork& diffusion, const torch::Tensor& window,
                               const torch::Tensor& noise);
// The autoencoder's 128-d latent codes of segments [batch, 30, 18].
torch::Tensor motion_codes(TrainableNetwork& autoencoder, const torch::Tensor& segments);

// A MoE network's (MPNet(MoE), UGNet(MoE)) tensors as MoeStep buffers (moe_step.h): the
// parameters' own memory, or with `gradients` the memory of their .grad() tensors, which must be
// defined. Throws naming the tensor when one is missing, not contiguous or not float32.
MoeBuffers moe_buffers(TrainableNetwork& network, bool gradients);
// The same for the FMD autoencoder (autoencoder_step.h).
AutoencoderBuffers autoencoder_buffers(TrainableNetwork& network, bool gradients);

// Copies every parameter and buffer from a safetensors file. Errors name the file and tensor:
// a missing or unexpected tensor, a wrong shape or dtype, a non-finite value.
void load_weights(TrainableNetwork& model, const SafetensorsFile& file);
// Parameters and buffers under their state_dict names, float32.
SafetensorsWriter export_weights(TrainableNetwork& model);

}  // namespace deixis::train
