// Training itself: a tiny run lowers its loss (MPNet and UGNet MoE); a run killed with SIGKILL in
// the middle of an epoch and started again with the same command reproduces the losses and the
// weights of a run that was never interrupted; the exported weights load in the runtime; a
// fine-tuning run starts from the weights it is given; a corrupt dataset, another network's
// weights or a checkpoint of another run fails with the file and the field named.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "core/error.h"
#include "core/io/machine.h"
#include "core/io/safetensors.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "synthetic_sequences.h"
#include "test_support.h"
#include "train/checkpoint.h"
#include "train/manifest.h"
#include "train/trainer.h"

extern char** environ;

namespace deixis::train {
namespace {

namespace fs = std::filesystem;

TrainOptions tiny_options(Network network, const fs::path& out) {
  TrainOptions o;
  o.network = network;
  o.schedule = default_schedule(family_of(network));
  o.schedule.epochs = 3;
  o.schedule.batch_size = 8;
  o.schedule.learning_rate = 1e-3;  // a few steps must show progress
  o.seed = 11;
  o.out_dir = out;
  o.dataset_hash = "test";
  return o;
}

TEST(Training, TinyMpnetLowersItsLoss) {
  deixis::testing::ScratchDir dir;
  const std::vector<Sequence> train = test_data::synthetic_sequences(20, 60, 1);
  const std::vector<Sequence> validation = test_data::synthetic_sequences(6, 60, 2);
  const TrainingData data{mpnet_clips(train), mpnet_clips(validation)};
  std::ostringstream log;
  const TrainOutcome out = train::train(tiny_options(Network::kMpnetMoe, dir.path()), data, log);
  ASSERT_EQ(out.history.size(), 3u);
  EXPECT_LT(out.history.back().train_loss, 0.8 * out.history.front().train_loss) << log.str();
  EXPECT_LT(out.history.back().validation_loss, out.history.front().validation_loss) << log.str();
  EXPECT_NE(log.str().find("epoch 3/3"), std::string::npos);
  // The exported file is what the runtime loads.
  const nn::Mpnet runtime = nn::Mpnet::load(out.weights);
  EXPECT_EQ(runtime.architecture(), nn::MpnetArchitecture::kGruMoe);
}

TEST(Training, TinyUgnetLowersItsLossWithScheduledSampling) {
  deixis::testing::ScratchDir dir;
  const std::vector<Sequence> train = test_data::synthetic_sequences(12, 60, 3);
  const TrainingData data{ugnet_clips(train), {}};
  TrainOptions o = tiny_options(Network::kUgnetMoe, dir.path());
  o.schedule.teacher_forcing_epochs = 1;  // P: 1, 0.5, 0 over the three epochs
  o.schedule.autoregressive_from_epoch = 3;
  std::ostringstream log;
  const TrainOutcome out = train::train(o, data, log);
  ASSERT_EQ(out.history.size(), 3u);
  EXPECT_EQ(out.history[1].teacher_forcing, 0.5);
  EXPECT_LT(out.history.back().train_loss, out.history.front().train_loss) << log.str();
  const nn::Ugnet runtime = nn::Ugnet::load(out.weights);
  EXPECT_EQ(runtime.architecture(), nn::UgnetArchitecture::kMoe);
}

// A tiny UGNet of the given architecture, trained three epochs with teacher forcing only (the loss
// of the network alone), must lower its loss and export what the runtime loads.
void expect_tiny_ugnet_learns(Network network, nn::UgnetArchitecture architecture) {
  deixis::testing::ScratchDir dir;
  const std::vector<Sequence> train = test_data::synthetic_sequences(12, 60, 3);
  const TrainingData data{ugnet_clips(train), {}};
  TrainOptions o = tiny_options(network, dir.path());
  o.schedule.teacher_forcing_epochs = 3;
  o.schedule.autoregressive_from_epoch = 4;
  std::ostringstream log;
  const TrainOutcome out = train::train(o, data, log);
  ASSERT_EQ(out.history.size(), 3u);
  EXPECT_LT(out.history.back().train_loss, 0.8 * out.history.front().train_loss) << log.str();
  const nn::Ugnet runtime = nn::Ugnet::load(out.weights);
  EXPECT_EQ(runtime.architecture(), architecture);
}

// The UGNet Transformer trains through the fused encoder layers (fused_transformer.h), dropout
// included.
TEST(Training, TinyUgnetTransformerLowersItsLoss) {
  expect_tiny_ugnet_learns(Network::kUgnetTransformer, nn::UgnetArchitecture::kTransformer);
}

// The UGNet Diffusion trains through the fused denoiser (fused_denoiser.h) on its own objective
// (the clean pose from a noised one at a random step).
TEST(Training, TinyUgnetDiffusionLowersItsLoss) {
  expect_tiny_ugnet_learns(Network::kUgnetDiffusion, nn::UgnetArchitecture::kDiffusion);
}

// The MoE networks and the autoencoder train through direct steps (moe_step.h,
// autoencoder_step.h); --autograd runs the same schedule through libtorch's autograd. Both must
// follow the same trajectory and export the same weights, with UGNet's scheduled sampling feeding
// predictions back in the last two epochs. The first epoch must agree to 1e-5; after it, float
// rounding (a different order of additions) grows as any two training runs' do, fastest for
// MPNet, whose clamp and L1 loss switch on signs, so later epochs get `tolerance`.
void expect_same_training_as_autograd(Network network, const TrainingData& data, double tolerance) {
  deixis::testing::ScratchDir dir;
  TrainOptions direct = tiny_options(network, dir.path() / "direct");
  if (network == Network::kMotionAutoencoder) {
    direct.schedule.batch_size = 3;  // the validation's last batch is then partial
  }
  direct.schedule.teacher_forcing_epochs = 1;
  direct.schedule.autoregressive_from_epoch = 3;
  TrainOptions autograd = direct;
  autograd.out_dir = dir.path() / "autograd";
  autograd.autograd = true;
  std::ostringstream log;
  const TrainOutcome a = train::train(direct, data, log);
  const TrainOutcome b = train::train(autograd, data, log);
  ASSERT_EQ(a.history.size(), b.history.size());
  for (std::size_t e = 0; e < a.history.size(); ++e) {
    const double within = e == 0 ? 1e-5 : tolerance;
    EXPECT_NEAR(a.history[e].train_loss, b.history[e].train_loss, within * b.history[e].train_loss)
        << "epoch " << e + 1;
    if (!data.validation.values.empty()) {
      EXPECT_NEAR(a.history[e].validation_loss, b.history[e].validation_loss,
                  within * b.history[e].validation_loss)
          << "epoch " << e + 1;
    }
  }
  EXPECT_NE(a.history.back().train_loss, a.history.front().train_loss);
  const SafetensorsFile wa = SafetensorsFile::read(a.weights);
  const SafetensorsFile wb = SafetensorsFile::read(b.weights);
  double largest = 0, difference = 0;
  for (const TensorInfo& t : wb.tensors()) {
    const std::vector<float> x = wa.read_f32(t.name, t.shape), y = wb.read_f32(t.name, t.shape);
    for (std::size_t i = 0; i < x.size(); ++i) {
      largest = std::max(largest, static_cast<double>(std::abs(y[i])));
      difference = std::max(difference, static_cast<double>(std::abs(x[i] - y[i])));
    }
  }
  // Adam moves a parameter whose gradient is mostly rounding noise by up to the learning rate per
  // step, either way: the weights are compared at 1e-3 of the largest at least.
  EXPECT_LT(difference, std::max(tolerance, 1e-3) * largest);
}

// deixis-train --threads 2 cuts every batch of the direct steps in two (parallel_steps.h): the
// same optimiser steps as one thread, the slices' gradients added before each, so the same
// trajectory to rounding. A batch of 5 leaves the second member 2 clips, and validation's last
// batch of 1, 2 or 3 clips leaves it fewer or none. The first epoch must agree to 1e-5, the
// later ones to `tolerance`; 0 compares the first only (a tiny MPNet at a learning rate of 1e-3
// and batches of 5 turns rounding into an epoch-3 difference of several percent; its single
// steps are compared in parallel_steps_test.cpp).
void expect_two_threads_train_as_one(Network network, const TrainingData& data, double tolerance) {
  deixis::testing::ScratchDir dir;
  TrainOptions one = tiny_options(network, dir.path() / "one");
  one.schedule.batch_size = 5;
  one.schedule.teacher_forcing_epochs = 1;
  one.schedule.autoregressive_from_epoch = 3;
  TrainOptions two = one;
  two.out_dir = dir.path() / "two";
  two.threads = 2;
  std::ostringstream log;
  const TrainOutcome a = train::train(one, data, log);
  const TrainOutcome b = train::train(two, data, log);
  ASSERT_EQ(a.history.size(), b.history.size());
  const std::size_t compared = tolerance > 0 ? a.history.size() : 1;
  for (std::size_t e = 0; e < compared; ++e) {
    const double within = e == 0 ? 1e-5 : tolerance;
    EXPECT_NEAR(b.history[e].train_loss, a.history[e].train_loss, within * a.history[e].train_loss)
        << "epoch " << e + 1;
    EXPECT_NEAR(b.history[e].validation_loss, a.history[e].validation_loss,
                within * a.history[e].validation_loss)
        << "epoch " << e + 1;
  }
  EXPECT_LT(b.history.back().train_loss, b.history.front().train_loss);
}

TEST(Training, TwoThreadsTrainTheMoeNetworksAsOneDoes) {
  const ExampleSet validation = ugnet_clips(test_data::synthetic_sequences(3, 61, 4));
  ASSERT_NE(validation.count % 5, 0u);
  expect_two_threads_train_as_one(
      Network::kUgnetMoe, {ugnet_clips(test_data::synthetic_sequences(12, 60, 3)), validation},
      1e-4);
  expect_two_threads_train_as_one(Network::kMpnetMoe,
                                  {mpnet_clips(test_data::synthetic_sequences(20, 60, 1)),
                                   mpnet_clips(test_data::synthetic_sequences(3, 61, 2))},
                                  0);
}

TEST(Training, TwoThreadsTrainTheAutoencoderAsOneDoes) {
  expect_two_threads_train_as_one(Network::kMotionAutoencoder,
                                  {motion_segments(test_data::synthetic_sequences(6, 60, 5)),
                                   motion_segments(test_data::synthetic_sequences(2, 50, 6))},
                                  1e-4);
}

// The validation sets' clip counts are not multiples of the batch of 8 (asserted), so the last
// validation batch of every epoch is a partial one.
TEST(Training, MpnetMoeStepTrainsAsAutogradDoes) {
  const std::vector<Sequence> train = test_data::synthetic_sequences(20, 60, 1);
  const ExampleSet validation = mpnet_clips(test_data::synthetic_sequences(3, 61, 2));
  ASSERT_NE(validation.count % 8, 0u);
  expect_same_training_as_autograd(Network::kMpnetMoe, {mpnet_clips(train), validation}, 1e-2);
}

TEST(Training, UgnetMoeStepTrainsAsAutogradDoes) {
  const std::vector<Sequence> train = test_data::synthetic_sequences(12, 60, 3);
  const ExampleSet validation = ugnet_clips(test_data::synthetic_sequences(3, 61, 4));
  ASSERT_NE(validation.count % 8, 0u);
  expect_same_training_as_autograd(Network::kUgnetMoe, {ugnet_clips(train), validation}, 1e-4);
}

TEST(Training, AutoencoderStepTrainsAsAutogradDoes) {
  const std::vector<Sequence> train = test_data::synthetic_sequences(6, 60, 5);
  const std::vector<Sequence> validation = test_data::synthetic_sequences(2, 50, 6);
  expect_same_training_as_autograd(Network::kMotionAutoencoder,
                                   {motion_segments(train), motion_segments(validation)}, 1e-4);
}

TEST(Training, TinyAutoencoderLowersItsLossAndReportsItsReconstruction) {
  deixis::testing::ScratchDir dir;
  const std::vector<Sequence> train = test_data::synthetic_sequences(20, 60, 5);
  const std::vector<Sequence> validation = test_data::synthetic_sequences(6, 60, 6);
  const TrainingData data{motion_segments(train), motion_segments(validation)};
  std::ostringstream log;
  const TrainOutcome out =
      train::train(tiny_options(Network::kMotionAutoencoder, dir.path()), data, log);
  ASSERT_EQ(out.history.size(), 3u);
  EXPECT_LT(out.history.back().train_loss, out.history.front().train_loss) << log.str();
  // The paper's encoder figures: per-frame position and rotation error, training and validation.
  EXPECT_NE(log.str().find("reconstruction per frame: training "), std::string::npos) << log.str();
  const nlohmann::json manifest = nlohmann::json::parse(std::ifstream(out.manifest));
  for (const char* set : {"training", "validation"}) {
    const nlohmann::json& e = manifest.at("reconstruction").at(set);
    EXPECT_GT(e.at("position_cm").get<double>(), 0.0) << set;
    EXPECT_GT(e.at("rotation_deg").get<double>(), 0.0) << set;
    EXPECT_LT(e.at("rotation_deg").get<double>(), 180.0) << set;
  }
  EXPECT_EQ(manifest.at("reconstruction").at("training").at("segments").get<std::size_t>(),
            data.train.count);
}

TEST(Training, TooLittleDataIsAClearError) {
  deixis::testing::ScratchDir dir;
  const TrainingData data{mpnet_clips(test_data::synthetic_sequences(1, 50, 4)), {}};
  std::ostringstream log;
  EXPECT_THROW(train::train(tiny_options(Network::kMpnetMoe, dir.path()), data, log), Error);
}

// ---- the executable: resume after SIGKILL, errors ----

struct Result {
  int exit_code = -1;
  std::string output;
};

pid_t spawn(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<char*> argv;
  for (const auto& a : args) {
    argv.push_back(const_cast<char*>(a.c_str()));
  }
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  EXPECT_EQ(posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  return pid;
}

std::string read_text(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

Result run(const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = spawn(args, log);
  int status = 0;
  waitpid(pid, &status, 0);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(log)};
}

std::vector<std::string> command(const fs::path& data, const fs::path& validation,
                                 const fs::path& out, const std::string& seed = "5") {
  return {DEIXIS_TRAIN_EXE,
          "mpnet",
          "--data",
          data.string(),
          "--validation",
          validation.string(),
          "--out",
          out.string(),
          "--epochs",
          "4",
          "--batch-size",
          "4",
          "--lr",
          "1e-3",
          "--seed",
          seed,
          "--checkpoint-batches",
          "3",
          "--threads",
          "1"};
}

nlohmann::json manifest(const fs::path& out) {
  return nlohmann::json::parse(read_text(out / "MPNet(MoE)(AC).manifest.json"));
}

class Executable : public ::testing::Test {
 protected:
  void SetUp() override {
    data_ = dir_.path() / "train.safetensors";
    validation_ = dir_.path() / "validation.safetensors";
    test_data::dataset_writer(test_data::synthetic_sequences(30, 60, 7)).write(data_);
    test_data::dataset_writer(test_data::synthetic_sequences(8, 60, 8)).write(validation_);
  }
  deixis::testing::ScratchDir dir_;
  fs::path data_, validation_;
};

TEST_F(Executable, ResumeAfterKillReproducesTheUninterruptedRun) {
  const fs::path whole = dir_.path() / "whole";
  const Result uninterrupted = run(command(data_, validation_, whole), dir_.path() / "whole.log");
  ASSERT_EQ(uninterrupted.exit_code, 0) << uninterrupted.output;

  // Start the same run elsewhere and kill it once a checkpoint from inside epoch 2 exists.
  const fs::path killed = dir_.path() / "killed";
  const pid_t pid = spawn(command(data_, validation_, killed), dir_.path() / "killed.log");
  const fs::path checkpoint = killed / "checkpoint.safetensors";
  bool mid_epoch = false;
  for (int i = 0; i < 20000 && !mid_epoch; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (fs::exists(checkpoint)) {
      try {
        const Checkpoint c = read_checkpoint(checkpoint);
        mid_epoch = c.epoch >= 2 && c.batch > 0;
      } catch (const Error&) {
      }
    }
  }
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(mid_epoch) << "no mid-epoch checkpoint appeared";
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run finished before it could be killed";
  EXPECT_FALSE(fs::exists(killed / "MPNet(MoE)(AC).manifest.json"));

  // --export-to writes the interrupted run's weights elsewhere, says where the run stood, and
  // leaves its checkpoint as it was (the resume below must still reproduce the whole run).
  const std::string checkpoint_bytes = read_text(checkpoint);
  const Checkpoint at_kill = read_checkpoint(checkpoint);
  std::vector<std::string> export_args = command(data_, validation_, killed);
  const fs::path partial = dir_.path() / "partial";
  export_args.insert(export_args.end(), {"--export-to", partial.string()});
  const Result exported = run(export_args, dir_.path() / "export.log");
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_EQ(read_text(checkpoint), checkpoint_bytes);
  EXPECT_FALSE(fs::exists(killed / "MPNet(MoE)(AC).safetensors"));
  const nlohmann::json p = manifest(partial);
  EXPECT_FALSE(p["complete"].get<bool>());
  EXPECT_EQ(p["stopped_at"]["epoch"].get<int>(), at_kill.epoch);
  EXPECT_EQ(p["stopped_at"]["batch"].get<std::int64_t>(), at_kill.batch);
  EXPECT_EQ(p["history"].size(), at_kill.history.size());
  const SafetensorsFile partial_weights =
      SafetensorsFile::read(partial / "MPNet(MoE)(AC).safetensors");

  const Result resumed = run(command(data_, validation_, killed), dir_.path() / "resumed.log");
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("resuming from"), std::string::npos) << resumed.output;

  const nlohmann::json a = manifest(whole), b = manifest(killed);
  ASSERT_EQ(a["history"].size(), 4u);
  ASSERT_EQ(b["history"].size(), 4u);
  for (std::size_t e = 0; e < 4; ++e) {
    EXPECT_EQ(a["history"][e]["train_loss"].get<double>(),
              b["history"][e]["train_loss"].get<double>())
        << "epoch " << e + 1;
    EXPECT_EQ(a["history"][e]["validation_loss"].get<double>(),
              b["history"][e]["validation_loss"].get<double>())
        << "epoch " << e + 1;
  }
  EXPECT_LT(a["final_train_loss"].get<double>(), a["history"][0]["train_loss"].get<double>());
  // Same weights to the bit; the export from mid-run holds the same tensors, less trained.
  const SafetensorsFile wa = SafetensorsFile::read(whole / "MPNet(MoE)(AC).safetensors");
  const SafetensorsFile wb = SafetensorsFile::read(killed / "MPNet(MoE)(AC).safetensors");
  bool partial_differs = false;
  for (const TensorInfo& t : wa.tensors()) {
    EXPECT_EQ(wa.read_f32(t.name, t.shape), wb.read_f32(t.name, t.shape)) << t.name;
    partial_differs = partial_differs ||
                      partial_weights.read_f32(t.name, t.shape) != wa.read_f32(t.name, t.shape);
  }
  EXPECT_EQ(partial_weights.tensors().size(), wa.tensors().size());
  EXPECT_TRUE(partial_differs);
  EXPECT_TRUE(a["complete"].get<bool>());
  EXPECT_FALSE(a.contains("stopped_at"));
  // The manifest says how the weights were made.
  EXPECT_EQ(a["seed"].get<int>(), 5);
  EXPECT_EQ(a["dataset_hash"].get<std::string>().size(), 64u);
  EXPECT_NE(a["command_line"].get<std::string>().find("--epochs 4"), std::string::npos);
  EXPECT_GT(a["wall_seconds"].get<double>(), 0.0);
  EXPECT_FALSE(a["commit"].get<std::string>().empty());
  // Trained by this one binary on this machine, without and with the interruption; the export
  // names no trainer of its own.
  const nlohmann::json one_trainer = nlohmann::json::array(
      {a["commit"].get<std::string>() + " on " + deixis::machine_description()});
  EXPECT_EQ(a["trained_by"], one_trainer);
  EXPECT_EQ(b["trained_by"], one_trainer);
  EXPECT_EQ(p["trained_by"], one_trainer);
}

TEST_F(Executable, ExportingAFinishedRunGivesItsWeightsAndExportingNothingIsAnError) {
  const fs::path out = dir_.path() / "out";
  ASSERT_EQ(run(command(data_, validation_, out), dir_.path() / "a.log").exit_code, 0);
  std::vector<std::string> args = command(data_, validation_, out);
  const fs::path copy = dir_.path() / "copy";
  args.insert(args.end(), {"--export-to", copy.string()});
  const Result exported = run(args, dir_.path() / "export.log");
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  const SafetensorsFile original = SafetensorsFile::read(out / "MPNet(MoE)(AC).safetensors");
  const SafetensorsFile again = SafetensorsFile::read(copy / "MPNet(MoE)(AC).safetensors");
  for (const TensorInfo& t : original.tensors()) {
    EXPECT_EQ(original.read_f32(t.name, t.shape), again.read_f32(t.name, t.shape)) << t.name;
  }
  EXPECT_TRUE(manifest(copy)["complete"].get<bool>());
  // Rerunning a finished run only re-exports it: a newer binary doing so adds no trainer.
  Checkpoint finished = read_checkpoint(out / "checkpoint.safetensors");
  finished.trainers = {"an-older-trainer"};
  write_checkpoint(out / "checkpoint.safetensors", finished);
  ASSERT_EQ(run(command(data_, validation_, out), dir_.path() / "again.log").exit_code, 0);
  EXPECT_EQ(manifest(out)["trained_by"], nlohmann::json::array({"an-older-trainer"}));
  EXPECT_EQ(manifest(copy)["history"], manifest(out)["history"]);

  std::vector<std::string> none = command(data_, validation_, dir_.path() / "never-ran");
  none.insert(none.end(), {"--export-to", (dir_.path() / "x").string()});
  const Result refused = run(none, dir_.path() / "none.log");
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.output.find("never-ran/checkpoint.safetensors: no checkpoint to export"),
            std::string::npos)
      << refused.output;
  EXPECT_FALSE(fs::exists(dir_.path() / "x"));
  EXPECT_FALSE(fs::exists(dir_.path() / "never-ran"));
}

TEST_F(Executable, ACheckpointOfAnotherRunIsRefused) {
  const fs::path out = dir_.path() / "out";
  ASSERT_EQ(run(command(data_, validation_, out), dir_.path() / "a.log").exit_code, 0);
  const Result other = run(command(data_, validation_, out, "6"), dir_.path() / "b.log");
  EXPECT_EQ(other.exit_code, 2);
  EXPECT_NE(other.output.find("checkpoint.safetensors"), std::string::npos) << other.output;
  EXPECT_NE(other.output.find("--restart"), std::string::npos) << other.output;
}

// Fine-tuning: a run given --init-weights starts from those weights (with a learning rate too
// small to move them, its export equals them to the bit; given the schedule's continuation, its
// first epoch already scores what the weights scored), the manifest names the file and its hash,
// and a checkpoint of a run from other weights is refused.
TEST_F(Executable, FineTuningStartsFromTheGivenWeights) {
  const fs::path base = dir_.path() / "base";
  ASSERT_EQ(run(command(data_, validation_, base), dir_.path() / "base.log").exit_code, 0);
  const fs::path weights = base / "MPNet(MoE)(AC).safetensors";
  auto fine_tune = [&](const fs::path& out, const fs::path& from,
                       const std::vector<std::string>& more) {
    std::vector<std::string> args = {DEIXIS_TRAIN_EXE, "mpnet",
                                     "--data",         data_.string(),
                                     "--validation",   validation_.string(),
                                     "--out",          out.string(),
                                     "--init-weights", from.string(),
                                     "--batch-size",   "4",
                                     "--seed",         "5",
                                     "--threads",      "1"};
    args.insert(args.end(), more.begin(), more.end());
    return run(args, out.string() + ".log");
  };

  const fs::path still = dir_.path() / "still";
  const Result a =
      fine_tune(still, weights, {"--epochs", "1", "--max-batches", "2", "--lr", "1e-30"});
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const SafetensorsFile original = SafetensorsFile::read(weights);
  const SafetensorsFile kept = SafetensorsFile::read(still / "MPNet(MoE)(AC).safetensors");
  for (const TensorInfo& t : original.tensors()) {
    EXPECT_EQ(original.read_f32(t.name, t.shape), kept.read_f32(t.name, t.shape)) << t.name;
  }
  const nlohmann::json m = manifest(still);
  EXPECT_EQ(m["initial_weights"]["file"].get<std::string>(), weights.string());
  EXPECT_EQ(m["initial_weights"]["sha256"].get<std::string>(), sha256_file(weights));

  const fs::path tuned = dir_.path() / "tuned";
  const Result b = fine_tune(tuned, weights, {"--continue", "1"});
  ASSERT_EQ(b.exit_code, 0) << b.output;
  const nlohmann::json first = manifest(base), second = manifest(tuned);
  EXPECT_LT(second["history"][0]["validation_loss"].get<double>(),
            first["history"][0]["validation_loss"].get<double>())
      << "the fine-tuning's first epoch should start from the trained weights";
  EXPECT_NEAR(second["schedule"]["learning_rate"].get<double>(), 1e-4 * std::pow(0.975, 80), 1e-18);
  EXPECT_FALSE(first.contains("initial_weights"));

  // Other starting weights (one value changed): the run's checkpoint is not theirs.
  const fs::path other = dir_.path() / "other.safetensors";
  SafetensorsWriter writer;
  bool changed = false;
  for (const TensorInfo& t : original.tensors()) {
    std::vector<float> values = original.read_f32(t.name, t.shape);
    if (!changed) {
      values[0] += 0.5f;
      changed = true;
    }
    writer.add_f32(t.name, t.shape, values);
  }
  writer.write(other);
  const Result refused = fine_tune(tuned, other, {"--continue", "1"});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.output.find("checkpoint of a different run"), std::string::npos)
      << refused.output;
}

