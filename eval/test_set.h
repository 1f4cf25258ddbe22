#pragma once
// One held-out subject's capture dataset (docs/dataset.md) as the evaluation reads it: the
// validated dataset plus what a tracker and a labeller would also know per sequence (root O,
// upright wrist positions, body), and nothing of the generator's hidden state
// (docs/conventions.md#synthetic-capture).
//
// The held-out guard lives here: no number may come from a training subject, so a file of the
// training set or of subject 170 (the training subject) is refused before it is read.

#include <array>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "core/tracking.h"
#include "dataset/category.h"
#include "dataset/dataset.h"
#include "gesture/features.h"

namespace deixis::eval {

// The training subject (docs/conventions.md#synthetic-capture); its datasets are never evaluated.
inline constexpr const char* kTrainingSubject = "170";
// The avatar of the authors' protocol has the training subject's size
// (docs/conventions.md#blending: scale = user/avatar size ratio, 0.9471 for 161 cm … 1.0588 for
// 180 cm).
inline constexpr float kAvatarHeight = 1.70f;

class TestSet {
 public:
  // Reads and validates `path`; deixis::Error naming the file (and field) when it is unreadable,
  // not a test or validation set, or a training subject's.
  static TestSet read(const std::filesystem::path& path);

  const std::string& subject() const { return subject_; }
  const std::string& source() const { return data_.source; }
  Hand hand() const { return hand_; }
  float height() const { return height_; }
  const dataset::Dataset& data() const { return data_; }

  std::size_t sequences() const { return data_.sequences(); }
  std::size_t length(std::size_t s) const { return data_.end(s) - data_.begin(s); }
  dataset::Category category(std::size_t s) const {
    return static_cast<dataset::Category>(data_.sequence_category[s]);
  }
  // Sequence indices of one category, in file order.
  std::vector<std::size_t> of_category(dataset::Category c) const;

  // Rows of sequence s (local frame index k).
  std::span<const float, kMpnetFeatureCount> features(std::size_t s, std::size_t k) const;
  std::span<const float, kEndEffectorSize> end_effectors(std::size_t s, std::size_t k) const;
  std::span<const float, kTargetFeatureSize> target_feature(std::size_t s, std::size_t k) const;
  std::array<float, 3> labels(std::size_t s, std::size_t k) const;
  bool phase_key(std::size_t s, std::size_t k) const;

  // The hand target's position relative to the sequence's root O, in the network frame
  // (docs/conventions.md#network-frame).
  Vec3 hand_target_in_root(std::size_t s, std::size_t k) const;
  // The person's calibration for sequence s and the tracking frame k as recorded (for
  // perturbing the tracking and recomputing the network columns in the robustness runs).
  const BodyCalibration& body(std::size_t s) const { return bodies_[s]; }
  TrackingFrame tracking(std::size_t s, std::size_t k) const;

 private:
  std::string subject_;
  Hand hand_ = Hand::kRight;
  float height_ = kAvatarHeight;
  dataset::Dataset data_;
  std::vector<BodyCalibration> bodies_;
};

// test_<subject>.safetensors in `dir` for the given subjects (all test files when empty), sorted.
std::vector<std::filesystem::path> test_files(const std::filesystem::path& dir,
                                              std::span<const std::string> subjects);

}  // namespace deixis::eval
