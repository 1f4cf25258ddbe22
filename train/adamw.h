#pragma once
// torch.optim.AdamW (libtorch 1.13, single tensor, no amsgrad) on flat float arrays: the whole
// network's parameters, gradients and moments each live in one buffer (trainer.cpp), so a step
// is one pass over memory. No libtorch here, so it is built and tested under ASan too.
//
// Denormals are flushed to zero inside the step. A parameter that stops receiving gradient (a
// dead ReLU channel of the FMD autoencoder, for example) has moments that shrink by beta1 and
// beta2 every step until they are denormal, and every operation on a denormal costs the CPU
// about a hundred cycles: by epoch 25 of the autoencoder's run 85 % of its moments were denormal
// and the optimiser took 78 % of a step that had become 4–7× slower (docs/training.md). Flushed,
// such moments become exactly 0, which changes the update by less than 1e-30.

#include <cstdint>
#include <span>

#include "train/schedule.h"

namespace deixis::train {

struct AdamWBuffers {
  std::span<float> values;      // parameters, updated in place
  std::span<float> grads;       // read, then cleared for the next step
  std::span<float> exp_avg;     // first moment
  std::span<float> exp_avg_sq;  // second moment
};

// One step number `step` (1-based, as torch counts) with learning rate `lr` and the schedule's
// betas, epsilon and weight decay. The caller's floating-point mode is restored on return.
void adamw_step(const AdamWBuffers& buffers, const Schedule& schedule, double lr,
                std::int64_t step);

}  // namespace deixis::train
