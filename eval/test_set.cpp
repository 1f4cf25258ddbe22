#include "eval/test_set.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/io/safetensors.h"

namespace deixis::eval {

namespace {

namespace fs = std::filesystem;
using Shape = std::vector<std::int64_t>;

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

Quat quaternion(std::span<const float> xyzw) {
  return Quat(xyzw[3], xyzw[0], xyzw[1], xyzw[2]).normalized();
}

std::vector<BodyCalibration> read_bodies(const SafetensorsFile& file, Hand hand,
                                         std::size_t sequences) {
  const auto s = static_cast<std::int64_t>(sequences);
  const std::vector<float> root_position = file.read_f32("root_position", Shape{s, 3});
  const std::vector<float> root_rotation = file.read_f32("root_rotation", Shape{s, 4});
  const std::vector<float> rest = file.read_f32("rest_wrist_in_root", Shape{s, 2, 3});
  const std::vector<float> body = file.read_f32("body", Shape{s, 2});
  std::vector<BodyCalibration> bodies(sequences);
  for (std::size_t i = 0; i < sequences; ++i) {
    BodyCalibration& b = bodies[i];
    b.height = body[i * 2];
    b.arm_length = body[i * 2 + 1];
    b.deictic_hand = hand;
    b.T_world_root.rotation =
        quaternion(std::span(root_rotation).subspan(i * 4, 4)).toRotationMatrix();
    b.T_world_root.translation =
        Vec3(root_position[i * 3], root_position[i * 3 + 1], root_position[i * 3 + 2]);
    for (int h = 0; h < 2; ++h) {
      const std::size_t at = (i * 2 + static_cast<std::size_t>(h)) * 3;
      b.rest_wrist_in_root[static_cast<std::size_t>(h)] =
          Vec3(rest[at], rest[at + 1], rest[at + 2]);
    }
  }
  return bodies;
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
  t.data_ = capture::Dataset::read(path);
  t.bodies_ = read_bodies(file, t.hand_, t.data_.sequences());
  return t;
}

std::vector<std::size_t> TestSet::of_category(capture::Category c) const {
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
  const std::size_t row = data_.begin(s) + k;
  TrackingFrame f;
  f.time = static_cast<double>(data_.time[row]);
  f.T_world_head.translation = vec3_at(data_.head_position, row);
  f.T_world_head.rotation =
      quaternion(std::span(data_.head_rotation).subspan(row * 4, 4)).toRotationMatrix();
  f.gaze = vec3_at(data_.gaze, row);
  for (std::size_t h = 0; h < 2; ++h) {
    f.T_world_wrist[h].translation = vec3_at(data_.wrist_position, row * 2 + h);
    f.T_world_wrist[h].rotation =
        quaternion(std::span(data_.wrist_rotation).subspan((row * 2 + h) * 4, 4))
            .toRotationMatrix();
    f.index_tip[h] = vec3_at(data_.index_tip, row * 2 + h);
  }
  f.valid = data_.valid[row];
  f.head_target = data_.head_target_id[row];
  f.hand_target = data_.hand_target_id[row];
  f.head_target_position = vec3_at(data_.head_target_position, row);
  f.hand_target_position = vec3_at(data_.hand_target_position, row);
  return f;
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
