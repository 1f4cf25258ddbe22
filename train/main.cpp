// `deixis-train`: fits the paper's networks on the project's datasets. This is the only
// translation unit that includes CLI11 (slow to compile); the work is in trainer.h and friends.
//
//   deixis-train mpnet --data train.safetensors --validation test*.safetensors --out out/mpnet
//   deixis-train ugnet --arch moe --hand left --data ... --out ...
//
// A run that stops for any reason continues from its last checkpoint when the same command is
// run again (--restart discards it).

#include <CLI/CLI.hpp>
#include <iostream>

#include "core/error.h"
#include "dataset/dataset.h"
#include "train/clips.h"
#include "train/interpolate.h"
#include "train/manifest.h"
#include "train/trainer.h"

namespace {

using namespace deixis::train;

struct Flags {
  std::vector<std::string> data, validation;
  std::string arch = "moe";
  std::string variant = "AC";
  std::string hand = "right";
  std::string out;
  std::uint64_t seed = 1;
  int threads = 1;
  int epochs = 0;
  int compress_to = 0;
  int continue_epochs = 0;
  std::string init_weights;
  int batch_size = 0;
  double learning_rate = 0;
  double checkpoint_seconds = 120;
  std::int64_t checkpoint_batches = 0;
  std::int64_t max_batches = 0;
  bool restart = false;
  bool autograd = false;
  std::string export_to;
};

void add_common(CLI::App* cmd, Flags& f, const std::string& architectures) {
  cmd->add_option("--data", f.data, "Training dataset files (the training subject, safetensors)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--validation", f.validation,
                  "Held-out subjects' dataset files for the validation loss")
      ->check(CLI::ExistingFile);
  if (!architectures.empty()) {
    cmd->add_option("--arch", f.arch, "Architecture: " + architectures)->capture_default_str();
    cmd->add_option("--variant", f.variant,
                    "AC: all ten categories; DG: deictic-gesture categories only")
        ->check(CLI::IsMember({"AC", "DG"}))
        ->capture_default_str();
  }
  cmd->add_option("--hand", f.hand,
                  "right, or left: files of the other hand are mirrored into this hand's view "
                  "(paper §III.C)")
      ->check(CLI::IsMember({"right", "left"}))
      ->capture_default_str();
  cmd->add_option("--out", f.out, "Output directory: checkpoint, weights, manifest")->required();
  cmd->add_option("--seed", f.seed, "Seed of initialisation, shuffling and sampling")
      ->capture_default_str();
  cmd->add_option("--threads", f.threads,
                  "Threads: MoE networks share out their nine experts (at most 9), the "
                  "autoencoder splits each batch (train/parallel_steps.h), the other "
                  "architectures use them as libtorch's intra-op threads")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  cmd->add_option("--epochs", f.epochs,
                  "Override the schedule's epoch count (after --compress-to: cut it short)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--compress-to", f.compress_to,
                  "Run the whole schedule in this many epochs: scheduled sampling's epochs scale "
                  "with it and the learning rate ends where the full schedule's does "
                  "(train/schedule.h); for where the full schedule cannot run")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--init-weights", f.init_weights,
                  "Start from these exported weights (this network's, e.g. a shipped "
                  "MPNet(MoE)(AC)80.safetensors) instead of a random initialisation: fine-tuning; "
                  "the optimiser's moments start at zero")
      ->check(CLI::ExistingFile);
  cmd->add_option("--continue", f.continue_epochs,
                  "With --init-weights: run this many epochs after the end of the schedule, the "
                  "learning rate going on from where it ended and scheduled sampling staying as "
                  "it ended (train/schedule.h continued; docs/training.md, \"Fine-tuning\")")
      ->check(CLI::PositiveNumber)
      ->needs("--init-weights")
      ->excludes("--compress-to");
  cmd->add_option("--batch-size", f.batch_size, "Override the schedule's batch size")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--lr", f.learning_rate, "Override the initial learning rate")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--checkpoint-seconds", f.checkpoint_seconds,
                  "Write a checkpoint at least this often (also after every epoch)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--checkpoint-batches", f.checkpoint_batches,
                  "Also write a checkpoint every N batches")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--max-batches", f.max_batches,
                  "At most N batches per epoch (timing and smoke runs)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--restart", f.restart, "Discard an existing checkpoint in --out");
  cmd->add_flag("--autograd", f.autograd,
                "Run MoE networks and the autoencoder through libtorch's autograd instead of "
                "their direct step (train/moe_step.h, autoencoder_step.h: the same maths, "
                "faster); for comparison. The other architectures always use autograd");
  cmd->add_option("--export-to", f.export_to,
                  "Train nothing: write the weights and manifest of --out's checkpoint (a run in "
                  "progress or a finished one) into this directory; the manifest says where the "
                  "run stood. Give the run's own options, as for resuming.");
}

std::vector<Sequence> load(const std::vector<std::string>& files, Variant variant, Hand hand) {
  std::vector<Sequence> sequences;
  for (const auto& file : files) {
    const deixis::dataset::Dataset d = deixis::dataset::Dataset::read(file);
    for (Sequence& s : training_sequences(d)) {
      if (variant == Variant::kDeicticOnly && !is_deictic_gesture(s.category)) {
        continue;
      }
      if (d.hand != hand) {
        mirror(s);  // another hand's view: its mirror image is this hand's (paper §III.C)
      }
      sequences.push_back(std::move(s));
    }
  }
  return sequences;
}

