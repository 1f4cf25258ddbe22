#pragma once
// The training schedules of paper §IV and the authors' scripts (docs/training.md, "The schedule"):
//   MPNet:  80 epochs, batch 16 clips, AdamW lr 1e-4 × 0.975 per epoch.
//   UGNet: 120 epochs, batch 32 clips, AdamW lr 1e-4 × 0.99 per epoch, scheduled sampling:
//          teacher forcing to epoch 30, the probability P of feeding the ground truth decays
//          linearly to 0 at epoch 60, fully autoregressive after.
//   FMD autoencoder (ISMAR2023/train_autoencoder.py): 600 epochs, batch 8 segments, Adam
//          lr 1e-3 × 0.999 (AdamW with weight decay 0 is Adam).
// Clips are 45 rows; a window of 30 rows slides over each clip one row at a time, so a clip holds
// 16 windows, and the optimiser steps once per window (the authors' "each time the window
// advanced by one frame").

namespace deixis::train {

enum class Family;

struct Schedule {
  int epochs = 80;
  int batch_size = 16;
  double learning_rate = 1e-4;
  double learning_rate_decay = 0.975;  // multiplied in after every epoch (ExponentialLR)
  double weight_decay = 0.01;          // AdamW's default in PyTorch, which the authors kept
  double beta1 = 0.9;
  double beta2 = 0.999;
  double epsilon = 1e-8;
  // Scheduled sampling (UGNet): P = 1 up to and including `teacher_forcing_epochs`, then linear
  // to 0 at `autoregressive_from_epoch` (train_UGNet.py --c1 30 --c2 60).
  bool scheduled_sampling = false;
  int teacher_forcing_epochs = 30;
  int autoregressive_from_epoch = 60;

  // Learning rate used during `epoch` (1-based): lr · decay^(epoch − 1).
  double learning_rate_at(int epoch) const;
  // Probability of feeding the ground-truth pose (not the previous prediction) during `epoch`.
  double teacher_forcing_at(int epoch) const;
};

Schedule default_schedule(Family family);

// The whole of `full` run in `epochs` epochs, for where the full schedule cannot run (UGNet
// Transformer: ≈ 90 hours of a core per hand on the 2-core machine, docs/training.md). Unlike
// cutting the schedule short (--epochs), every epoch-indexed part scales with it: scheduled
// sampling's teacher-forcing and autoregressive epochs in proportion (rounded, and the second
// kept after the first; below about 4 epochs no epoch is left with a fractional P), and the
// per-epoch learning-rate decay raised to (full − 1) / (epochs − 1), so that the last epoch
// trains at the full schedule's last rate. `epochs` must be from 2 to full.epochs.
Schedule compressed(const Schedule& full, int epochs);

// `epochs` more epochs after the end of `full`, for fine-tuning weights that `full` trained on a
// grown dataset (--init-weights, docs/training.md "Fine-tuning"): the learning rate goes on from
// the rate after full's last epoch with full's decay, and scheduled sampling stays where full
// ended (UGNet fully autoregressive). `epochs` must be ≥ 1.
Schedule continued(const Schedule& full, int epochs);

// Clip and window geometry (paper §III.A, docs/conventions.md#training-data).
inline constexpr int kClipRows = 45;
inline constexpr int kClipHop = 7;  // (45 − 30) / 2, the authors' "overlap of 7"
inline constexpr int kWindowsPerClip = kClipRows - 30 + 1;  // 16
// FMD segments (docs/eval.md#what-each-number-is): 30 frames, hop 15, plus the last 30 frames.
inline constexpr int kSegmentRows = 30;
inline constexpr int kSegmentHop = 15;

}  // namespace deixis::train
