#pragma once
// What a training run needs to continue exactly where it stopped: the parameters, AdamW's moment
// estimates and step count, the position inside the epoch (batches done), the running loss of the
// epoch in progress and the history of finished epochs. Every random draw of an epoch is derived
// from (seed, epoch, batch) (trainer.cpp), so a run resumed from any checkpoint makes the same
// draws, and the same losses, as one that never stopped.
//
// Stored as safetensors (the project's one file format): tensors "parameters", "exp_avg",
// "exp_avg_sq" (flat float32, in named_parameters order) and the rest as JSON in the metadata
// key "state". Written through a temporary file and a rename, so `kill -9` at any moment leaves
// either the previous checkpoint or the new one.

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace deixis::train {

struct EpochReport {
  int epoch = 0;
  double train_loss = 0;       // mean L1 over the epoch's optimiser steps
  double validation_loss = 0;  // NaN without validation data
  double learning_rate = 0;
  double teacher_forcing = 1;  // P of scheduled sampling (1 for MPNet)
  double seconds = 0;          // wall time of the epoch (training + validation)
};

struct Checkpoint {
  // Everything that must match for a resume to be the same run: network, variant, hand, seed,
  // schedule and dataset hash.
  std::string fingerprint;
  int epoch = 1;           // the epoch in progress, 1-based
  std::int64_t batch = 0;  // batches of that epoch already done
  std::int64_t step = 0;   // AdamW steps so far
  double loss_sum = 0;     // of the epoch in progress
  std::int64_t loss_count = 0;
  double epoch_seconds = 0;  // spent in the epoch in progress so far
  double train_seconds = 0;  // spent training over all runs so far
  std::vector<EpochReport> history;
  // The build commits of the deixis-train binaries that ran this run, in order, each once per
  // change: a long run resumed across sessions can be continued by a newer trainer, and its
  // manifest says so. "unrecorded" stands for training done before checkpoints kept this list.
  std::vector<std::string> trainers;
  std::vector<float> parameters;
  std::vector<float> exp_avg;
  std::vector<float> exp_avg_sq;
};

void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint);
// Validates the file and every field; errors name the file and the field.
Checkpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace deixis::train
