#pragma once
// How well the FMD autoencoder reconstructs motion, in the paper's terms (§V, "FMD"): the average
// per-frame position error (cm) and rotation error (degrees) of head and hand over 30-frame
// segments, on the training subject and on the validation subjects (the paper's own figures:
// nn::kPaperReconstructionRight and Left, gesture/nn/motion_encoder.h).

#include <torch/torch.h>

#include "train/clips.h"
#include "train/manifest.h"  // ReconstructionError
#include "train/models.h"

namespace deixis::train {

// Errors between real and reconstructed segments [N, 30, 18] (head 6D, head position, hand 6D,
// hand position; columns 3–20 of docs/conventions.md#end-effectors): per frame and per joint (head,
// hand), the distance of the positions (m → cm) and the geodesic angle between the rotations (each
// 6D pair of forward and up vectors orthonormalised as the runtime does), averaged over frames,
// joints and segments.
ReconstructionError motion_errors(const torch::Tensor& real, const torch::Tensor& reconstructed);

// The autoencoder's reconstruction of every segment in `segments` (eval mode, no gradients).
ReconstructionError reconstruction_error(TrainableNetwork& autoencoder, const ExampleSet& segments);

}  // namespace deixis::train
