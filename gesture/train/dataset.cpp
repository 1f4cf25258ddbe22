#include "gesture/train/dataset.h"

#include <cmath>
#include <cstring>

#include "gesture/error.h"

namespace deixis::train {

namespace {

std::vector<std::int64_t> read_i64(const SafetensorsFile& file, const std::string& name) {
  const TensorInfo* info = file.find(name);
  if (info == nullptr) {
    throw Error(file.source() + ": tensor '" + name + "' missing");
  }
  if (info->dtype != DType::kI64 || info->shape.size() != 1) {
    throw Error(file.source() + ": tensor '" + name + "': expected I64 [sequences], found " +
                std::string(dtype_name(info->dtype)) + " " + shape_string(info->shape));
  }
  const std::span<const std::byte> bytes = file.bytes(*info);
  std::vector<std::int64_t> values(static_cast<std::size_t>(info->shape[0]));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(std::int64_t));
  return values;
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
  const std::vector<float> features = read_rows(file, "features", kFeatureColumns, frames);
  const std::vector<float> progression =
      read_rows(file, "progression", kProgressionColumns, frames);
  const std::vector<float> pose = read_rows(file, "pose", kPoseColumns, frames);
  const std::vector<std::int64_t> counts = read_i64(file, "sequence_frames");
  const std::vector<std::int64_t> categories = read_i64(file, "sequence_category");
  if (counts.size() != categories.size()) {
    throw Error(file.source() + ": tensor 'sequence_category' has " +
                std::to_string(categories.size()) + " entries, 'sequence_frames' has " +
                std::to_string(counts.size()));
  }
  for (std::size_t i = 0; i < progression.size(); ++i) {
    if (progression[i] < 0.0f || progression[i] > 1.0f) {
      throw Error(file.source() + ": tensor 'progression': value " +
                  std::to_string(progression[i]) + " at frame " +
                  std::to_string(i / kProgressionColumns) + " is outside [0, 1]");
    }
  }
  Dataset out;
  out.source = file.source();
  std::int64_t first = 0;
  for (std::size_t s = 0; s < counts.size(); ++s) {
    if (counts[s] < 1 || counts[s] > frames - first) {
      throw Error(file.source() + ": tensor 'sequence_frames': entry " + std::to_string(s) +
                  " is " + std::to_string(counts[s]) + ", but only " +
                  std::to_string(frames - first) + " frames are left");
    }
    if (categories[s] < 0 || categories[s] >= kCategoryCount) {
      throw Error(file.source() + ": tensor 'sequence_category': entry " + std::to_string(s) +
                  " is " + std::to_string(categories[s]) + ", expected 0–9");
    }
    Sequence seq;
    seq.category = static_cast<Category>(categories[s]);
    seq.frames = static_cast<int>(counts[s]);
    auto slice = [&](const std::vector<float>& v, int columns) {
      const auto begin = v.begin() + first * columns;
      return std::vector<float>(begin, begin + counts[s] * columns);
    };
    seq.features = slice(features, kFeatureColumns);
    seq.progression = slice(progression, kProgressionColumns);
    seq.pose = slice(pose, kPoseColumns);
    out.sequences.push_back(std::move(seq));
    first += counts[s];
  }
  if (first != frames) {
    throw Error(file.source() + ": tensor 'sequence_frames' adds up to " + std::to_string(first) +
                " frames, the data have " + std::to_string(frames));
  }
  return out;
}

SafetensorsWriter dataset_writer(const std::vector<Sequence>& sequences) {
  std::vector<float> features, progression, pose;
  std::vector<std::int64_t> counts, categories;
  for (const Sequence& s : sequences) {
    features.insert(features.end(), s.features.begin(), s.features.end());
    progression.insert(progression.end(), s.progression.begin(), s.progression.end());
    pose.insert(pose.end(), s.pose.begin(), s.pose.end());
    counts.push_back(s.frames);
    categories.push_back(static_cast<std::int64_t>(s.category));
  }
  const auto frames = static_cast<std::int64_t>(counts.empty() ? 0 : progression.size() / 3);
  const auto n = static_cast<std::int64_t>(counts.size());
  SafetensorsWriter writer;
  writer.add_f32("features", {frames, kFeatureColumns}, features);
  writer.add_f32("progression", {frames, kProgressionColumns}, progression);
  writer.add_f32("pose", {frames, kPoseColumns}, pose);
  writer.add_i64("sequence_frames", {n}, counts);
  writer.add_i64("sequence_category", {n}, categories);
  return writer;
}

}  // namespace deixis::train
