#include "dataset/dataset.h"

#include <cstring>

#include "core/error.h"

namespace deixis::dataset {

namespace {

using Shape = std::vector<std::int64_t>;

template <class T>
std::span<const std::byte> as_bytes(const std::vector<T>& v) {
  return std::as_bytes(std::span<const T>(v));
}

void push(std::vector<float>& out, const Vec3& v) {
  out.insert(out.end(), {v.x(), v.y(), v.z()});
}
void push_quat(std::vector<float>& out, const Mat3& R) {
  const Quat q(R);
  out.insert(out.end(), {q.x(), q.y(), q.z(), q.w()});
}

Vec3 vec3_at(const std::vector<float>& v, std::size_t row) {
  return {v[row * 3], v[row * 3 + 1], v[row * 3 + 2]};
}
// Quaternions are stored (x, y, z, w).
Mat3 rotation_at(const std::vector<float>& v, std::size_t row) {
  return Quat(v[row * 4 + 3], v[row * 4], v[row * 4 + 1], v[row * 4 + 2])
      .normalized()
      .toRotationMatrix();
}

template <class T>
std::vector<T> read_ints(const SafetensorsFile& file, std::string_view name, DType dtype,
                         const Shape& shape) {
  const TensorInfo& info = file.require(name, dtype, shape);
  const std::span<const std::byte> bytes = file.bytes(info);
  std::vector<T> out(info.numel());
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

std::int64_t dim(std::size_t n) {
  return static_cast<std::int64_t>(n);
}

}  // namespace

void DatasetWriter::set_metadata(std::string key, std::string value) {
  metadata_[std::move(key)] = std::move(value);
}

void DatasetWriter::add(const SequenceRows& s) {
  const std::size_t n = s.frames.size();
  if (s.labels.size() != n || s.phase_keys.size() != n ||
      s.mpnet_features.size() != n * kFeatureColumns ||
      s.end_effectors.size() != n * kEndEffectorColumns) {
    throw Error("dataset writer: sequence " + std::to_string(next_index()) + " has " +
                std::to_string(n) + " frames but " + std::to_string(s.labels.size()) +
                " label rows, " + std::to_string(s.phase_keys.size()) + " phase keys, " +
                std::to_string(s.mpnet_features.size()) + " feature values and " +
                std::to_string(s.end_effectors.size()) + " end-effector values");
  }
  const auto index = next_index();
  for (std::size_t i = 0; i < n; ++i) {
    const TrackingFrame& f = s.frames[i];
    time_.push_back(static_cast<float>(f.time));
    push(head_position_, f.T_world_head.translation);
    push_quat(head_rotation_, f.T_world_head.rotation);
    push(gaze_, f.gaze);
    for (int h = 0; h < 2; ++h) {
      push(wrist_position_, f.T_world_wrist[h].translation);
      push_quat(wrist_rotation_, f.T_world_wrist[h].rotation);
      push(index_tip_, f.index_tip[h]);
    }
    valid_.push_back(f.valid);
    head_target_.push_back(f.head_target);
    hand_target_.push_back(f.hand_target);
    push(head_target_position_, f.head_target_position);
    push(hand_target_position_, f.hand_target_position);
    labels_.insert(labels_.end(), s.labels[i].begin(), s.labels[i].end());
    const std::span<const float> row =
        s.mpnet_features.subspan(i * kFeatureColumns, kFeatureColumns);
    features_.insert(features_.end(), row.begin(), row.end());
    const std::span<const float> x =
        s.end_effectors.subspan(i * kEndEffectorColumns, kEndEffectorColumns);
    end_effectors_.insert(end_effectors_.end(), x.begin(), x.end());
    target_feature_.insert(target_feature_.end(), row.begin() + kTargetFeatureColumn, row.end());
    phase_key_.push_back(s.phase_keys[i]);
    frame_category_.push_back(static_cast<std::int32_t>(s.category));
    frame_sequence_.push_back(index);
  }
  const BodyCalibration& body = s.body;
  offsets_.push_back(static_cast<std::int64_t>(time_.size()));
  categories_.push_back(static_cast<std::int32_t>(s.category));
  sources_.push_back(s.source);
  seeds_.push_back(static_cast<std::int64_t>(s.seed));
  speeds_.push_back(s.speed);
  mirrored_.push_back(s.mirrored ? 1 : 0);
  deictic_hand_.push_back(static_cast<std::uint8_t>(body.deictic_hand));
  push(root_position_, body.T_world_root.translation);
  push_quat(root_rotation_, body.T_world_root.rotation);
  for (int h = 0; h < 2; ++h) {
    push(rest_wrist_, body.rest_wrist_in_root[h]);
  }
  body_.insert(body_.end(), {body.height, body.arm_length});
  for (const TargetObject& t : s.targets) {
    target_id_.push_back(t.id);
    target_kind_.push_back(static_cast<std::uint8_t>(t.kind));
    push(target_position_, t.position);
    push(target_size_, t.size);
  }
  target_offsets_.push_back(static_cast<std::int64_t>(target_id_.size()));
}

SafetensorsWriter DatasetWriter::safetensors() const {
  const std::int64_t n = dim(time_.size());
  const std::int64_t s = dim(categories_.size());
  const std::int64_t t = dim(target_id_.size());
  SafetensorsWriter w;
  w.set_metadata("schema", kSchema);
  for (const auto& [key, value] : metadata_) {
    w.set_metadata(key, value);
  }
  w.add_f32("time", {n}, time_);
  w.add_f32("head_position", {n, 3}, head_position_);
  w.add_f32("head_rotation", {n, 4}, head_rotation_);
  w.add_f32("gaze", {n, 3}, gaze_);
  w.add_f32("wrist_position", {n, 2, 3}, wrist_position_);
  w.add_f32("wrist_rotation", {n, 2, 4}, wrist_rotation_);
  w.add_f32("index_tip", {n, 2, 3}, index_tip_);
  w.add("valid", DType::kU8, {n}, as_bytes(valid_));
  w.add("head_target_id", DType::kI32, {n}, as_bytes(head_target_));
  w.add("hand_target_id", DType::kI32, {n}, as_bytes(hand_target_));
  w.add_f32("head_target_position", {n, 3}, head_target_position_);
  w.add_f32("hand_target_position", {n, 3}, hand_target_position_);
  w.add_f32("labels", {n, kLabelColumns}, labels_);
  w.add_f32("mpnet_features", {n, kFeatureColumns}, features_);
  w.add_f32("end_effectors", {n, kEndEffectorColumns}, end_effectors_);
  w.add_f32("target_feature", {n, kTargetFeatureColumns}, target_feature_);
  w.add("phase_key", DType::kU8, {n}, as_bytes(phase_key_));
  w.add("category", DType::kI32, {n}, as_bytes(frame_category_));
  w.add("sequence", DType::kI32, {n}, as_bytes(frame_sequence_));
  w.add_i64("sequence_offsets", {s + 1}, offsets_);
  w.add("sequence_category", DType::kI32, {s}, as_bytes(categories_));
  w.add("sequence_source", DType::kI32, {s}, as_bytes(sources_));
  w.add_i64("sequence_seed", {s}, seeds_);
  w.add_f32("sequence_speed", {s}, speeds_);
  w.add("sequence_mirrored", DType::kU8, {s}, as_bytes(mirrored_));
  w.add("deictic_hand", DType::kU8, {s}, as_bytes(deictic_hand_));
  w.add_f32("root_position", {s, 3}, root_position_);
  w.add_f32("root_rotation", {s, 4}, root_rotation_);
  w.add_f32("rest_wrist_in_root", {s, 2, 3}, rest_wrist_);
  w.add_f32("body", {s, 2}, body_);
  w.add_i64("target_offsets", {s + 1}, target_offsets_);
  w.add("target_id", DType::kI32, {t}, as_bytes(target_id_));
  w.add("target_kind", DType::kU8, {t}, as_bytes(target_kind_));
  w.add_f32("target_position", {t, 3}, target_position_);
  w.add_f32("target_size", {t, 3}, target_size_);
  return w;
}

std::vector<std::byte> DatasetWriter::serialize() const {
  return safetensors().serialize();
}

void DatasetWriter::write(const std::filesystem::path& path) const {
  safetensors().write(path);
}

Dataset Dataset::read(const std::filesystem::path& path) {
  return read(SafetensorsFile::read(path));
}

Dataset Dataset::read(const SafetensorsFile& file) {
  Dataset d;
  d.source = file.source();
  d.metadata = file.metadata();
  const auto fail = [&](const std::string& what) { throw Error(d.source + ": " + what); };
  const auto schema = d.metadata.find("schema");
  if (schema == d.metadata.end() || schema->second != kSchema) {
    fail(std::string("not a capture dataset (metadata 'schema' is not '") + kSchema + "')");
  }
  const auto hand = d.metadata.find("deictic_hand");
  if (hand != d.metadata.end() && hand->second != "right" && hand->second != "left") {
    fail("metadata 'deictic_hand' is '" + hand->second + "', expected right or left");
  }
  d.hand = hand != d.metadata.end() && hand->second == "left" ? Hand::kLeft : Hand::kRight;

  // The frame count from `time`, the sequence count from `sequence_offsets`; every other tensor
  // must agree with them.
  const std::vector<std::int64_t>& time_shape = file.shape_of("time");
  if (time_shape.size() != 1) {
    fail("tensor 'time': expected one dimension, found " + shape_string(time_shape));
  }
  const std::int64_t n = time_shape[0];
  const std::vector<std::int64_t>& offsets_shape = file.shape_of("sequence_offsets");
  if (offsets_shape.size() != 1 || offsets_shape[0] < 1) {
    fail("tensor 'sequence_offsets': expected [sequences + 1], found " +
         shape_string(offsets_shape));
  }
  const std::int64_t s = offsets_shape[0] - 1;
  const std::vector<std::int64_t>& targets_shape = file.shape_of("target_id");
  if (targets_shape.size() != 1) {
    fail("tensor 'target_id': expected one dimension, found " + shape_string(targets_shape));
  }
  const std::int64_t t = targets_shape[0];

  d.frames = static_cast<std::size_t>(n);
  d.time = file.read_f32("time", Shape{n});
  d.head_position = file.read_f32("head_position", Shape{n, 3});
  d.head_rotation = file.read_f32("head_rotation", Shape{n, 4});
  d.gaze = file.read_f32("gaze", Shape{n, 3});
  d.wrist_position = file.read_f32("wrist_position", Shape{n, 2, 3});
  d.wrist_rotation = file.read_f32("wrist_rotation", Shape{n, 2, 4});
  d.index_tip = file.read_f32("index_tip", Shape{n, 2, 3});
  d.head_target_position = file.read_f32("head_target_position", Shape{n, 3});
  d.hand_target_position = file.read_f32("hand_target_position", Shape{n, 3});
  d.labels = file.read_f32("labels", Shape{n, kLabelColumns});
  d.mpnet_features = file.read_f32("mpnet_features", Shape{n, kFeatureColumns});
  d.end_effectors = file.read_f32("end_effectors", Shape{n, kEndEffectorColumns});
  d.target_feature = file.read_f32("target_feature", Shape{n, kTargetFeatureColumns});
  d.valid = read_ints<std::uint8_t>(file, "valid", DType::kU8, Shape{n});
  d.phase_key = read_ints<std::uint8_t>(file, "phase_key", DType::kU8, Shape{n});
  d.head_target_id = read_ints<std::int32_t>(file, "head_target_id", DType::kI32, Shape{n});
  d.hand_target_id = read_ints<std::int32_t>(file, "hand_target_id", DType::kI32, Shape{n});
  d.category = read_ints<std::int32_t>(file, "category", DType::kI32, Shape{n});
  d.sequence = read_ints<std::int32_t>(file, "sequence", DType::kI32, Shape{n});
  d.sequence_offsets = read_ints<std::int64_t>(file, "sequence_offsets", DType::kI64, Shape{s + 1});
  d.sequence_category = read_ints<std::int32_t>(file, "sequence_category", DType::kI32, Shape{s});
  d.sequence_source = read_ints<std::int32_t>(file, "sequence_source", DType::kI32, Shape{s});
  d.sequence_seed = read_ints<std::int64_t>(file, "sequence_seed", DType::kI64, Shape{s});
  d.sequence_speed = file.read_f32("sequence_speed", Shape{s});
  d.sequence_mirrored = read_ints<std::uint8_t>(file, "sequence_mirrored", DType::kU8, Shape{s});
  d.deictic_hand = read_ints<std::uint8_t>(file, "deictic_hand", DType::kU8, Shape{s});
  d.root_position = file.read_f32("root_position", Shape{s, 3});
  d.root_rotation = file.read_f32("root_rotation", Shape{s, 4});
  d.rest_wrist_in_root = file.read_f32("rest_wrist_in_root", Shape{s, 2, 3});
  d.body = file.read_f32("body", Shape{s, 2});
  d.target_offsets = read_ints<std::int64_t>(file, "target_offsets", DType::kI64, Shape{s + 1});
  d.target_id = read_ints<std::int32_t>(file, "target_id", DType::kI32, Shape{t});
  d.target_kind = read_ints<std::uint8_t>(file, "target_kind", DType::kU8, Shape{t});
  d.target_position = file.read_f32("target_position", Shape{t, 3});
  d.target_size = file.read_f32("target_size", Shape{t, 3});

  // Offsets tile [0, n] and [0, t] in order; per-frame ids agree with them.
  if (d.sequence_offsets.front() != 0 || d.sequence_offsets.back() != n) {
    fail("tensor 'sequence_offsets': must run from 0 to the frame count " + std::to_string(n));
  }
  if (d.target_offsets.front() != 0 || d.target_offsets.back() != t) {
    fail("tensor 'target_offsets': must run from 0 to the target count " + std::to_string(t));
  }
  for (std::size_t k = 0; k < d.sequences(); ++k) {
    if (d.sequence_offsets[k + 1] <= d.sequence_offsets[k]) {
      fail("tensor 'sequence_offsets': sequence " + std::to_string(k) + " is empty or reversed");
    }
    if (d.target_offsets[k + 1] < d.target_offsets[k]) {
      fail("tensor 'target_offsets': sequence " + std::to_string(k) + " is reversed");
    }
    if (d.sequence_category[k] < 0 || d.sequence_category[k] >= kCategoryCount) {
      fail("tensor 'sequence_category': sequence " + std::to_string(k) + " has category " +
           std::to_string(d.sequence_category[k]) + ", not in [0, 9]");
    }
    if (d.sequence_source[k] < 0 || static_cast<std::size_t>(d.sequence_source[k]) > k) {
      fail("tensor 'sequence_source': sequence " + std::to_string(k) + " names source " +
           std::to_string(d.sequence_source[k]));
    }
    if (d.deictic_hand[k] > 1) {
      fail("tensor 'deictic_hand': sequence " + std::to_string(k) + " is neither 0 nor 1");
    }
    for (std::size_t i = d.begin(k); i < d.end(k); ++i) {
      if (d.sequence[i] != static_cast<std::int32_t>(k) ||
          d.category[i] != d.sequence_category[k]) {
        fail("tensors 'sequence'/'category': frame " + std::to_string(i) +
             " disagrees with sequence_offsets/sequence_category");
      }
    }
  }
  for (std::size_t i = 0; i < d.target_kind.size(); ++i) {
    if (d.target_kind[i] > static_cast<std::uint8_t>(TargetKind::kScreen)) {
      fail("tensor 'target_kind': target " + std::to_string(i) + " has kind " +
           std::to_string(d.target_kind[i]) + ", not 0, 1 or 2");
    }
  }
  for (std::size_t i = 0; i < d.labels.size(); ++i) {
    if (d.labels[i] < 0.0f || d.labels[i] > 1.0f) {
      fail("tensor 'labels': value " + std::to_string(d.labels[i]) + " at frame " +
           std::to_string(i / kLabelColumns) + " is outside [0, 1]");
    }
  }
  return d;
}

TrackingFrame Dataset::tracking(std::size_t row) const {
  TrackingFrame f;
  f.time = static_cast<double>(time[row]);
  f.T_world_head.translation = vec3_at(head_position, row);
  f.T_world_head.rotation = rotation_at(head_rotation, row);
  f.gaze = vec3_at(gaze, row);
  for (std::size_t h = 0; h < 2; ++h) {
    f.T_world_wrist[h].translation = vec3_at(wrist_position, row * 2 + h);
    f.T_world_wrist[h].rotation = rotation_at(wrist_rotation, row * 2 + h);
    f.index_tip[h] = vec3_at(index_tip, row * 2 + h);
  }
  f.valid = valid[row];
  f.head_target = head_target_id[row];
  f.hand_target = hand_target_id[row];
  f.head_target_position = vec3_at(head_target_position, row);
  f.hand_target_position = vec3_at(hand_target_position, row);
  return f;
}

BodyCalibration Dataset::calibration(std::size_t s) const {
  BodyCalibration b;
  b.height = body[s * 2];
  b.arm_length = body[s * 2 + 1];
  b.deictic_hand = deictic_hand[s] == 0 ? Hand::kLeft : Hand::kRight;
  b.T_world_root.rotation = rotation_at(root_rotation, s);
  b.T_world_root.translation = vec3_at(root_position, s);
  for (std::size_t h = 0; h < 2; ++h) {
    b.rest_wrist_in_root[h] = vec3_at(rest_wrist_in_root, s * 2 + h);
  }
  return b;
}

}  // namespace deixis::dataset
