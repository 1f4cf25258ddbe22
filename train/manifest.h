#pragma once
// The manifest written next to exported weights: how they were made, so that a figure or a
// shipped file can be traced to its command, data and code.

#include <cstdint>
#include <filesystem>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "train/checkpoint.h"
#include "train/schedule.h"

namespace deixis::train {

// The FMD autoencoder's average per-frame reconstruction error of head and hand
// (train/reconstruction.h computes it).
struct ReconstructionError {
  double position_cm = std::numeric_limits<double>::quiet_NaN();
  double rotation_deg = std::numeric_limits<double>::quiet_NaN();
  std::size_t segments = 0;
};

struct Manifest {
  std::string weights_file;  // file name of the weights this describes
  std::string network;       // "MPNet(MoE)"
  std::string variant;       // "AC" / "DG"
  std::string hand;          // "right" / "left"
  std::string command_line;
  std::uint64_t seed = 0;
  int threads = 1;
  std::string commit;  // the exporting binary's build_commit()
  // The build commits of the binaries that trained the run, in order (Checkpoint::trainers).
  std::vector<std::string> trained_by;
  std::string dataset_hash;  // sha256 over the dataset files' hashes (dataset_hash())
  std::vector<std::string> dataset_files;
  // Fine-tuning (--init-weights): the weights the run started from, as given and their SHA-256.
  struct InitialWeights {
    std::string file, sha256;
  };
  std::optional<InitialWeights> initial_weights;
  std::size_t train_examples = 0;
  std::size_t validation_examples = 0;
  std::size_t parameter_count = 0;
  Schedule schedule;
  double train_seconds = 0;  // wall time spent training, summed over resumed runs
  std::vector<EpochReport> history;
  // Whether the schedule ran to its end. Weights exported from a run in progress (--export-to)
  // say where it stood: the next epoch to run and the batches of it already done.
  bool complete = true;
  int stopped_at_epoch = 0;
  std::int64_t stopped_at_batch = 0;
  // The autoencoder only: its reconstruction of the training and the validation segments.
  std::optional<ReconstructionError> training_reconstruction, validation_reconstruction;
};

void write_manifest(const std::filesystem::path& path, const Manifest& manifest);

// SHA-256 of a file's bytes, lower-case hex.
std::string sha256_file(const std::filesystem::path& path);
// SHA-256 of the concatenated per-file hashes, in the given order.
std::string dataset_hash(const std::vector<std::filesystem::path>& files);
// `git describe --always --dirty` of the source tree this binary was built from (taken at build
// time), or "unknown".
std::string build_commit();

}  // namespace deixis::train