ExampleSet examples(Family family, const std::vector<Sequence>& sequences) {
  switch (family) {
    case Family::kMpnet:
      return mpnet_clips(sequences);
    case Family::kUgnet:
      return ugnet_clips(sequences);
    case Family::kMotionAutoencoder:
      return motion_segments(sequences);
  }
  return {};
}

int run(Family family, const Flags& f, const std::string& command_line) {
  TrainOptions o;
  const std::optional<Network> network =
      parse_architecture(family, family == Family::kMotionAutoencoder ? "conv" : f.arch);
  if (!network) {
    throw deixis::Error("--arch: '" + f.arch + "' is not an architecture of this network");
  }
  o.network = *network;
  o.variant = f.variant == "DG" ? Variant::kDeicticOnly : Variant::kAllCategories;
  o.hand = f.hand == "left" ? Hand::kLeft : Hand::kRight;
  o.schedule = default_schedule(family);
  if (f.compress_to > 0) {
    try {
      o.schedule = compressed(o.schedule, f.compress_to);
    } catch (const deixis::Error& e) {
      throw deixis::Error(std::string("--compress-to: ") + e.what());
    }
  }
  if (f.continue_epochs > 0) {
    o.schedule = continued(o.schedule, f.continue_epochs);
  }
  if (f.epochs > 0) {  // after compressing: a smoke run cuts the compressed schedule short
    o.schedule.epochs = f.epochs;
  }
  if (f.batch_size > 0) {
    o.schedule.batch_size = f.batch_size;
  }
  if (f.learning_rate > 0) {
    o.schedule.learning_rate = f.learning_rate;
  }
  o.seed = f.seed;
  o.threads = f.threads;
  o.out_dir = f.out;
  o.checkpoint_seconds = f.checkpoint_seconds;
  o.checkpoint_batches = f.checkpoint_batches;
  o.max_batches = f.max_batches;
  o.restart = f.restart;
  o.autograd = f.autograd;
  o.export_to = f.export_to;
  o.initial_weights = f.init_weights;
  o.command_line = command_line;
  std::vector<std::filesystem::path> files;
  for (const auto& list : {f.data, f.validation}) {
    for (const auto& file : list) {
      files.emplace_back(file);
      o.dataset_files.push_back(file);
    }
  }
  o.dataset_hash = dataset_hash(files);

  TrainingData data;
  data.train = examples(family, load(f.data, o.variant, o.hand));
  data.validation = examples(family, load(f.validation, o.variant, o.hand));
  train(o, data, std::cout);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "deixis-train: trains MPNet, UGNet (and the alternatives of the paper's Tables II-IV) and "
      "the FMD autoencoder on Deixis' datasets with libtorch, on the CPU. Progress per epoch, "
      "checkpoints, resume (run the same command again), and export of safetensors weights with "
      "the authors' tensor names plus a manifest JSON."};
  app.require_subcommand(1);
  Flags mpnet_flags, ugnet_flags, autoencoder_flags;
  CLI::App* mpnet = app.add_subcommand(
      "mpnet", "MPNet: 80 epochs, batch 16, AdamW 1e-4 x0.975/epoch, a step per window");
  add_common(mpnet, mpnet_flags, "moe, mlp, transformer");
  CLI::App* ugnet = app.add_subcommand(
      "ugnet",
      "UGNet: 120 epochs, batch 32, AdamW 1e-4 x0.99/epoch, scheduled sampling (teacher forcing "
      "to epoch 30, linear to autoregressive at 60)");
  add_common(ugnet, ugnet_flags, "moe, mlp, transformer, diffusion");
  CLI::App* autoencoder = app.add_subcommand(
      "autoencoder",
      "The FMD motion autoencoder: 600 epochs, batch 8, Adam 1e-3 x0.999/epoch, 30-frame "
      "segments of head and hand");
  add_common(autoencoder, autoencoder_flags, "");
  std::string from, to, blend_out;
  double alpha = 0.5;
  CLI::App* interpolate = app.add_subcommand(
      "interpolate",
      "Blend two weight files of one network, (1 - alpha) * FROM + alpha * TO per tensor (e.g. "
      "the weights a fine-tuning started from and its result; docs/training.md, "
      "\"Fine-tuning\"), with a manifest naming both");
  interpolate->add_option("--from", from, "Weights at alpha = 0")
      ->required()
      ->check(CLI::ExistingFile);
  interpolate->add_option("--to", to, "Weights at alpha = 1 (their manifest is carried over)")
      ->required()
      ->check(CLI::ExistingFile);
  interpolate->add_option("--alpha", alpha, "Share of --to")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  interpolate->add_option("--out", blend_out, "The blended weights (.safetensors)")->required();

  // Bad flags exit 2 (as bad files do, and as `deixis` does), with CLI11's message naming the
  // flag; --help exits 0.
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  std::string command_line;
  for (int i = 0; i < argc; ++i) {
    command_line += (i > 0 ? " " : "") + std::string(argv[i]);
  }
  try {
    if (mpnet->parsed()) {
      return run(Family::kMpnet, mpnet_flags, command_line);
    }
    if (ugnet->parsed()) {
      return run(Family::kUgnet, ugnet_flags, command_line);
    }
    if (interpolate->parsed()) {
      write_interpolation(from, to, alpha, blend_out);
      std::cout << "wrote " << blend_out << " (alpha " << alpha << ")\n";
      return 0;
    }
    return run(Family::kMotionAutoencoder, autoencoder_flags, command_line);
  } catch (const deixis::Error& e) {
    std::cerr << "deixis-train: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "deixis-train: error: " << e.what() << "\n";
    return 2;
  }
}
