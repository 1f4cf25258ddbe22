#pragma once
// One training run: the schedule of the network's family on prepared examples, with progress per
// epoch, checkpoints, resume, and export of weights + manifest at the end. No libtorch in this
// header.
//
// Output directory layout:
//   checkpoint.safetensors          resume state (checkpoint.h), rewritten every few minutes
//                                   and after every epoch
//   <stem>.safetensors              the weights, the authors' tensor names (e.g. MPNet(MoE)(AC))
//   <stem>.manifest.json            manifest.h

#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "train/checkpoint.h"
#include "train/clips.h"
#include "train/network_kind.h"
#include "train/schedule.h"

namespace deixis::train {

struct TrainOptions {
  Network network = Network::kMpnetMoe;
  Variant variant = Variant::kAllCategories;
  Hand hand = Hand::kRight;
  Schedule schedule;
  std::uint64_t seed = 1;
  int threads = 1;
  std::filesystem::path out_dir;
  double checkpoint_seconds = 120;      // also after every epoch
  std::int64_t checkpoint_batches = 0;  // > 0: also every that many batches (tests)
  bool restart = false;                 // ignore an existing checkpoint
  std::int64_t max_batches = 0;         // > 0: at most that many batches per epoch (timing)
  // The MoE networks and the autoencoder run through their direct steps (moe_step.h,
  // autoencoder_step.h) unless this asks for libtorch's autograd (the same maths, slower; for
  // comparison and measurement).
  bool autograd = false;
  // Non-empty: train nothing; write the weights and manifest of out_dir's checkpoint (a run in
  // progress, or a finished one) into this directory. The checkpoint is only read.
  std::filesystem::path export_to;
  // Non-empty: exported weights (the authors' tensor names, this network's shapes) the run starts
  // from instead of a random initialisation, for fine-tuning (schedule.h continued); the
  // optimiser's moments start at zero. Its SHA-256 is part of the run's identity.
  std::filesystem::path initial_weights;
  std::string command_line;
  std::string dataset_hash;
  std::vector<std::string> dataset_files;
};

// Examples cut for the network's family (clips.h): MPNet and UGNet clips, autoencoder segments.
struct TrainingData {
  ExampleSet train;
  ExampleSet validation;  // may be empty
};

struct TrainOutcome {
  std::vector<EpochReport> history;
  std::filesystem::path weights;
  std::filesystem::path manifest;
  double train_seconds = 0;
  bool resumed = false;
};

// Throws deixis::Error on bad options, a checkpoint from a different run, or (export_to) no
// checkpoint to export.
TrainOutcome train(const TrainOptions& options, const TrainingData& data, std::ostream& log);

}  // namespace deixis::train
