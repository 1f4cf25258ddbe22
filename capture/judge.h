#pragma once
// A judge no one here wrote: the authors' MPNet MoE, trained on real people, run on the test
// subjects' sequences the way their test_MPNet.py does (NOTES §7.1): each sequence is prefixed
// with 29 copies of its first row, every 30-row window is fed, and the output is compared with
// the labels of the window's newest row; MPE = mean |p − p̂| per channel, total = mean of the
// three. Right-handed subjects use the right checkpoint, left-handed ones the left.
//
// The datasets store MPNet rows as gesture/features.h computes them, which mirrors a left-handed
// person into the right-handed view (θ^H and θ^R negated). The authors' left checkpoint was
// trained on mirrored right-handed data, i.e. on left-handed people seen *unmirrored*, so for it
// the judge negates both θ back (docs/decisions.md). It also reports the right checkpoint on the
// rows as stored, for comparison.

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "capture/category.h"
#include "capture/sequence.h"
#include "gesture/nn/mpnet.h"

namespace deixis::capture {

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
  std::string checkpoint;                         // the one of the authors' protocol
  std::array<MpeSum, kCategoryCount> categories;  // by Category
  MpeSum all;
  MpeSum right_checkpoint_on_stored_rows;  // left-handed subjects only: the comparison
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
// computes them; `unmirror_theta` negates both θ first (the left checkpoint, see above).
std::vector<Labels> predict_progressions(const nn::Mpnet& net, std::span<const float> rows,
                                         bool unmirror_theta);

// The checkpoint of the authors' protocol for a hand: <reference>/weights/{right,left}/<name>.
std::filesystem::path authors_checkpoint(const std::filesystem::path& reference_dir, Hand hand,
                                         const std::string& name = "MPNet(MoE)(AC)80.safetensors");

}  // namespace deixis::capture
