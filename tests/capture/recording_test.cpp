// From motion to files: mirroring, tracker noise, the dataset schema read back, CSV, and
// reproducibility (the same seed gives identical bytes; different seeds differ).

#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <sstream>

#include "capture/mirror.h"
#include "capture/tracker_noise.h"
#include "core/error.h"
#include "dataset/csv.h"
#include "dataset/dataset.h"
#include "gesture/features.h"
#include "sequences.h"
#include "test_support.h"

namespace deixis::capture {
namespace {

namespace fs = std::filesystem;
using dataset::Dataset;
using testing::sample_sequences;

std::vector<char> bytes_of(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(Mirror, IsItsOwnInverseAndMakesALeftHandedTwin) {
  const Sequence& s = sample_sequences()[3];
  ASSERT_EQ(s.calibration.deictic_hand, Hand::kRight);
  const Sequence m = mirror(s);
  EXPECT_EQ(m.calibration.deictic_hand, Hand::kLeft);
  EXPECT_TRUE(m.mirrored);
  EXPECT_NE(m.dominant_eye, s.dominant_eye);
  const Sequence back = mirror(m);
  for (std::size_t i = 0; i < s.size(); i += 7) {
    EXPECT_LT((back.frames[i].index_tip[1] - s.frames[i].index_tip[1]).norm(), 1e-4f);
    EXPECT_TRUE(
        back.frames[i].T_world_head.rotation.isApprox(s.frames[i].T_world_head.rotation, 1e-5f));
    // The twin's left wrist is a proper rotation in the left-hand convention.
    EXPECT_NEAR(m.frames[i].T_world_wrist[0].rotation.determinant(), 1.0f, 1e-5f);
  }
  // The feature code sees each person in their own view, so the twin's network vectors are the
  // mirror image of the original's (both θ and every 3-vector's x negated): the left-hand
  // weights' training data (docs/decisions.md §17).
  for (std::size_t i = 0; i < s.size(); i += 11) {
    const MpnetFeatureRow a = mpnet_features(s.frames[i], s.calibration);
    const MpnetFeatureRow b = mpnet_features(m.frames[i], m.calibration);
    EndEffectors x = end_effectors(s.frames[i], s.calibration);
    mirror_end_effectors(x);
    const EndEffectors y = end_effectors(m.frames[i], m.calibration);
    for (int k = 0; k < kMpnetFeatureCount; ++k) {
      const bool theta = k == mf::kTarget + tf::kHeadTheta || k == mf::kTarget + tf::kHandTheta;
      ASSERT_NEAR(theta ? -a[k] : a[k], b[k], 1e-4f) << "frame " << i << " column " << k;
    }
    for (int k = 0; k < kEndEffectorSize; ++k) {
      ASSERT_NEAR(x[k], y[k], 1e-4f) << "frame " << i << " index " << k;
    }
  }
}

TEST(TrackerNoise, HeadsetNoiseDropsPartsAndHoldsTheirLastValues) {
  int dropped = 0;
  int blinks = 0;
  double head_error = 0;
  std::size_t frames = 0;
  const std::size_t step = sample_sequences().size() / 20;
  for (std::size_t k = 0; k < 20; ++k) {
    const Sequence& clean = sample_sequences()[k * step];
    Sequence noisy = clean;
    apply_tracker_noise(noisy, tracker_noise("headset"), 100 + k);
    for (std::size_t i = 0; i < 30; ++i) {
      ASSERT_EQ(noisy.frames[i].valid, tracked::kAll);  // the first second is whole
    }
    for (std::size_t i = 1; i < noisy.size(); ++i) {
      const TrackingFrame& f = noisy.frames[i];
      for (const Hand h : {Hand::kLeft, Hand::kRight}) {
        if (!(f.valid & tracked::hand(h))) {
          ++dropped;
          ASSERT_EQ(f.index_tip[index(h)], noisy.frames[i - 1].index_tip[index(h)]);
          ASSERT_TRUE(f.T_world_wrist[index(h)].translation ==
                      noisy.frames[i - 1].T_world_wrist[index(h)].translation);
        }
      }
      if (!(f.valid & tracked::kGaze)) {
        ++blinks;
        ASSERT_EQ(f.gaze, noisy.frames[i - 1].gaze);
      }
      if (f.valid & tracked::kHead) {
        head_error += static_cast<double>(
            (f.T_world_head.translation - clean.frames[i].T_world_head.translation).norm());
        ++frames;
      }
    }
  }
  EXPECT_GT(dropped, 0);
  EXPECT_GT(blinks, 0);
  const double mean = head_error / static_cast<double>(frames);
  EXPECT_GT(mean, 0.0008);  // 1 mm per axis: about 1.6 mm in 3-D
  EXPECT_LT(mean, 0.003);

  const Sequence& clean = sample_sequences()[0];
  Sequence a = clean;
  Sequence b = clean;
  apply_tracker_noise(a, tracker_noise("headset"), 99);
  apply_tracker_noise(b, tracker_noise("headset"), 99);
  EXPECT_EQ(a.frames[50].index_tip[1], b.frames[50].index_tip[1]);
  Sequence untouched = clean;
  apply_tracker_noise(untouched, tracker_noise("none"), 99);
  EXPECT_EQ(untouched.frames[50].index_tip[1], clean.frames[50].index_tip[1]);
}

GenerateOptions small(const fs::path& dir, std::uint64_t seed) {
  GenerateOptions o;
  o.out_dir = dir;
  o.seed = seed;
  o.sets = {"train", "test"};
  o.subjects = {"170", "173"};
  o.count_scale = 0.001;  // one sequence per category
  return o;
}

const GenerateProgress kQuiet = [](const std::string&, std::size_t, std::size_t, std::size_t) {};

TEST(Dataset, WritesTheSchemaAndReadsItBack) {
  deixis::testing::ScratchDir dir;
  const std::vector<GeneratedFile> files = generate_datasets(small(dir.path(), 1), kQuiet);
  ASSERT_EQ(files.size(), 3u);  // train_right, train_left, test_173
  const Dataset right = Dataset::read(dir.path() / "train_right.safetensors");
  const Dataset left = Dataset::read(dir.path() / "train_left.safetensors");
  const Dataset test = Dataset::read(dir.path() / "test_173.safetensors");
  // One recording per category; the four speed-augmented categories three times.
  EXPECT_EQ(right.sequences(), 10u + 4u * 2u);
  EXPECT_EQ(left.sequences(), right.sequences());
  EXPECT_EQ(test.sequences(), 10u);
  EXPECT_EQ(right.metadata.at("deictic_hand"), "right");
  EXPECT_EQ(left.metadata.at("deictic_hand"), "left");
  EXPECT_EQ(test.metadata.at("deictic_hand"), "left");
  EXPECT_EQ(right.frames, files[0].frames);
  // Augmented copies point at their source recording and differ in length by their speed.
  int augmented = 0;
  for (std::size_t s = 0; s < right.sequences(); ++s) {
    const auto source = static_cast<std::size_t>(right.sequence_source[s]);
    if (source != s) {
      ++augmented;
      EXPECT_TRUE(is_speed_augmented(static_cast<Category>(right.sequence_category[s])));
      const double ratio = static_cast<double>(right.end(source) - right.begin(source)) /
                           static_cast<double>(right.end(s) - right.begin(s));
      EXPECT_NEAR(ratio, right.sequence_speed[s], 0.02);
    }
  }
  EXPECT_EQ(augmented, 8);
  // The stored network rows are the feature code's, and the target feature is their tail.
  for (std::size_t i = 0; i < right.frames; i += 97) {
    for (int k = 0; k < kTargetFeatureSize; ++k) {
      ASSERT_EQ(right.target_feature[i * 5 + k], right.mpnet_features[i * 11 + 6 + k]);
    }
  }
  // CSV: a header and one line per frame of the sequence.
  std::ostringstream csv;
  write_csv(test, std::size_t{2}, csv);
  const std::string text = csv.str();
  EXPECT_EQ(static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n')),
            1 + test.end(2) - test.begin(2));
  EXPECT_NE(text.find("label_deictic"), std::string::npos);
  EXPECT_NE(text.find("f_theta_R"), std::string::npos);
  EXPECT_THROW(write_csv(test, std::size_t{10}, csv), Error);
}

TEST(Dataset, SameSeedSameBytesOtherSeedOtherBytes) {
  deixis::testing::ScratchDir a;
  deixis::testing::ScratchDir b;
  deixis::testing::ScratchDir c;
  generate_datasets(small(a.path(), 5), kQuiet);
  generate_datasets(small(b.path(), 5), kQuiet);
  generate_datasets(small(c.path(), 6), kQuiet);
  for (const char* name :
       {"train_right.safetensors", "train_left.safetensors", "test_173.safetensors"}) {
    const std::vector<char> first = bytes_of(a.path() / name);
    ASSERT_FALSE(first.empty());
    EXPECT_EQ(first, bytes_of(b.path() / name)) << name;
    EXPECT_NE(first, bytes_of(c.path() / name)) << name;
  }
}

}  // namespace
}  // namespace deixis::capture
