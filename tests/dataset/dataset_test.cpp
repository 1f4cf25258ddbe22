// The dataset files (dataset/, docs/dataset.md): what the writer stores is what the reader gives
// back; every corruption is rejected with the file and the tensor named; the ten categories and
// their names.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <limits>

#include "core/error.h"
#include "dataset/dataset.h"
#include "test_support.h"

namespace deixis::dataset {
namespace {

namespace fs = std::filesystem;

// A small recording: `frames` frames of a person whose wrists and head move a little, with one
// target; network columns that are a function of the frame; labels that ramp up.
struct Recording {
  Category category = Category::kPointingSingle;
  BodyCalibration body;
  std::vector<TargetObject> targets;
  std::vector<TrackingFrame> frames;
  std::vector<Labels> labels;
  std::vector<std::uint8_t> phase_keys;
  std::vector<float> features, end_effectors;

  SequenceRows rows(std::int32_t source) const {
    SequenceRows r;
    r.category = category;
    r.source = source;
    r.seed = 0xfedcba9876543210ull;
    r.speed = 0.5f;
    r.mirrored = true;
    r.body = body;
    r.targets = targets;
    r.frames = frames;
    r.labels = labels;
    r.phase_keys = phase_keys;
    r.mpnet_features = features;
    r.end_effectors = end_effectors;
    return r;
  }
};

Recording recording(Category category, int frames, float shift) {
  Recording r;
  r.category = category;
  r.body.height = 1.61f + shift;
  r.body.arm_length = 0.7f;
  r.body.deictic_hand = Hand::kLeft;
  r.body.T_world_root.rotation = yaw_rotation(0.3f + shift);
  r.body.T_world_root.translation = Vec3(1.0f, 1.5f + shift, -2.0f);
  r.targets.push_back(
      {3, "lamp", TargetKind::kBox, Vec3(0.5f, 1.0f, -1.0f + shift), Vec3(0.2f, 0.3f, 0.4f)});
  for (int i = 0; i < frames; ++i) {
    const float t = static_cast<float>(i) / 30.0f;
    TrackingFrame f;
    f.time = static_cast<double>(t);
    f.T_world_head.rotation = yaw_rotation(0.1f * t);
    f.T_world_head.translation = Vec3(0.0f, 1.5f, shift + t);
    f.gaze = Vec3(0.0f, std::sin(t), -std::cos(t));
    for (int h = 0; h < 2; ++h) {
      f.T_world_wrist[h].rotation = yaw_rotation(static_cast<float>(h) - t);
      f.T_world_wrist[h].translation = Vec3(0.2f * static_cast<float>(h), 1.0f, -t);
      f.index_tip[h] = Vec3(0.1f, 0.9f + t, -0.3f);
    }
    f.valid = static_cast<std::uint8_t>(i % 16);
    f.head_target = i % 2 == 0 ? kPartnerTarget : 3;
    f.hand_target = 3;
    f.head_target_position = Vec3(0.0f, 1.6f, -2.0f);
    f.hand_target_position = r.targets[0].position;
    r.frames.push_back(f);
    const float ramp = static_cast<float>(i) / static_cast<float>(frames - 1);
    r.labels.push_back({ramp, 1.0f - ramp, 0.5f});
    r.phase_keys.push_back(i == 0 ? 1 : 0);
    for (int k = 0; k < kFeatureColumns; ++k) {
      r.features.push_back(shift + static_cast<float>(i * kFeatureColumns + k) * 0.01f);
    }
    for (int k = 0; k < kEndEffectorColumns; ++k) {
      r.end_effectors.push_back(-shift - static_cast<float>(i * kEndEffectorColumns + k) * 0.01f);
    }
  }
  return r;
}

std::vector<Recording> recordings() {
  return {recording(Category::kPointingSingle, 20, 0.0f),
          recording(Category::kTouchingTransition, 31, 0.25f),
          recording(Category::kPointingSingle, 10, 0.5f)};
}

// The recordings as a file; the third derives from the first (a speed-augmented copy).
DatasetWriter writer_of(const std::vector<Recording>& recordings) {
  DatasetWriter w;
  w.set_metadata("subject", "161");
  w.set_metadata("deictic_hand", "left");
  for (std::size_t k = 0; k < recordings.size(); ++k) {
    w.add(recordings[k].rows(k == 2 ? 0 : w.next_index()));
  }
  return w;
}

SafetensorsFile file_of(const std::vector<Recording>& recordings) {
  return SafetensorsFile::from_bytes("subject161.safetensors", writer_of(recordings).serialize());
}

void expect_near(const Vec3& a, const Vec3& b) {
  EXPECT_LT((a - b).norm(), 1e-6f) << a.transpose() << " vs " << b.transpose();
}
void expect_near(const Mat3& a, const Mat3& b) {
  EXPECT_LT((a - b).norm(), 1e-5f);
}

TEST(Dataset, WhatIsWrittenIsReadBack) {
  const std::vector<Recording> r = recordings();
  const Dataset d = Dataset::read(file_of(r));
  EXPECT_EQ(d.source, "subject161.safetensors");
  EXPECT_EQ(d.metadata.at("schema"), kSchema);
  EXPECT_EQ(d.metadata.at("subject"), "161");
  EXPECT_EQ(d.hand, Hand::kLeft);
  ASSERT_EQ(d.sequences(), 3u);
  ASSERT_EQ(d.frames, 61u);
  EXPECT_EQ(d.begin(1), 20u);
  EXPECT_EQ(d.end(1), 51u);
  EXPECT_EQ(d.sequence_source, (std::vector<std::int32_t>{0, 1, 0}));
  EXPECT_EQ(d.sequence_category[1], static_cast<std::int32_t>(Category::kTouchingTransition));
  EXPECT_EQ(static_cast<std::uint64_t>(d.sequence_seed[2]), 0xfedcba9876543210ull);
  EXPECT_EQ(d.sequence_speed[0], 0.5f);
  EXPECT_EQ(d.sequence_mirrored[0], 1);
  EXPECT_EQ(d.target_offsets, (std::vector<std::int64_t>{0, 1, 2, 3}));
  EXPECT_EQ(d.target_kind[1], static_cast<std::uint8_t>(TargetKind::kBox));
  EXPECT_EQ(d.target_size[2 * 3 + 2], 0.4f);
  for (std::size_t s = 0; s < d.sequences(); ++s) {
    const Recording& rec = r[s];
    const BodyCalibration b = d.calibration(s);
    EXPECT_EQ(b.height, rec.body.height);
    EXPECT_EQ(b.deictic_hand, Hand::kLeft);
    expect_near(b.T_world_root.translation, rec.body.T_world_root.translation);
    expect_near(b.T_world_root.rotation, rec.body.T_world_root.rotation);
    expect_near(b.rest_wrist_in_root[1], rec.body.rest_wrist_in_root[1]);
    for (std::size_t k = 0; k < rec.frames.size(); ++k) {
      const std::size_t row = d.begin(s) + k;
      const TrackingFrame f = d.tracking(row);
      const TrackingFrame& g = rec.frames[k];
      EXPECT_FLOAT_EQ(static_cast<float>(f.time), static_cast<float>(g.time));
      expect_near(f.T_world_head.translation, g.T_world_head.translation);
      expect_near(f.T_world_head.rotation, g.T_world_head.rotation);
      expect_near(f.gaze, g.gaze);
      expect_near(f.T_world_wrist[1].rotation, g.T_world_wrist[1].rotation);
      expect_near(f.index_tip[0], g.index_tip[0]);
      EXPECT_EQ(f.valid, g.valid);
      EXPECT_EQ(f.head_target, g.head_target);
      expect_near(f.hand_target_position, g.hand_target_position);
      EXPECT_EQ(d.labels[row * 3 + 1], rec.labels[k][1]);
      EXPECT_EQ(d.phase_key[row], rec.phase_keys[k]);
      EXPECT_EQ(d.sequence[row], static_cast<std::int32_t>(s));
      for (int c = 0; c < kFeatureColumns; ++c) {
        ASSERT_EQ(d.mpnet_features[row * kFeatureColumns + c],
                  rec.features[k * kFeatureColumns + c]);
      }
      for (int c = 0; c < kTargetFeatureColumns; ++c) {
        ASSERT_EQ(d.target_feature[row * kTargetFeatureColumns + c],
                  rec.features[k * kFeatureColumns + kTargetFeatureColumn + c]);
      }
      ASSERT_EQ(d.end_effectors[row * kEndEffectorColumns + 23],
                rec.end_effectors[k * kEndEffectorColumns + 23]);
    }
  }
}

TEST(Dataset, TheSameSequencesGiveTheSameBytes) {
  EXPECT_EQ(writer_of(recordings()).serialize(), writer_of(recordings()).serialize());
}

TEST(Dataset, TheWriterRefusesRowsThatDisagreeWithTheFrames) {
  Recording r = recording(Category::kPointingSingle, 5, 0.0f);
  r.end_effectors.pop_back();
  DatasetWriter w;
  EXPECT_THROW(w.add(r.rows(0)), Error);
  EXPECT_EQ(w.next_index(), 0);
}

// The valid file with one tensor replaced (`add` writes the replacement; an empty `add` drops
// it) and its metadata kept, except `schema` when given.
SafetensorsFile with_tensor_replaced(const std::string& name,
                                     const std::function<void(SafetensorsWriter&)>& add,
                                     const char* schema = kSchema) {
  const SafetensorsFile valid = file_of(recordings());
  SafetensorsWriter writer;
  for (const auto& [key, value] : valid.metadata()) {
    writer.set_metadata(key, key == "schema" ? schema : value);
  }
  for (const TensorInfo& t : valid.tensors()) {
    if (t.name == name) {
      add(writer);
    } else {
      writer.add(t.name, t.dtype, t.shape, valid.bytes(t));
    }
  }
  return SafetensorsFile::from_bytes("subject161.safetensors", writer.serialize());
}

template <class T>
std::function<void(SafetensorsWriter&)> ints(const char* name, DType dtype, std::vector<T> v) {
  return [=](SafetensorsWriter& w) {
    w.add(name, dtype, {static_cast<std::int64_t>(v.size())}, std::as_bytes(std::span(v)));
  };
}

TEST(Dataset, RejectsEveryCorruptionNamingFileAndTensor) {
  const std::int64_t frames = 61;
  const auto nothing = [](SafetensorsWriter&) {};
  const auto floats = [](const char* name, std::vector<std::int64_t> shape, float value,
                         std::size_t at, float bad) {
    return [=](SafetensorsWriter& w) {
      std::size_t count = 1;
      for (const std::int64_t d : shape) {
        count *= static_cast<std::size_t>(d);
      }
      std::vector<float> v(count, value);
      if (at < count) {
        v[at] = bad;
      }
      w.add_f32(name, shape, v);
    };
  };
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<std::pair<const char*, SafetensorsFile>> cases = {
      {"end_effectors", with_tensor_replaced("end_effectors", nothing)},  // missing
      {"mpnet_features",
       with_tensor_replaced("mpnet_features", floats("mpnet_features", {frames, 12}, 0, 0, 0))},
      {"labels", with_tensor_replaced("labels", floats("labels", {frames - 1, 3}, 0, 0, 0))},
      {"labels", with_tensor_replaced("labels", floats("labels", {frames, 3}, 0.5f, 7, 1.5f))},
      {"end_effectors",
       with_tensor_replaced("end_effectors", floats("end_effectors", {frames, 24}, 0, 100, nan))},
      {"head_rotation",
       with_tensor_replaced("head_rotation", floats("head_rotation", {frames, 4}, 0, 9, nan))},
      {"sequence_offsets",
       with_tensor_replaced("sequence_offsets",
                            ints<std::int64_t>("sequence_offsets", DType::kI64, {0, 20, 51, 60}))},
      {"sequence_offsets",
       with_tensor_replaced("sequence_offsets",
                            ints<std::int64_t>("sequence_offsets", DType::kI64, {0, 20, 20, 61}))},
      {"sequence_offsets",
       with_tensor_replaced("sequence_offsets", floats("sequence_offsets", {4}, 0, 9, 0))},
      {"sequence_category",
       with_tensor_replaced("sequence_category",
                            ints<std::int32_t>("sequence_category", DType::kI32, {0, 10, 0}))},
      {"sequence_category",
       with_tensor_replaced("sequence_category",
                            ints<std::int32_t>("sequence_category", DType::kI32, {0, 9}))},
      {"sequence_source",
       with_tensor_replaced("sequence_source",
                            ints<std::int32_t>("sequence_source", DType::kI32, {0, 2, 0}))},
      {"deictic_hand",
       with_tensor_replaced("deictic_hand",
                            ints<std::uint8_t>("deictic_hand", DType::kU8, {1, 2, 1}))},
      {"category",
       with_tensor_replaced("category", ints<std::int32_t>("category", DType::kI32,
                                                           std::vector<std::int32_t>(61, 0)))},
      {"target_offsets",
       with_tensor_replaced("target_offsets",
                            ints<std::int64_t>("target_offsets", DType::kI64, {0, 2, 1, 3}))},
      {"target_kind", with_tensor_replaced(
                          "target_kind", ints<std::uint8_t>("target_kind", DType::kU8, {0, 3, 1}))},
      {"target_id", with_tensor_replaced("target_id", nothing)},
      {"schema", with_tensor_replaced("", nothing, "deixis-capture/0")},
  };
  for (const auto& [field, file] : cases) {
    try {
      Dataset::read(file);
      ADD_FAILURE() << "accepted a dataset with a bad '" << field << "'";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("subject161.safetensors"), std::string::npos) << message;
      EXPECT_NE(message.find(field), std::string::npos) << message;
    }
  }
}

TEST(Dataset, RejectsAnUnknownHand) {
  SafetensorsWriter writer;
  const SafetensorsFile valid = file_of(recordings());
  for (const auto& [key, value] : valid.metadata()) {
    writer.set_metadata(key, key == "deictic_hand" ? "both" : value);
  }
  for (const TensorInfo& t : valid.tensors()) {
    writer.add(t.name, t.dtype, t.shape, valid.bytes(t));
  }
  try {
    Dataset::read(SafetensorsFile::from_bytes("x.safetensors", writer.serialize()));
    ADD_FAILURE() << "accepted deictic_hand=both";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'deictic_hand' is 'both'"), std::string::npos)
        << e.what();
  }
}

TEST(Dataset, RejectsATruncatedFileNamingIt) {
  deixis::testing::ScratchDir dir;
  std::vector<std::byte> bytes = writer_of(recordings()).serialize();
  bytes.resize(bytes.size() - 100);
  const fs::path path = dir.path() / "truncated.safetensors";
  {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size()));
  }
  try {
    Dataset::read(path);
    ADD_FAILURE() << "accepted a truncated file";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("truncated.safetensors"), std::string::npos) << e.what();
  }
}

TEST(Categories, NamesTitlesAndKinds) {
  EXPECT_EQ(category_name(Category::kPointingTwoTargets), "pointing-two-targets");
  EXPECT_EQ(category_title(Category::kTouchingTransition), "Transition (Touching)");
  for (const Category c : kAllCategories) {
    EXPECT_EQ(parse_category(category_name(c)), c);
  }
  EXPECT_THROW(parse_category("Pointing at single target"), Error);
  int touching = 0, free_form = 0, deictic = 0;
  for (const Category c : kAllCategories) {
    touching += is_touching(c) ? 1 : 0;
    free_form += has_free_form(c) ? 1 : 0;
    deictic += is_deictic_gesture(c) ? 1 : 0;
    EXPECT_EQ(is_speed_augmented(c), is_deictic_gesture(c)) << category_name(c);
  }
  EXPECT_EQ(touching, 5);
  EXPECT_EQ(free_form, 4);
  EXPECT_EQ(deictic, 4);
  EXPECT_FALSE(is_deictic_gesture(Category::kPointingExplanation));
  EXPECT_TRUE(has_free_form(Category::kTouchingExplanation));
}

}  // namespace
}  // namespace deixis::dataset
