#pragma once
// Capture datasets as safetensors (schema in docs/dataset.md): per frame the raw tracking, the
// targets, the labels, and what the networks read — MPNet's 11 features, the 24 end-effectors
// and the target feature — computed by the runtime's own feature code (gesture/features.h), so
// training and runtime share one implementation. Whole sequences are stored; the trainer cuts
// 45-frame clips with a hop of 7 (docs/conventions.md#training-data).

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "capture/sequence.h"

namespace deixis::capture {

inline constexpr const char* kDatasetSchema = "deixis-capture/1";

class DatasetWriter {
 public:
  void set_metadata(std::string key, std::string value);
  // Appends a sequence; `source` is the file index of the recording it derives from (itself for
  // an original, the original for a speed-augmented copy).
  void add(const Sequence& sequence, std::int32_t source);
  // The index the next added sequence gets.
  std::int32_t next_index() const { return static_cast<std::int32_t>(categories_.size()); }
  std::size_t frames() const { return time_.size(); }
  void write(const std::filesystem::path& path) const;

 private:
  std::map<std::string, std::string> metadata_;
  // Per frame.
  std::vector<float> time_, head_position_, head_rotation_, gaze_, wrist_position_, wrist_rotation_,
      index_tip_, head_target_position_, hand_target_position_, labels_, features_, end_effectors_,
      target_feature_;
  std::vector<std::uint8_t> valid_, phase_key_;
  std::vector<std::int32_t> head_target_, hand_target_, frame_category_, frame_sequence_;
  // Per sequence.
  std::vector<std::int64_t> offsets_{0}, seeds_, target_offsets_{0};
  std::vector<std::int32_t> categories_, sources_;
  std::vector<float> speeds_, root_position_, root_rotation_, rest_wrist_, body_;
  std::vector<std::uint8_t> mirrored_, deictic_hand_;
  // Targets of all sequences.
  std::vector<std::int32_t> target_id_;
  std::vector<std::uint8_t> target_kind_;
  std::vector<float> target_position_, target_size_;
};

// A dataset file read back and validated (shapes agree, offsets tile the frames, ids in range,
// labels in [0, 1]); errors name the file and the tensor.
struct Dataset {
  std::string source;
  std::map<std::string, std::string> metadata;
  std::size_t frames = 0;
  // Per frame (row-major, widths as in docs/dataset.md).
  std::vector<float> time, head_position, head_rotation, gaze, wrist_position, wrist_rotation,
      index_tip, head_target_position, hand_target_position, labels, mpnet_features, end_effectors,
      target_feature;
  std::vector<std::uint8_t> valid, phase_key;
  std::vector<std::int32_t> head_target_id, hand_target_id, category, sequence;
  // Per sequence.
  std::vector<std::int64_t> sequence_offsets;  // S + 1
  std::vector<std::int32_t> sequence_category, sequence_source;
  std::vector<float> sequence_speed;
  std::vector<std::uint8_t> sequence_mirrored, deictic_hand;

  std::size_t sequences() const { return sequence_category.size(); }
  std::size_t begin(std::size_t s) const { return static_cast<std::size_t>(sequence_offsets[s]); }
  std::size_t end(std::size_t s) const { return static_cast<std::size_t>(sequence_offsets[s + 1]); }

  static Dataset read(const std::filesystem::path& path);
};

}  // namespace deixis::capture
