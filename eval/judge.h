#pragma once
// A judge no one here wrote: the authors' MPNet MoE, trained on real people, run on the test
// subjects' sequences the way their test_MPNet.py does (docs/eval.md#what-each-number-is): each
// sequence is prefixed with 29 copies of its first row, every 30-row window is fed, and the output
// is compared with the labels of the window's newest row; MPE = mean |p − p̂| per channel,
// total = mean of the three. Right-handed subjects use the right checkpoint, left-handed ones the
// left, each on the rows as stored: gesture/features.h sees every person in their own view, which
// is what the checkpoint of their hand was trained on (docs/decisions.md §17).

#include <array>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "core/tracking.h"
#include "dataset/category.h"
#include "dataset/schema.h"
#include "gesture/nn/mpnet.h"

namespace deixis::eval {

struct MpeSum {
  std::array<double, 3> error{};  // summed |p − p̂| per channel (gaze, deictic, idle)
  std::size_t frames = 0;

  double channel(int k) const { return frames ? error[k] / static_cast<double>(frames) : 0.0; }
  double total() const { return (channel(0) + channel(1) + channel(2)) / 3.0; }
  void add(const MpeSum& other);
};

struct SubjectVerdict {
  std::string subject;
  bool left_handed = false;
  std::string checkpoint;                                  // the one of the authors' protocol
  std::array<MpeSum, dataset::kCategoryCount> categories;  // by dataset::Category
  MpeSum all;
};

struct JudgeOptions {
  std::filesystem::path dataset_dir;    // holds test_<subject>.safetensors
  std::filesystem::path reference_dir;  // the authors' weights: <dir>/weights/{right,left}/
  std::vector<std::string> subjects;    // empty: every test file in the directory
  std::string checkpoint = "MPNet(MoE)(AC)80.safetensors";
};

// Errors (missing files, corrupt datasets or weights) are deixis::Error naming the file.
std::vector<SubjectVerdict> judge(const JudgeOptions& options);

// MPNet's progression for every row of one sequence (rows: n × 11, as stored), as the judge
// computes them. Rows are in the person's own view (gesture/features.h), which is what the
// checkpoint of their hand expects.
std::vector<dataset::Labels> predict_progressions(const nn::Mpnet& net,
                                                  std::span<const float> rows);

// The checkpoint of the authors' protocol for a hand: <reference>/weights/{right,left}/<name>.
std::filesystem::path authors_checkpoint(const std::filesystem::path& reference_dir, Hand hand,
                                         const std::string& name = "MPNet(MoE)(AC)80.safetensors");

}  // namespace deixis::eval
