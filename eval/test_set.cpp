#include "eval/test_set.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/io/safetensors.h"

namespace deixis::eval {

namespace {

namespace fs = std::filesystem;

const std::string& metadata(const SafetensorsFile& file, const char* key) {
  return file.metadata_value(key);
}

// The held-out guard: a training set or the training subject's data is refused outright, so
// that no reported number can come from the subject the networks were trained on.
void refuse_training_data(const SafetensorsFile& file) {
  const std::string& set = metadata(file, "set");
  const std::string& subject = metadata(file, "subject");
  if (set == "train" || subject == kTrainingSubject) {
    throw Error(file.source() + ": metadata set=" + set + ", subject=" + subject +
                " is the training subject's data; deixis eval reports held-out subjects only "
                "(test_<subject>.safetensors of 161, 172, 173, 174, 180)");
  }
  if (set != "test" && set != "validation") {
    throw Error(file.source() + ": metadata set=" + set + ", expected test or validation");
  }
}

float parse_height(const SafetensorsFile& file) {
  const std::string& text = metadata(file, "height");
  try {
    const float h = std::stof(text);
    if (std::isfinite(h) && h > 0.5f && h < 2.5f) {
      return h;
    }
  } catch (const std::exception&) {
  }
  throw Error(file.source() + ": metadata height=" + text + " is not a height in metres");
}

Vec3 vec3_at(const std::vector<float>& v, std::size_t row) {
  return {v[row * 3], v[row * 3 + 1], v[row * 3 + 2]};
}

}  // namespace

TestSet TestSet::read(const fs::path& path) {
  const SafetensorsFile file = SafetensorsFile::read(path);
  refuse_training_data(file);
  TestSet t;
  t.subject_ = metadata(file, "subject");
  const std::string& hand = metadata(file, "deictic_hand");
  if (hand != "right" && hand != "left") {
    throw Error(file.source() + ": metadata deictic_hand=" + hand + ", expected right or left");
  }
  t.hand_ = hand == "left" ? Hand::kLeft : Hand::kRight;
  t.height_ = parse_height(file);
  t.data_ = dataset::Dataset::read(file);
  for (std::size_t s = 0; s < t.data_.sequences(); ++s) {
    t.bodies_.push_back(t.data_.calibration(s));
    t.bodies_.back().deictic_hand = t.hand_;  // the person's, as the metadata says
  }
  return t;
}

std::vector<std::size_t> TestSet::of_category(dataset::Category c) const {
  std::vector<std::size_t> out;
  for (std::size_t s = 0; s < sequences(); ++s) {
    if (category(s) == c) {
      out.push_back(s);
    }
  }
  return out;
}

std::span<const float, kMpnetFeatureCount> TestSet::features(std::size_t s, std::size_t k) const {
  return std::span<const float, kMpnetFeatureCount>(
      data_.mpnet_features.data() + (data_.begin(s) + k) * kMpnetFeatureCount, kMpnetFeatureCount);
}

std::span<const float, kEndEffectorSize> TestSet::end_effectors(std::size_t s,
                                                                std::size_t k) const {
  return std::span<const float, kEndEffectorSize>(
      data_.end_effectors.data() + (data_.begin(s) + k) * kEndEffectorSize, kEndEffectorSize);
}

std::span<const float, kTargetFeatureSize> TestSet::target_feature(std::size_t s,
                                                                   std::size_t k) const {
  return std::span<const float, kTargetFeatureSize>(
      data_.target_feature.data() + (data_.begin(s) + k) * kTargetFeatureSize, kTargetFeatureSize);
}

std::array<float, 3> TestSet::labels(std::size_t s, std::size_t k) const {
  const std::size_t row = data_.begin(s) + k;
  return {data_.labels[row * 3], data_.labels[row * 3 + 1], data_.labels[row * 3 + 2]};
}

bool TestSet::phase_key(std::size_t s, std::size_t k) const {
  return data_.phase_key[data_.begin(s) + k] != 0;
}

Vec3 TestSet::hand_target_in_root(std::size_t s, std::size_t k) const {
  const Vec3 world = vec3_at(data_.hand_target_position, data_.begin(s) + k);
  return to_network_frame(transform_point(inverse(bodies_[s].T_world_root), world));
}

TrackingFrame TestSet::tracking(std::size_t s, std::size_t k) const {
  return data_.tracking(data_.begin(s) + k);
}

std::vector<fs::path> test_files(const fs::path& dir, std::span<const std::string> subjects) {
  std::vector<fs::path> files;
  if (!fs::is_directory(dir)) {
    throw Error(dir.string() + ": not a directory");
  }
  if (!subjects.empty()) {
    for (const std::string& s : subjects) {
      files.push_back(dir / ("test_" + s + ".safetensors"));
      if (!fs::exists(files.back())) {
        throw Error(files.back().string() + ": no such file (subject " + s + ")");
      }
    }
    return files;
  }
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("test_") && name.ends_with(".safetensors")) {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    throw Error(dir.string() +
                ": no test_<subject>.safetensors files (run `deixis capture generate` first)");
  }
  return files;
}

}  // namespace deixis::eval
