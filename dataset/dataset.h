#pragma once
// The dataset files (docs/dataset.md, schema deixis-capture/1) as safetensors: per frame the raw
// tracking, the targets, the labels, and what the networks read (MPNet's 11 features, the 24
// end-effectors and the target feature); per sequence its category, source recording, seed,
// speed, body and root; the targets of every sequence. Whole sequences are stored; the trainer
// cuts 45-frame clips with a hop of 7 (docs/conventions.md#training-data).
//
// One writer (the capture's `generate`) and one reader (the capture's tools, training and the
// evaluation). The network columns are computed by the writer's caller with the runtime's own
// feature code (gesture/features.h), which dataset/ does not link.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "core/io/safetensors.h"
#include "core/target_map.h"
#include "core/tracking.h"
#include "dataset/category.h"
#include "dataset/schema.h"

namespace deixis::dataset {

// One sequence as the writer takes it: the recording, and the network columns computed from it
// (one row per frame).
struct SequenceRows {
  Category category = Category::kPointingSingle;
  // The file index of the recording this sequence derives from: itself for an original, the
  // original for a speed-augmented copy.
  std::int32_t source = 0;
  std::uint64_t seed = 0;
  float speed = 1.0f;     // 1, or the ×0.5 / ×2 augmentation
  bool mirrored = false;  // the left–right mirror image of a recording
  BodyCalibration body;
  std::span<const TargetObject> targets;
  std::span<const TrackingFrame> frames;
  std::span<const Labels> labels;
  std::span<const std::uint8_t> phase_keys;  // 1 where a label ramp starts or ends
  std::span<const float> mpnet_features;     // frames × kFeatureColumns
  std::span<const float> end_effectors;      // frames × kEndEffectorColumns
};

class DatasetWriter {
 public:
  void set_metadata(std::string key, std::string value);
  // Appends a sequence; a row count that disagrees with the frames' is a deixis::Error.
  void add(const SequenceRows& sequence);
  // The index the next added sequence gets.
  std::int32_t next_index() const { return static_cast<std::int32_t>(categories_.size()); }
  std::size_t frames() const { return time_.size(); }
  std::vector<std::byte> serialize() const;
  void write(const std::filesystem::path& path) const;

 private:
  SafetensorsWriter safetensors() const;

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

// A dataset file read back and validated: the schema's name, every tensor's dtype and shape,
// finite values, offsets tiling the frames and the targets, categories, sources, hands and
// target kinds in range, labels in [0, 1]. Errors (deixis::Error) name the file and the tensor.
struct Dataset {
  std::string source;
  std::map<std::string, std::string> metadata;
  // Whose view the network columns are in (metadata "deictic_hand"; right when absent): a
  // left-handed person's own view is the mirror image of a right-handed one's
  // (docs/decisions.md §17).
  Hand hand = Hand::kRight;
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
  std::vector<std::int64_t> sequence_seed;  // bits of a u64
  std::vector<float> sequence_speed, root_position, root_rotation, rest_wrist_in_root, body;
  std::vector<std::uint8_t> sequence_mirrored, deictic_hand;
  // Targets of all sequences.
  std::vector<std::int64_t> target_offsets;  // S + 1
  std::vector<std::int32_t> target_id;
  std::vector<std::uint8_t> target_kind;
  std::vector<float> target_position, target_size;

  std::size_t sequences() const { return sequence_category.size(); }
  std::size_t begin(std::size_t s) const { return static_cast<std::size_t>(sequence_offsets[s]); }
  std::size_t end(std::size_t s) const { return static_cast<std::size_t>(sequence_offsets[s + 1]); }

  // Frame `row` (an index into the per-frame tensors) as the tracker reported it.
  TrackingFrame tracking(std::size_t row) const;
  // Sequence s's body calibration: root O, upright wrists, height and arm length, deictic hand.
  BodyCalibration calibration(std::size_t s) const;

  static Dataset read(const std::filesystem::path& path);
  static Dataset read(const SafetensorsFile& file);
};

}  // namespace deixis::dataset
