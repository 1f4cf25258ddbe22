// The torch-free half of training: dataset validation (every corruption is rejected with the
// file and the field named), clip geometry, the free-form hold, mirroring, schedules, and the
// checkpoint file. Runs under ASan + UBSan too.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "dataset/dataset.h"
#include "synthetic_sequences.h"
#include "test_support.h"
#include "train/checkpoint.h"
#include "train/clips.h"
#include "train/network_kind.h"
#include "train/progress.h"
#include "train/schedule.h"

namespace deixis::train {
namespace {

// ---- from a dataset file (dataset/ reads and validates it: tests/dataset) ----

TEST(TrainingSequences, AreTheNetworkColumnsOfEachSequenceOfAFile) {
  const std::vector<Sequence> sequences = test_data::synthetic_sequences(5, 50, 1);
  const dataset::Dataset d = dataset::Dataset::read(SafetensorsFile::from_bytes(
      "d.safetensors", test_data::dataset_writer(sequences).serialize()));
  EXPECT_EQ(d.hand, Hand::kRight);
  const std::vector<Sequence> read = training_sequences(d);
  ASSERT_EQ(read.size(), 5u);
  for (std::size_t s = 0; s < read.size(); ++s) {
    EXPECT_EQ(read[s].category, sequences[s].category);
    EXPECT_EQ(read[s].frames, sequences[s].frames);
    EXPECT_EQ(read[s].features, sequences[s].features);
    EXPECT_EQ(read[s].progression, sequences[s].progression);
    EXPECT_EQ(read[s].pose, sequences[s].pose);
  }
}

// ---- clips ----

TEST(Clips, StartEverySevenRowsPlusTheLastClip) {
  EXPECT_EQ(clip_starts(60, 45, 7), (std::vector<int>{15, 0, 7, 14}));
  EXPECT_EQ(clip_starts(45, 45, 7), (std::vector<int>{0, 0}));
  EXPECT_TRUE(clip_starts(44, 45, 7).empty());
}

TEST(Clips, MpnetRowsAreFeaturesThenLabels) {
  const std::vector<Sequence> s = test_data::synthetic_sequences(1, 60, 4);
  const ExampleSet clips = mpnet_clips(s);
  ASSERT_EQ(clips.count, 4u);
  ASSERT_EQ(clips.columns, 14);
  // Clip 1 starts at row 0; its row 3 is frame 3.
  const std::span<const float> c = clips.example(1);
  EXPECT_EQ(c[3 * 14 + 2], s[0].features[3 * 11 + 2]);
  EXPECT_EQ(c[3 * 14 + 12], s[0].progression[3 * 3 + 1]);
  // Clip 0 is the last 45 rows: its row 0 is frame 15.
  EXPECT_EQ(clips.example(0)[0], s[0].features[15 * 11]);
}

TEST(Clips, UgnetRowsPairEachPoseWithTheNextFrame) {
  std::vector<Sequence> s = test_data::synthetic_sequences(1, 60, 5);
  s[0].category = Category::kPointingSingle;  // no hold
  const ExampleSet clips = ugnet_clips(s);
  ASSERT_EQ(clips.columns, 56);
  const std::span<const float> c = clips.example(1);  // starts at pair 0
  const int row = 4;
  EXPECT_EQ(c[row * 56 + 5], s[0].pose[row * 24 + 5]);               // x_i
  EXPECT_EQ(c[row * 56 + 24], s[0].features[(row + 1) * 11 + 6]);    // θ^H of frame i+1
  EXPECT_EQ(c[row * 56 + 30], s[0].progression[(row + 1) * 3 + 1]);  // deictic of i+1
  EXPECT_EQ(c[row * 56 + 32 + 20], s[0].pose[(row + 1) * 24 + 20]);  // x_{i+1}
}

TEST(Clips, FreeFormHoldKeepsThePartWhoseProgressionIsZero) {
  std::vector<Sequence> s = test_data::synthetic_sequences(1, 50, 6);
  s[0].category = Category::kPointingTransition;
  for (int f = 0; f < 50; ++f) {
    s[0].progression[f * 3 + 0] = f % 2 == 0 ? 0.0f : 0.5f;  // gaze 0 on even frames
    s[0].progression[f * 3 + 1] = 0.0f;                      // deictic always 0
  }
  const ExampleSet clips = ugnet_clips(s);
  const std::span<const float> c = clips.example(1);  // pairs 0…44
  for (int i = 0; i < 45; ++i) {
    const float* target = c.data() + i * 56 + 32;
    const float* now = s[0].pose.data() + i * 24;
    const float* next = now + 24;
    const bool gaze_zero = (i + 1) % 2 == 0;
    EXPECT_EQ(target[4], gaze_zero ? now[4] : next[4]) << i;  // head part
    EXPECT_EQ(target[19], now[19]) << i;                      // hand part held throughout
  }
}

TEST(Clips, MirrorIsItsOwnInverseAndNegatesTheta) {
  std::vector<Sequence> s = test_data::synthetic_sequences(1, 10, 7);
  Sequence m = s[0];
  mirror(m);
  EXPECT_EQ(m.features[6], -s[0].features[6]);  // θ^H
  EXPECT_EQ(m.features[7], s[0].features[7]);   // φ^H unchanged
  EXPECT_EQ(m.pose[21], -s[0].pose[21]);        // fingertip x
  EXPECT_EQ(m.pose[22], s[0].pose[22]);
  mirror(m);
  EXPECT_EQ(m.pose, s[0].pose);
  EXPECT_EQ(m.features, s[0].features);
}

// ---- schedules ----

TEST(Schedule, LearningRateAndScheduledSampling) {
  const Schedule mpnet = default_schedule(Family::kMpnet);
  EXPECT_EQ(mpnet.epochs, 80);
  EXPECT_EQ(mpnet.batch_size, 16);
  EXPECT_DOUBLE_EQ(mpnet.learning_rate_at(1), 1e-4);
  EXPECT_NEAR(mpnet.learning_rate_at(3), 1e-4 * 0.975 * 0.975, 1e-15);
  EXPECT_EQ(mpnet.teacher_forcing_at(70), 1.0);
  const Schedule ugnet = default_schedule(Family::kUgnet);
  EXPECT_EQ(ugnet.epochs, 120);
  EXPECT_EQ(ugnet.batch_size, 32);
  EXPECT_NEAR(ugnet.learning_rate_at(2), 0.99e-4, 1e-15);
  EXPECT_EQ(ugnet.teacher_forcing_at(30), 1.0);
  EXPECT_NEAR(ugnet.teacher_forcing_at(45), 0.5, 1e-12);
  EXPECT_EQ(ugnet.teacher_forcing_at(60), 0.0);
  EXPECT_EQ(ugnet.teacher_forcing_at(120), 0.0);
}

// A schedule compressed to a tenth of its epochs keeps its shape: scheduled sampling decays over
// the same share of the run and the last epoch's learning rate is the full schedule's last.
TEST(Schedule, CompressedKeepsTheShapeOfTheWholeSchedule) {
  const Schedule full = default_schedule(Family::kUgnet);
  const Schedule s = compressed(full, 12);
  EXPECT_EQ(s.epochs, 12);
  EXPECT_EQ(s.teacher_forcing_epochs, 3);
  EXPECT_EQ(s.autoregressive_from_epoch, 6);
  EXPECT_EQ(s.teacher_forcing_at(3), 1.0);
  EXPECT_NEAR(s.teacher_forcing_at(4), 2.0 / 3.0, 1e-12);
  EXPECT_EQ(s.teacher_forcing_at(6), 0.0);
  EXPECT_NEAR(s.learning_rate_at(12), full.learning_rate_at(120), 1e-18);
  EXPECT_NEAR(s.learning_rate_at(1), full.learning_rate_at(1), 1e-18);
  EXPECT_EQ(s.batch_size, full.batch_size);
  // Compressed to its own length it is the schedule itself.
  const Schedule same = compressed(full, 120);
  EXPECT_EQ(same.teacher_forcing_epochs, 30);
  EXPECT_EQ(same.autoregressive_from_epoch, 60);
  EXPECT_NEAR(same.learning_rate_decay, full.learning_rate_decay, 1e-15);
  // Two epochs: the first teacher-forced, the second autoregressive, ending at the last rate.
  const Schedule two = compressed(full, 2);
  EXPECT_EQ(two.teacher_forcing_at(1), 1.0);
  EXPECT_EQ(two.teacher_forcing_at(2), 0.0);
  EXPECT_NEAR(two.learning_rate_at(2), full.learning_rate_at(120), 1e-18);
  // One epoch cannot hold the schedule's shape.
  EXPECT_THROW(compressed(full, 1), deixis::Error);
  EXPECT_THROW(compressed(full, 0), deixis::Error);
  EXPECT_THROW(compressed(full, 121), deixis::Error);
}

// Continuing a schedule (fine-tuning): the learning rate goes on from where the full schedule
// ended, UGNet stays fully autoregressive, MPNet keeps feeding its ground truth.
TEST(Schedule, ContinuedGoesOnFromTheEndOfTheSchedule) {
  const Schedule ugnet = default_schedule(Family::kUgnet);
  const Schedule u = continued(ugnet, 20);
  EXPECT_EQ(u.epochs, 20);
  EXPECT_NEAR(u.learning_rate_at(1), ugnet.learning_rate_at(121), 1e-18);
  EXPECT_NEAR(u.learning_rate_at(20), ugnet.learning_rate_at(140), 1e-18);
  for (const int epoch : {1, 10, 20}) {
    EXPECT_EQ(u.teacher_forcing_at(epoch), 0.0) << epoch;
  }
  EXPECT_EQ(u.batch_size, ugnet.batch_size);
  const Schedule mpnet = default_schedule(Family::kMpnet);
  const Schedule m = continued(mpnet, 5);
  EXPECT_NEAR(m.learning_rate_at(1), 1e-4 * std::pow(0.975, 80), 1e-18);
  EXPECT_EQ(m.teacher_forcing_at(3), 1.0);
  // Still teacher-forced at its end (cut to 20 epochs): stays teacher-forced.
  Schedule early = ugnet;
  early.epochs = 20;
  EXPECT_EQ(continued(early, 4).teacher_forcing_at(4), 1.0);
  // Cut inside the ramp: no single P to keep.
  early.epochs = 45;
  EXPECT_THROW(continued(early, 4), deixis::Error);
  EXPECT_THROW(continued(ugnet, 0), deixis::Error);
}

// ---- progress ----

// The ETA follows the pace of the last five epochs: after a run sped up (a faster trainer, a
// quieter machine) it says so at once instead of averaging in the slow start.
TEST(Progress, TheEtaFollowsTheRecentPace) {
  std::vector<EpochReport> history;
  EXPECT_EQ(eta_seconds(history, 10), 0.0);
  for (int e = 1; e <= 20; ++e) {
    EpochReport r;
    r.epoch = e;
    r.seconds = e <= 15 ? 180.0 : 30.0;
    history.push_back(r);
  }
  EXPECT_DOUBLE_EQ(eta_seconds(history, 100), 80 * 30.0);
  history.resize(2);
  EXPECT_DOUBLE_EQ(eta_seconds(history, 4), 2 * 180.0);
  EXPECT_EQ(eta_seconds(history, 2), 0.0);
}

// ---- checkpoint file ----

TEST(Checkpoint, RoundTripsExactly) {
  deixis::testing::ScratchDir dir;
  Checkpoint c;
  c.fingerprint = "MPNet(MoE)|seed 3";
  c.epoch = 7;
  c.batch = 12;
  c.step = 1234;
  c.loss_sum = 0.1 + 0.2;  // not representable in short decimal: must round-trip bit-exactly
  c.loss_count = 99;
  c.history.push_back({1, 0.123456789012345, std::numeric_limits<double>::quiet_NaN(), 1e-4, 1, 3});
  c.parameters = {1.5f, -2.0f, 3.25f};
  c.exp_avg = {0.1f, 0.2f, 0.3f};
  c.exp_avg_sq = {0.01f, 0.02f, 0.03f};
  c.trainers = {"unrecorded", "ffb63a1", "abc1234-dirty"};
  write_checkpoint(dir.path() / "c.safetensors", c);
  const Checkpoint r = read_checkpoint(dir.path() / "c.safetensors");
  EXPECT_EQ(r.fingerprint, c.fingerprint);
  EXPECT_EQ(r.epoch, 7);
  EXPECT_EQ(r.batch, 12);
  EXPECT_EQ(r.step, 1234);
  EXPECT_EQ(r.loss_sum, c.loss_sum);
  ASSERT_EQ(r.history.size(), 1u);
  EXPECT_EQ(r.history[0].train_loss, c.history[0].train_loss);
  EXPECT_TRUE(std::isnan(r.history[0].validation_loss));
  EXPECT_EQ(r.parameters, c.parameters);
  EXPECT_EQ(r.exp_avg_sq, c.exp_avg_sq);
  EXPECT_EQ(r.trainers, c.trainers);
}

// Checkpoints written before the list of trainers existed still resume; their earlier training
// is marked "unrecorded" rather than attributed to the binary that resumes them.
TEST(Checkpoint, AnOlderCheckpointWithoutTrainersSaysTheyAreUnrecorded) {
  deixis::testing::ScratchDir dir;
  Checkpoint c;
  c.fingerprint = "UGNet(MoE)|seed 1";
  c.step = 10;
  c.parameters = c.exp_avg = c.exp_avg_sq = {1.0f};
  write_checkpoint(dir.path() / "new.safetensors", c);
  const SafetensorsFile file = SafetensorsFile::read(dir.path() / "new.safetensors");
  nlohmann::json state = nlohmann::json::parse(file.metadata_value("state"));
  const auto rewrite = [&](const std::filesystem::path& path) {  // same tensors, the edited state
    SafetensorsWriter w;
    const std::vector<std::int64_t> shape = {1};
    for (const char* name : {"parameters", "exp_avg", "exp_avg_sq"}) {
      w.add_f32(name, shape, file.read_f32(name, shape));
    }
    w.set_metadata("format", "deixis-train checkpoint 1");
    w.set_metadata("state", state.dump());
    w.write(path);
  };
  state.erase("trainers");
  rewrite(dir.path() / "old.safetensors");
  EXPECT_EQ(read_checkpoint(dir.path() / "old.safetensors").trainers,
            std::vector<std::string>{"unrecorded"});
  state["trainers"] = "not a list";
  rewrite(dir.path() / "bad.safetensors");
  try {
    read_checkpoint(dir.path() / "bad.safetensors");
    ADD_FAILURE() << "a malformed trainers field was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'trainers'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace deixis::train
