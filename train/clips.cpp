#include "train/clips.h"

#include <algorithm>

#include "core/math/network_frame.h"
#include "train/schedule.h"

namespace deixis::train {

std::vector<Sequence> training_sequences(const dataset::Dataset& file) {
  std::vector<Sequence> out;
  out.reserve(file.sequences());
  for (std::size_t s = 0; s < file.sequences(); ++s) {
    Sequence seq;
    seq.category = static_cast<Category>(file.sequence_category[s]);
    seq.frames = static_cast<int>(file.end(s) - file.begin(s));
    const auto slice = [&](const std::vector<float>& v, int columns) {
      const auto first = v.begin() + static_cast<std::ptrdiff_t>(file.begin(s) * columns);
      return std::vector<float>(first, first + static_cast<std::ptrdiff_t>(seq.frames * columns));
    };
    seq.features = slice(file.mpnet_features, kFeatureColumns);
    seq.progression = slice(file.labels, kProgressionColumns);
    seq.pose = slice(file.end_effectors, kPoseColumns);
    out.push_back(std::move(seq));
  }
  return out;
}

std::span<const float> ExampleSet::example(std::size_t i) const {
  return std::span<const float>(values).subspan(i * example_size(), example_size());
}

std::vector<int> clip_starts(int frames, int clip_rows, int hop) {
  std::vector<int> starts;
  if (frames < clip_rows) {
    return starts;
  }
  starts.push_back(frames - clip_rows);
  for (int start = 0; start + clip_rows <= frames; start += hop) {
    starts.push_back(start);
  }
  return starts;
}

namespace {

// Cuts `rows` (frames × columns) into clips and appends them to `out`.
void append_clips(std::span<const float> rows, int frames, int clip_rows, int hop,
                  ExampleSet& out) {
  const std::size_t columns = static_cast<std::size_t>(out.columns);
  for (const int start : clip_starts(frames, clip_rows, hop)) {
    const auto first = rows.begin() + static_cast<std::ptrdiff_t>(start * columns);
    out.values.insert(out.values.end(), first,
                      first + static_cast<std::ptrdiff_t>(clip_rows * columns));
    ++out.count;
  }
}

// The head part of x (gaze 3, head 6D 6, head position 3) and the hand part (the rest).
constexpr int kHeadPart = 12;

}  // namespace

ExampleSet mpnet_clips(std::span<const Sequence> sequences) {
  ExampleSet out{kClipRows, kMpnetClipColumns, 0, {}};
  std::vector<float> rows;
  for (const Sequence& s : sequences) {
    rows.resize(static_cast<std::size_t>(s.frames) * kMpnetClipColumns);
    for (int f = 0; f < s.frames; ++f) {
      float* row = rows.data() + static_cast<std::size_t>(f) * kMpnetClipColumns;
      std::copy_n(s.features.data() + static_cast<std::size_t>(f) * kFeatureColumns,
                  kFeatureColumns, row);
      std::copy_n(s.progression.data() + static_cast<std::size_t>(f) * kProgressionColumns,
                  kProgressionColumns, row + kFeatureColumns);
    }
    append_clips(rows, s.frames, kClipRows, kClipHop, out);
  }
  return out;
}

ExampleSet ugnet_clips(std::span<const Sequence> sequences) {
  ExampleSet out{kClipRows, kUgnetClipColumns, 0, {}};
  std::vector<float> rows;
  for (const Sequence& s : sequences) {
    if (s.frames < 2) {
      continue;
    }
    const int pairs = s.frames - 1;
    const bool hold = has_free_form(s.category);
    rows.resize(static_cast<std::size_t>(pairs) * kUgnetClipColumns);
    for (int i = 0; i < pairs; ++i) {
      float* row = rows.data() + static_cast<std::size_t>(i) * kUgnetClipColumns;
      const float* x_now = s.pose.data() + static_cast<std::size_t>(i) * kPoseColumns;
      const float* x_next = x_now + kPoseColumns;
      const float* features_next =
          s.features.data() + static_cast<std::size_t>(i + 1) * kFeatureColumns;
      const float* progression_next =
          s.progression.data() + static_cast<std::size_t>(i + 1) * kProgressionColumns;
      std::copy_n(x_now, kPoseColumns, row);
      std::copy_n(features_next + kTargetFeatureColumn, 5, row + kPoseColumns);
      std::copy_n(progression_next, kProgressionColumns, row + kPoseColumns + 5);
      float* target = row + kPoseColumns + 8;
      std::copy_n(x_next, kPoseColumns, target);
      if (hold) {
        // data_parser.py: x_i + delta with delta zeroed where the next frame's progression is 0
        // (strictly: where it is not > 0).
        if (!(progression_next[0] > 0.0f)) {
          std::copy_n(x_now, kHeadPart, target);
        }
        if (!(progression_next[1] > 0.0f)) {
          std::copy_n(x_now + kHeadPart, kPoseColumns - kHeadPart, target + kHeadPart);
        }
      }
    }
    append_clips(rows, pairs, kClipRows, kClipHop, out);
  }
  return out;
}

ExampleSet motion_segments(std::span<const Sequence> sequences) {
  ExampleSet out{kSegmentRows, kMotionColumns, 0, {}};
  std::vector<float> rows;
  for (const Sequence& s : sequences) {
    rows.resize(static_cast<std::size_t>(s.frames) * kMotionColumns);
    for (int f = 0; f < s.frames; ++f) {
      std::copy_n(s.pose.data() + static_cast<std::size_t>(f) * kPoseColumns + kMotionFirstColumn,
                  kMotionColumns, rows.data() + static_cast<std::size_t>(f) * kMotionColumns);
    }
    append_clips(rows, s.frames, kSegmentRows, kSegmentHop, out);
  }
  return out;
}

void mirror(Sequence& sequence) {
  for (int f = 0; f < sequence.frames; ++f) {
    mirror_end_effectors(std::span<float, kEndEffectorSize>(
        sequence.pose.data() + static_cast<std::size_t>(f) * kPoseColumns, kEndEffectorSize));
    mirror_target_feature(std::span<float, kTargetFeatureSize>(
        sequence.features.data() + static_cast<std::size_t>(f) * kFeatureColumns +
            kTargetFeatureColumn,
        kTargetFeatureSize));
  }
}

}  // namespace deixis::train
