#include "train/dataset.h"

#include <cmath>
#include <cstring>

#include "core/error.h"

namespace deixis::train {

namespace {

// A 1-D integer tensor of the given dtype (I64 or I32), widened to int64.
std::vector<std::int64_t> read_integers(const SafetensorsFile& file, const std::string& name,
                                        DType dtype, std::int64_t count) {
  const TensorInfo* info = file.find(name);
  if (info == nullptr) {
    throw Error(file.source() + ": tensor '" + name + "' missing");
  }
  if (info->dtype != dtype || info->shape.size() != 1 || info->shape[0] != count) {
    throw Error(file.source() + ": tensor '" + name + "': expected " +
                std::string(dtype_name(dtype)) + " [" + std::to_string(count) + "], found " +
                std::string(dtype_name(info->dtype)) + " " + shape_string(info->shape));
  }
  const std::span<const std::byte> bytes = file.bytes(*info);
  std::vector<std::int64_t> values(static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (dtype == DType::kI64) {
      std::memcpy(&values[i], bytes.data() + i * 8, 8);
    } else {
      std::int32_t v = 0;
      std::memcpy(&v, bytes.data() + i * 4, 4);
      values[i] = v;
    }
  }
  return values;
}

// The number of sequences, from sequence_offsets' length.
std::int64_t sequence_count(const SafetensorsFile& file) {
  const TensorInfo* info = file.find("sequence_offsets");
  if (info == nullptr) {
    throw Error(file.source() + ": tensor 'sequence_offsets' missing");
  }
  if (info->shape.size() != 1 || info->shape[0] < 2) {
    throw Error(file.source() +
                ": tensor 'sequence_offsets': expected [sequences + 1] with at "
                "least one sequence, found " +
                shape_string(info->shape));
  }
  return info->shape[0] - 1;
}

// Rows of a [frames, columns] F32 tensor; `frames` from the first tensor read.
std::vector<float> read_rows(const SafetensorsFile& file, const std::string& name, int columns,
                             std::int64_t& frames) {
  const TensorInfo* info = file.find(name);
  if (info == nullptr) {
    throw Error(file.source() + ": tensor '" + name + "' missing");
  }
  if (info->shape.size() != 2 || info->shape[1] != columns) {
    throw Error(file.source() + ": tensor '" + name + "': expected shape [frames, " +
                std::to_string(columns) + "], found " + shape_string(info->shape));
  }
  if (frames < 0) {
    frames = info->shape[0];
  }
  const std::int64_t shape[] = {frames, columns};
  return file.read_f32(name, shape);  // checks dtype, the agreed frame count, finite values
}

}  // namespace

Dataset read_dataset(const std::filesystem::path& path) {
  return read_dataset(SafetensorsFile::read(path));
}

Dataset read_dataset(const SafetensorsFile& file) {
  std::int64_t frames = -1;
  const std::vector<float> features = read_rows(file, "mpnet_features", kFeatureColumns, frames);
  const std::vector<float> progression = read_rows(file, "labels", kProgressionColumns, frames);
  const std::vector<float> pose = read_rows(file, "end_effectors", kPoseColumns, frames);
  const std::int64_t sequences = sequence_count(file);
  const std::vector<std::int64_t> offsets =
      read_integers(file, "sequence_offsets", DType::kI64, sequences + 1);
  const std::vector<std::int64_t> categories =
      read_integers(file, "sequence_category", DType::kI32, sequences);
  for (std::size_t i = 0; i < progression.size(); ++i) {
    if (progression[i] < 0.0f || progression[i] > 1.0f) {
      throw Error(file.source() + ": tensor 'labels': value " + std::to_string(progression[i]) +
                  " at frame " + std::to_string(i / kProgressionColumns) + " is outside [0, 1]");
    }
  }
  if (offsets.front() != 0 || offsets.back() != frames) {
    throw Error(file.source() + ": tensor 'sequence_offsets': runs from " +
                std::to_string(offsets.front()) + " to " + std::to_string(offsets.back()) +
                ", expected 0 to " + std::to_string(frames) + " (the frame count)");
  }
  Dataset out;
  out.source = file.source();
  const auto hand = file.metadata().find("deictic_hand");
  if (hand != file.metadata().end() && hand->second != "right" && hand->second != "left") {
    throw Error(file.source() + ": __metadata__.deictic_hand: expected right or left, found \"" +
                hand->second + "\"");
  }
  out.hand = hand != file.metadata().end() && hand->second == "left" ? Hand::kLeft : Hand::kRight;
  for (std::size_t s = 0; s < static_cast<std::size_t>(sequences); ++s) {
    const std::int64_t first = offsets[s];
    const std::int64_t count = offsets[s + 1] - first;
    if (count < 1) {
      throw Error(file.source() + ": tensor 'sequence_offsets': sequence " + std::to_string(s) +
                  " has " + std::to_string(count) + " frames (offsets must increase)");
    }
    if (categories[s] < 0 || categories[s] >= kCategoryCount) {
      throw Error(file.source() + ": tensor 'sequence_category': entry " + std::to_string(s) +
                  " is " + std::to_string(categories[s]) + ", expected 0–9");
    }
    Sequence seq;
    seq.category = static_cast<Category>(categories[s]);
    seq.frames = static_cast<int>(count);
    auto slice = [&](const std::vector<float>& v, int columns) {
      const auto begin = v.begin() + first * columns;
      return std::vector<float>(begin, begin + count * columns);
    };
    seq.features = slice(features, kFeatureColumns);
    seq.progression = slice(progression, kProgressionColumns);
    seq.pose = slice(pose, kPoseColumns);
    out.sequences.push_back(std::move(seq));
  }
  return out;
}

SafetensorsWriter dataset_writer(const std::vector<Sequence>& sequences) {
  std::vector<float> features, progression, pose;
  std::vector<std::int64_t> offsets = {0};
  std::vector<std::int32_t> categories;
  for (const Sequence& s : sequences) {
    features.insert(features.end(), s.features.begin(), s.features.end());
    progression.insert(progression.end(), s.progression.begin(), s.progression.end());
    pose.insert(pose.end(), s.pose.begin(), s.pose.end());
    offsets.push_back(offsets.back() + s.frames);
    categories.push_back(static_cast<std::int32_t>(s.category));
  }
  const std::int64_t frames = offsets.back();
  const auto n = static_cast<std::int64_t>(sequences.size());
  SafetensorsWriter writer;
  writer.set_metadata("schema", "deixis-capture/1");
  writer.set_metadata("deictic_hand", "right");
  writer.add_f32("mpnet_features", {frames, kFeatureColumns}, features);
  writer.add_f32("labels", {frames, kProgressionColumns}, progression);
  writer.add_f32("end_effectors", {frames, kPoseColumns}, pose);
  writer.add_i64("sequence_offsets", {n + 1}, offsets);
  writer.add("sequence_category", DType::kI32, {n}, std::as_bytes(std::span(categories)));
  return writer;
}

}  // namespace deixis::train
