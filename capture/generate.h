#pragma once
// The capture's datasets (docs/dataset.md; paper §III): the training subject's sequences with speed
// augmentation and a mirrored (left-handed) copy, and test and validation sets of other subjects,
// each a safetensors file in one directory:
//   train_right.safetensors      training subject; ×1, ×0.5, ×2 for the single/two-target
//   categories train_left.safetensors       the same sequences mirrored (a left-handed person)
//   test_<subject>.safetensors   per test subject, per category counts as the authors'
//   validation_<subject>.safetensors   extra subjects (FMD autoencoder validation)
// Every sequence's seed is derived from (seed, set, subject, category, index), so a sequence can
// be re-performed alone (`deixis capture preview`) and the same options give identical files.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "capture/sequence.h"
#include "capture/subject.h"

namespace deixis::capture {

inline constexpr std::string_view kTrainingSet = "train";
inline constexpr std::string_view kTestSet = "test";
inline constexpr std::string_view kValidationSet = "validation";

// Sequences per category: at least the authors' training counts (docs/dataset.md#files;
// single-target categories ×3, standing in for their unpublished easing augmentation), and their
// test counts.
int training_count(Category category);
int test_count(Category category);

// Pointing sequences the training set adds to a pointing category of `count` sequences, with
// targets under low_target_rules (indices count, count + 1, …): round(count × 25/55), the same
// number per degree of elevation as the first range's 55° holds. Zero for other categories.
int low_target_count(Category category, int count);

struct GenerateOptions {
  std::filesystem::path out_dir;
  std::uint64_t seed = 1;
  std::vector<std::string> sets = {"train", "test", "validation"};
  std::vector<std::string> subjects;  // empty: every subject of each set
  double count_scale = 1.0;           // scales every per-category count (each stays ≥ 1)
  bool low_targets = true;            // false: the training set without low_target_count's
  std::string train_noise = "mocap";
  std::string test_noise = "headset";
};

struct GeneratedFile {
  std::filesystem::path path;
  std::size_t sequences = 0;
  std::size_t frames = 0;
  double seconds = 0;
};

// Called after every sequence: file name, sequences done, sequences in the file, frames so far.
using GenerateProgress = std::function<void(const std::string& file, std::size_t done,
                                            std::size_t total, std::size_t frames)>;

// Validates the options (unknown set, subject or noise, bad scale: deixis::Error) and writes the
// files.
std::vector<GeneratedFile> generate_datasets(const GenerateOptions& options,
                                             const GenerateProgress& progress);

// The seed of one sequence of a set.
std::uint64_t sequence_seed(std::uint64_t seed, std::string_view set, std::string_view subject,
                            Category category, int index);

// The seed of the tracker noise on a recording played at `speed`.
std::uint64_t noise_seed(std::uint64_t sequence_seed, float speed);

// One sequence exactly as `generate_datasets` records it, at `count_scale`, before augmentation
// and noise. Training indices from the category's (scaled) count on are the low-target additions.
Sequence clean_sequence(std::uint64_t seed, std::string_view set, const Subject& subject,
                        Category category, int index, double count_scale = 1.0);

}  // namespace deixis::capture
