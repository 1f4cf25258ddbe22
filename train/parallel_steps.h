#pragma once
// The direct training steps (moe_step.h, autoencoder_step.h) on several threads:
// deixis-train --threads N, within the authors' schedule (the same optimiser steps as on one
// thread; only the order of floating-point additions differs, deterministically for a given N).
//
// MPNet(MoE) and UGNet(MoE) share out their nine experts (MoeStep's ExpertTeam): the batch stays
// whole, every expert's products and gradients are one member's, and AdamW is split by
// parameter range. The autoencoder has no such seam, so its batches are cut into N slices of
// consecutive segments (data parallelism): each member computes its slice's loss, as a share of
// the whole batch's mean, and gradients, which are added in member order before AdamW. Member 0
// writes its gradients straight into the trainer's flat gradient buffer, the others into
// buffers of their own laid out the same way.

#include <barrier>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <utility>
#include <vector>

#include "train/adamw.h"
#include "train/aligned_buffer.h"
#include "train/autoencoder_step.h"
#include "train/moe_step.h"
#include "train/step_team.h"

namespace deixis::train {

// AdamW (adamw.h) on a team, each member its own range of the parameters, after adding the
// `extra` gradient buffers (members 1..n−1 of a data-parallel team; none for experts) into the
// flat gradients.
void adamw_on_team(StepTeam& team, const AdamWBuffers& flat, const Schedule& schedule, double lr,
                   std::int64_t step, const std::vector<AlignedFloats>& extra = {});

// A data-parallel team: the members' gradient buffers, the slicing of a batch and the summed
// AdamW step.
class GradientTeam {
 public:
  // `flat_gradients`: the trainer's gradient buffer, which every member's buffers mirror.
  GradientTeam(int members, std::span<float> flat_gradients);

  int members() const { return team_->size(); }
  // Where member m keeps the gradient that the flat buffer holds at `flat_pointer`.
  float* member_pointer(int member, float* flat_pointer);
  // The first and one-past-last item of member m's slice of a batch of `count`.
  std::pair<int, int> slice(int member, int count) const;

  // Adds every member's gradients into the flat buffer, then AdamW: each member sums and updates
  // its own range of the parameters.
  void optimiser_step(const AdamWBuffers& flat, const Schedule& schedule, double lr,
                      std::int64_t step) {
    adamw_on_team(*team_, flat, schedule, lr, step, member_gradients_);
  }

  // The last batch's forward and backward time: the team's wall time (the slowest member
  // included), shared as member 0 (this thread) spent its own. For the trainer's timing line.
  double forward_seconds() const { return forward_seconds_; }
  double backward_seconds() const { return backward_seconds_; }

 protected:
  // Every member runs forward(m, first, last) → its share of the loss on its slice of `count`
  // items, then with `backward` backward(m); a member without items zeroes its gradients.
  // Returns the batch's loss, the members' shares added in member order.
  double run_slices(int count, bool backward,
                    const std::function<double(int member, int first, int last)>& forward,
                    const std::function<void(int member)>& backward_pass);

 private:
  void clear_member(int member);

  std::unique_ptr<StepTeam> team_;
  std::span<float> flat_gradients_;
  std::vector<AlignedFloats> member_gradients_;  // members 1..n−1
  std::vector<double> losses_;
  double forward_seconds_ = 0, backward_seconds_ = 0;
};

// MPNet(MoE) and UGNet(MoE) with their experts shared out among a team.
class ParallelMoeStep {
 public:
  ParallelMoeStep(const MoeShape& shape, int batch_size, int members, const MoeBuffers& parameters,
                  const MoeBuffers& gradients);

  // One window of a batch of `count` clips ([count][45][columns], the inputs then the targets of
  // every row): returns the loss, the mean over the batch. `feed_back` (UGNet's scheduled
  // sampling) first overwrites every clip's newest pose row of this window with that clip's
  // prediction from the previous window. With `backward` the batch's gradients are in the flat
  // gradient buffer afterwards.
  double window(float* clips, int columns, int window, int count, bool feed_back, bool backward);
  void optimiser_step(const AdamWBuffers& flat, const Schedule& schedule, double lr,
                      std::int64_t step) {
    adamw_on_team(*team_, flat, schedule, lr, step);
  }
  // The last window's forward and backward time (member 0's, the team's wall time).
  double forward_seconds() const { return forward_seconds_; }
  double backward_seconds() const { return backward_seconds_; }

 private:
  std::unique_ptr<StepTeam> team_;
  std::barrier<> sync_;
  int batch_size_;
  MoeStep step_;
  MoeBuffers parameters_, gradients_;
  double forward_seconds_ = 0, backward_seconds_ = 0;
};

// The FMD autoencoder on a team.
class ParallelAutoencoderStep : public GradientTeam {
 public:
  ParallelAutoencoderStep(int batch_size, int members, const AutoencoderBuffers& parameters,
                          const AutoencoderBuffers& gradients, std::span<float> flat_gradients);

  // One batch of `count` segments ([count][30][18]); returns the loss, the mean over the batch.
  double batch(const float* segments, int count, bool backward);

 private:
  AutoencoderBuffers parameters_;
  std::vector<AutoencoderStep> steps_;
  std::vector<AutoencoderBuffers> gradients_;
};

}  // namespace deixis::train
