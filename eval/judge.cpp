#include "eval/judge.h"

#include <algorithm>
#include <cmath>

#include "dataset/dataset.h"
#include "eval/test_set.h"
#include "gesture/nn/mpnet.h"

namespace deixis::eval {

namespace {

namespace fs = std::filesystem;
using dataset::Dataset;
using dataset::Labels;
constexpr int kRows = nn::kWindowRows;
constexpr int kCols = nn::kMpnetFeatures;

// MPE of one sequence: rows [begin, end) of the dataset against their labels.
MpeSum sequence_mpe(const nn::Mpnet& net, const Dataset& d, std::size_t begin, std::size_t end) {
  const std::span<const float> rows(d.mpnet_features.data() + begin * kCols, (end - begin) * kCols);
  const std::vector<Labels> p = predict_progressions(net, rows);
  MpeSum sum;
  for (std::size_t t = 0; t < p.size(); ++t) {
    for (int k = 0; k < 3; ++k) {
      sum.error[k] += std::abs(static_cast<double>(p[t][k] - d.labels[(begin + t) * 3 + k]));
    }
    ++sum.frames;
  }
  return sum;
}

}  // namespace

std::vector<Labels> predict_progressions(const nn::Mpnet& net, std::span<const float> rows) {
  const std::size_t n = rows.size() / kCols;
  std::vector<Labels> out(n);
  std::array<float, nn::kMpnetWindowSize> window{};
  for (std::size_t t = 0; t < n; ++t) {
    // Rows t−29 … t; the first row stands in for rows before the sequence (29 copies, as MPE
    // does: docs/eval.md#what-each-number-is).
    for (int r = 0; r < kRows; ++r) {
      const long source = std::max(0L, static_cast<long>(t) - (kRows - 1) + r);
      std::copy_n(rows.begin() + source * kCols, kCols, window.begin() + r * kCols);
    }
    const nn::Progression p = net.run(window).progression;
    out[t] = {p[0], p[1], p[2]};
  }
  return out;
}

std::filesystem::path authors_checkpoint(const std::filesystem::path& reference_dir, Hand hand,
                                         const std::string& name) {
  return reference_dir / "weights" / (hand == Hand::kLeft ? "left" : "right") / name;
}

void MpeSum::add(const MpeSum& other) {
  for (int k = 0; k < 3; ++k) {
    error[k] += other.error[k];
  }
  frames += other.frames;
}

std::vector<SubjectVerdict> judge(const JudgeOptions& options) {
  const fs::path right_path =
      authors_checkpoint(options.reference_dir, Hand::kRight, options.checkpoint);
  const fs::path left_path =
      authors_checkpoint(options.reference_dir, Hand::kLeft, options.checkpoint);
  const nn::Mpnet right = nn::Mpnet::load(right_path);
  std::vector<SubjectVerdict> verdicts;
  for (const fs::path& file : test_files(options.dataset_dir, options.subjects)) {
    const Dataset d = Dataset::read(file);
    SubjectVerdict v;
    v.subject = d.metadata.count("subject") ? d.metadata.at("subject") : file.stem().string();
    v.left_handed = d.metadata.count("deictic_hand") && d.metadata.at("deictic_hand") == "left";
    v.checkpoint = (v.left_handed ? left_path : right_path).string();
    const nn::Mpnet net = v.left_handed ? nn::Mpnet::load(left_path) : right;
    for (std::size_t s = 0; s < d.sequences(); ++s) {
      const MpeSum m = sequence_mpe(net, d, d.begin(s), d.end(s));
      v.categories[static_cast<std::size_t>(d.sequence_category[s])].add(m);
      v.all.add(m);
    }
    verdicts.push_back(std::move(v));
  }
  return verdicts;
}

}  // namespace deixis::eval