TEST_F(Executable, FineTuningFromAnotherNetworksWeightsIsAnErrorNamingTheFile) {
  const fs::path base = dir_.path() / "base";
  ASSERT_EQ(run(command(data_, validation_, base), dir_.path() / "base.log").exit_code, 0);
  const fs::path weights = base / "MPNet(MoE)(AC).safetensors";
  const Result r =
      run({DEIXIS_TRAIN_EXE, "ugnet", "--data", data_.string(), "--out",
           (dir_.path() / "u").string(), "--init-weights", weights.string(), "--continue", "1"},
          dir_.path() / "u.log");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find(weights.string() + ": tensor"), std::string::npos) << r.output;
  // --continue needs --init-weights.
  const Result alone = run({DEIXIS_TRAIN_EXE, "mpnet", "--data", data_.string(), "--out",
                            (dir_.path() / "m").string(), "--continue", "1"},
                           dir_.path() / "m.log");
  EXPECT_EQ(alone.exit_code, 2);
  EXPECT_NE(alone.output.find("--init-weights"), std::string::npos) << alone.output;
}

TEST_F(Executable, ACorruptDatasetIsAnErrorNamingFileAndField) {
  // The training file with MPNet's features one column too wide.
  const fs::path bad = dir_.path() / "bad.safetensors";
  const SafetensorsFile valid = SafetensorsFile::read(data_);
  SafetensorsWriter writer;
  for (const auto& [key, value] : valid.metadata()) {
    writer.set_metadata(key, value);
  }
  for (const TensorInfo& t : valid.tensors()) {
    if (t.name == "mpnet_features") {
      const std::vector<float> features(static_cast<std::size_t>(t.shape[0]) * 12, 0.0f);
      writer.add_f32(t.name, {t.shape[0], 12}, features);
    } else {
      writer.add(t.name, t.dtype, t.shape, valid.bytes(t));
    }
  }
  writer.write(bad);
  const Result r = run(command(bad, validation_, dir_.path() / "out"), dir_.path() / "bad.log");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("bad.safetensors"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("'mpnet_features'"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace deixis::train
