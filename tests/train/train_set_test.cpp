// tools/train-set as a user runs it (a real shell script starting real deixis-train processes, two
// at a time): on a tiny capture it trains the shipped set for one epoch of two batches, and
// assembles a weight set under the authors' file names that the runtime loads as the right
// networks; run again, every run resumes from its finished checkpoint instead of training again;
// it fine-tunes the shipped weights into a set of the same names; bad options and missing data
// exit 2 naming them, and a failing run fails the command.

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "test_support.h"

namespace deixis::train {
namespace {

namespace fs = std::filesystem;

struct Outcome {
  int exit_code = -1;
  std::string output;  // standard output and error together
};

std::string read_all(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// `command` through the shell, its output captured in `scratch`.
Outcome run(const std::string& command, const fs::path& scratch) {
  const fs::path log = scratch / "command.log";
  const int status = std::system((command + " > '" + log.string() + "' 2>&1").c_str());
  Outcome outcome;
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  outcome.output = read_all(log);
  return outcome;
}

// The parts one after the other. (Appended piecewise: GCC 12 warns falsely, -Wrestrict, on
// short literal + std::string concatenations.)
template <typename... Parts>
std::string concat(const Parts&... parts) {
  std::string s;
  (s.append(parts), ...);
  return s;
}

std::string quoted(const std::string& path) {
  return concat("'", path, "'");
}

std::string train_set() {
  return quoted((deixis::testing::source_dir() / "tools/train-set").string());
}

// The training subject and one held-out subject per hand, at 2 % of the protocol's counts.
fs::path make_tiny_capture(const fs::path& scratch) {
  const fs::path data = scratch / "data";
  const Outcome capture = run(
      std::string("'") + DEIXIS_EXE +
          "' capture generate --sets train test --subjects 170,161,173 --count-scale 0.02 -o '" +
          data.string() + "'",
      scratch);
  EXPECT_EQ(capture.exit_code, 0) << capture.output;
  return data;
}

// For tests of the script's own logic: an empty training set (enough for its checks) and a
// stand-in trainer, a shell script running `body`.
struct StandIn {
  fs::path data, trainer;
};
StandIn make_stand_in(const fs::path& scratch, const std::string& body) {
  const StandIn stand_in{scratch / "data", scratch / "trainer.sh"};
  fs::create_directories(stand_in.data);
  std::ofstream(stand_in.data / "train_right.safetensors") << "";
  std::ofstream(stand_in.trainer) << "#!/bin/sh\n" << body;
  fs::permissions(stand_in.trainer, fs::perms::owner_all);
  return stand_in;
}

std::string train_command(const fs::path& data, const fs::path& out) {
  return train_set() + " --data '" + data.string() + "' --out '" + out.string() + "' --trainer '" +
         DEIXIS_TRAIN_EXE + "' -- --epochs 1 --max-batches 2";
}

TEST(TrainSet, TrainsTheShippedSetAndAssemblesAWeightSetTheRuntimeLoads) {
  deixis::testing::ScratchDir scratch;
  const fs::path data = make_tiny_capture(scratch.path());
  const fs::path out = scratch.path() / "train";
  const Outcome first = run(train_command(data, out), scratch.path());
  ASSERT_EQ(first.exit_code, 0) << first.output;
  for (const char* run_name :
       {"mpnet-moe-right", "mpnet-moe-left", "ugnet-moe-right", "ugnet-moe-left"}) {
    // Each run's epoch line reaches the terminal with the run's name.
    EXPECT_NE(first.output.find(concat("[", run_name, "] epoch 1/1")), std::string::npos)
        << run_name << "\n"
        << first.output;
  }
  for (const char* hand : {"right", "left"}) {
    const fs::path set = out / "weights" / hand;
    // One epoch, so the authors' names carry 1 where the full schedule's carry 80 and 120.
    EXPECT_EQ(nn::Mpnet::load(set / "MPNet(MoE)(AC)1.safetensors").architecture(),
              nn::MpnetArchitecture::kGruMoe);
    EXPECT_EQ(nn::Ugnet::load(set / "UGNet(MoE)(AC)1.safetensors").architecture(),
              nn::UgnetArchitecture::kMoe);
    const std::string manifest = read_all(set / "MPNet(MoE)(AC)1.manifest.json");
    EXPECT_NE(manifest.find(concat("\"hand\": \"", hand, "\"")), std::string::npos) << manifest;
  }

  // Again: every run finds its finished checkpoint and only exports; nothing trains.
  const std::string weights_before = read_all(out / "weights/left/UGNet(MoE)(AC)1.safetensors");
  const Outcome second = run(train_command(data, out), scratch.path());
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_EQ(second.output.find("epoch 1/1"), std::string::npos) << second.output;
  std::size_t resumed = 0;
  for (std::size_t at = second.output.find("resuming from"); at != std::string::npos;
       at = second.output.find("resuming from", at + 1)) {
    ++resumed;
  }
  EXPECT_EQ(resumed, 4u) << second.output;
  EXPECT_EQ(read_all(out / "weights/left/UGNet(MoE)(AC)1.safetensors"), weights_before);
}

// Fine-tuning the shipped weights (assets/weights) on a tiny capture: each run starts from the
// shipped file of its role, runs in a directory of its own, and its result takes that file's
// name, so the weight set drops in where the shipped one is.
TEST(TrainSet, FineTunesAWeightSetAndKeepsItsNames) {
  deixis::testing::ScratchDir scratch;
  const fs::path data = make_tiny_capture(scratch.path());
  const fs::path out = scratch.path() / "tuned";
  const fs::path shipped = deixis::testing::source_dir() / "assets/weights";
  const Outcome tuned =
      run(concat(train_set(), " --data ", quoted(data.string()), " --out ", quoted(out.string()),
                 " --trainer ", quoted(DEIXIS_TRAIN_EXE), " --fine-tune ", quoted(shipped.string()),
                 " --fine-tune-epochs 1,1 -- --max-batches 2"),
          scratch.path());
  ASSERT_EQ(tuned.exit_code, 0) << tuned.output;
  for (const char* hand : {"right", "left"}) {
    EXPECT_TRUE(fs::exists(out / concat("mpnet-moe-ft1-", hand) / "checkpoint.safetensors"));
    const fs::path set = out / "weights" / hand;
    EXPECT_EQ(nn::Mpnet::load(set / "MPNet(MoE)(AC)80.safetensors").architecture(),
              nn::MpnetArchitecture::kGruMoe);
    EXPECT_EQ(nn::Ugnet::load(set / "UGNet(MoE)(AC)120.safetensors").architecture(),
              nn::UgnetArchitecture::kMoe);
    const std::string manifest = read_all(set / "UGNet(MoE)(AC)120.manifest.json");
    EXPECT_NE(manifest.find(concat("\"file\": \"", (shipped / hand).string(),
                                   "/UGNet(MoE)(AC)120.safetensors\"")),
              std::string::npos)
        << manifest;
    EXPECT_NE(read_all(set / "UGNet(MoE)(AC)120.safetensors"),
              read_all(shipped / hand / "UGNet(MoE)(AC)120.safetensors"));
  }

  // 0 epochs for MPNet: only UGNet trains, and the set holds the shipped MPNet as it is.
  const fs::path half = scratch.path() / "half";
  const Outcome ugnet_only =
      run(concat(train_set(), " --data ", quoted(data.string()), " --out ", quoted(half.string()),
                 " --trainer ", quoted(DEIXIS_TRAIN_EXE), " --fine-tune ", quoted(shipped.string()),
                 " --fine-tune-epochs 0,1 -- --max-batches 2"),
          scratch.path());
  ASSERT_EQ(ugnet_only.exit_code, 0) << ugnet_only.output;
  EXPECT_EQ(ugnet_only.output.find("[mpnet"), std::string::npos) << ugnet_only.output;
  for (const char* hand : {"right", "left"}) {
    EXPECT_EQ(read_all(half / "weights" / hand / "MPNet(MoE)(AC)80.safetensors"),
              read_all(shipped / hand / "MPNet(MoE)(AC)80.safetensors"));
    EXPECT_NE(read_all(half / "weights" / hand / "UGNet(MoE)(AC)120.safetensors"),
              read_all(shipped / hand / "UGNet(MoE)(AC)120.safetensors"));
  }
  const Outcome nothing = run(concat(train_set(), " --data ", quoted(data.string()), " --trainer ",
                                     quoted(DEIXIS_TRAIN_EXE), " --fine-tune ",
                                     quoted(shipped.string()), " --fine-tune-epochs 0,0"),
                              scratch.path());
  EXPECT_EQ(nothing.exit_code, 2);
  EXPECT_NE(nothing.output.find("not '0,0'"), std::string::npos) << nothing.output;

  // A weight set missing a file, or fine-tuning another set: refused before any run.
  fs::create_directories(scratch.path() / "partial/right");
  const Outcome partial = run(concat(train_set(), " --data ", quoted(data.string()), " --trainer ",
                                     quoted(DEIXIS_TRAIN_EXE), " --fine-tune ",
                                     quoted((scratch.path() / "partial").string())),
                              scratch.path());
  EXPECT_EQ(partial.exit_code, 2);
  EXPECT_NE(partial.output.find("partial/right/MPNet(MoE)(AC)80.safetensors"), std::string::npos)
      << partial.output;
  const Outcome other_set =
      run(concat(train_set(), " --set fmd --data ", quoted(data.string()), " --trainer ",
                 quoted(DEIXIS_TRAIN_EXE), " --fine-tune ", quoted(shipped.string())),
          scratch.path());
  EXPECT_EQ(other_set.exit_code, 2);
  EXPECT_NE(other_set.output.find("--fine-tune works on --set shipped"), std::string::npos)
      << other_set.output;
}

TEST(TrainSet, BadOptionsAndMissingDataExitTwoNamingThem) {
  deixis::testing::ScratchDir scratch;
  const Outcome bad_set = run(train_set() + " --set everything", scratch.path());
  EXPECT_EQ(bad_set.exit_code, 2);
  EXPECT_NE(bad_set.output.find("'everything'"), std::string::npos) << bad_set.output;

  const Outcome bad_option = run(train_set() + " --fast", scratch.path());
  EXPECT_EQ(bad_option.exit_code, 2);
  EXPECT_NE(bad_option.output.find("'--fast'"), std::string::npos) << bad_option.output;

  // The UGNet Transformer's compressed epochs: 2 to its schedule's 120, refused before any run.
  for (const char* epochs : {"1", "121", "twelve"}) {
    const Outcome bad_epochs =
        run(concat(train_set(), " --set comparison --ugnet-transformer-epochs ", epochs),
            scratch.path());
    EXPECT_EQ(bad_epochs.exit_code, 2) << epochs;
    EXPECT_NE(bad_epochs.output.find(concat("from 2 to 120, not '", epochs, "'")),
              std::string::npos)
        << bad_epochs.output;
  }

  const fs::path missing = scratch.path() / "no-data";
  const Outcome no_data =
      run(train_set() + " --trainer '" + DEIXIS_TRAIN_EXE + "' --data '" + missing.string() + "'",
          scratch.path());
  EXPECT_EQ(no_data.exit_code, 2);
  EXPECT_NE(no_data.output.find((missing / "train_right.safetensors").string()), std::string::npos)
      << no_data.output;

  // deixis-train itself: a bad flag exits 2 naming it, as `deixis` does (the required flags given,
  // any existing file as --data, so the unknown flag is what is refused).
  const Outcome trainer = run(concat(quoted(DEIXIS_TRAIN_EXE), " mpnet --data ", train_set(),
                                     " --out ", quoted((scratch.path() / "t").string()), " --fast"),
                              scratch.path());
  EXPECT_EQ(trainer.exit_code, 2);
  EXPECT_NE(trainer.output.find("--fast"), std::string::npos) << trainer.output;

  // A schedule cannot be compressed into more epochs than it has: refused before any data is read.
  const Outcome compress =
      run(concat(quoted(DEIXIS_TRAIN_EXE), " mpnet --data ", train_set(), " --out ",
                 quoted((scratch.path() / "t").string()), " --compress-to 200"),
          scratch.path());
  EXPECT_EQ(compress.exit_code, 2);
  EXPECT_NE(compress.output.find("--compress-to: a schedule of 80 epochs can be compressed to 2 "
                                 "to 80 epochs, not 200"),
            std::string::npos)
      << compress.output;
  EXPECT_FALSE(fs::exists(scratch.path() / "t/checkpoint.safetensors"));
}

// A stopped session resumes the run nearest its end first: a run's hours left are its epochs left
// of its schedule when it has a checkpoint (its train.log's last epoch line), all of them when it
// has none. A stand-in trainer records the order the runs start in (only the order is tested
// here; the test above trains for real).
TEST(TrainSet, ResumesTheRunNearestItsEndFirst) {
  deixis::testing::ScratchDir scratch;
  const fs::path out = scratch.path() / "train";
  const fs::path order = scratch.path() / "order.txt";
  const StandIn stand_in =
      make_stand_in(scratch.path(), concat("while [ $# -gt 0 ]; do\n"
                                           "  [ \"$1\" = --out ] && basename \"$2\" >> '",
                                           order.string(),
                                           "'\n"
                                           "  shift\n"
                                           "done\n"));
  // UGNet MoE left: 119 of 120 epochs done (0.01 h left of 1.7); right: the same log but no
  // checkpoint, so it starts over (1.7 h, last).
  for (const char* hand : {"left", "right"}) {
    fs::create_directories(out / concat("ugnet-moe-", hand));
    std::ofstream(out / concat("ugnet-moe-", hand) / "train.log")
        << "epoch 118/120  train 0.1\nepoch 119/120  train 0.1\n";
  }
  std::ofstream(out / "ugnet-moe-left/checkpoint.safetensors") << "";

  const Outcome outcome =
      run(concat(train_set(), " --lanes 1 --data ", quoted(stand_in.data.string()), " --out ",
                 quoted(out.string()), " --trainer ", quoted(stand_in.trainer.string())),
          scratch.path());
  ASSERT_EQ(outcome.exit_code, 0) << outcome.output;
  std::istringstream lines(read_all(order));
  std::vector<std::string> started;
  for (std::string line; std::getline(lines, line);) {
    started.push_back(line);
  }
  ASSERT_EQ(started.size(), 4u) << read_all(order);
  EXPECT_EQ(started.front(), "ugnet-moe-left");
  EXPECT_EQ(started.back(), "ugnet-moe-right");
}

// The comparison set's UGNet Transformer runs its schedule compressed into the epochs asked for,
// in a run directory of its own per count (a checkpoint cannot resume under another schedule);
// 120 is the full schedule, uncompressed. A stand-in trainer records each run's command line.
TEST(TrainSet, TheComparisonSetCompressesTheUgnetTransformerAsAsked) {
  deixis::testing::ScratchDir scratch;
  const fs::path calls = scratch.path() / "calls.txt";
  const StandIn stand_in =
      make_stand_in(scratch.path(), concat("echo \"$@\" >> '", calls.string(), "'\n"));
  const auto transformer_calls = [&](const std::string& epochs) {
    fs::remove(calls);
    const Outcome outcome =
        run(concat(train_set(), " --set comparison --data ", quoted(stand_in.data.string()),
                   " --out ", quoted((scratch.path() / "train").string()), " --trainer ",
                   quoted(stand_in.trainer.string()), " --ugnet-transformer-epochs ", epochs),
            scratch.path());
    EXPECT_EQ(outcome.exit_code, 0) << outcome.output;
    std::vector<std::string> found;
    std::istringstream lines(read_all(calls));
    for (std::string line; std::getline(lines, line);) {
      if (line.starts_with("ugnet ") && line.find("--arch transformer") != std::string::npos) {
        found.push_back(line);
      }
    }
    return found;
  };
  const std::vector<std::string> compressed = transformer_calls("5");
  ASSERT_EQ(compressed.size(), 2u);
  for (const std::string& line : compressed) {
    EXPECT_NE(line.find("/ugnet-transformer-c5-"), std::string::npos) << line;
    EXPECT_NE(line.find("--compress-to 5"), std::string::npos) << line;
  }
  const std::vector<std::string> full = transformer_calls("120");
  ASSERT_EQ(full.size(), 2u);
  for (const std::string& line : full) {
    EXPECT_NE(line.find("/ugnet-transformer-"), std::string::npos) << line;
    EXPECT_EQ(line.find("/ugnet-transformer-c"), std::string::npos) << line;
    EXPECT_EQ(line.find("--compress-to"), std::string::npos) << line;
  }
}

TEST(TrainSet, AFailingRunFailsTheCommandAndShowsWhy) {
  deixis::testing::ScratchDir scratch;
  const fs::path data = make_tiny_capture(scratch.path());
  const Outcome failed = run(train_set() + " --data '" + data.string() + "' --out '" +
                                 (scratch.path() / "train").string() + "' --trainer '" +
                                 DEIXIS_TRAIN_EXE + "' -- --epochs 0",
                             scratch.path());
  EXPECT_EQ(failed.exit_code, 1) << failed.output;
  EXPECT_NE(failed.output.find("[ugnet-moe-right] FAILED (exit 2)"), std::string::npos)
      << failed.output;
  // The end of the run's log, shown under its name: deixis-train's own refusal of --epochs 0.
  EXPECT_NE(failed.output.find("[ugnet-moe-right]   --epochs: Value 0 not in range"),
            std::string::npos)
      << failed.output;
  EXPECT_FALSE(fs::exists(scratch.path() / "train/weights/right/MPNet(MoE)(AC)0.safetensors"));
}

}  // namespace
}  // namespace deixis::train
