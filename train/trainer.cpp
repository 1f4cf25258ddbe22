// The training loop (paper §IV, docs/conventions.md#training-data, the authors' train_MPNet.py /
// train_UGNet.py): per batch of clips, a 30-row window slides over the 45 rows and the optimiser
// steps once per window (16 steps per batch); UGNet replaces the newest pose of a window by the
// previous window's prediction with probability 1 − P (scheduled sampling).
//
// Speed on 2 CPU cores comes from removing per-operation overhead, not from changing the
// schedule: the MoE networks and the autoencoder train through direct steps without autograd
// (moe_step.h, autoencoder_step.h), the other architectures through fused autograd nodes
// (fused_gru.h, fused_experts.h, fused_transformer.h); all parameters live in one flat buffer so
// that AdamW is one loop over memory, and the data are gathered into one tensor per batch.

#include "train/trainer.h"

#include <ATen/CPUGeneratorImpl.h>
#include <torch/torch.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <ostream>
#include <random>
#include <sstream>

#include "core/error.h"
#include "core/io/machine.h"
#include "gesture/nn/motion_encoder.h"
#include "train/adamw.h"
#include "train/manifest.h"
#include "train/models.h"
#include "train/moe_step.h"
#include "train/parallel_steps.h"
#include "train/progress.h"
#include "train/reconstruction.h"

namespace deixis::train {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// splitmix64: independent, reproducible streams from (seed, epoch, batch).
std::uint64_t mix(std::uint64_t a, std::uint64_t b) {
  std::uint64_t z = a + 0x9e3779b97f4a7c15ULL * (b + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// The epoch's shuffled clip order (DataLoader(shuffle=True)). Fisher–Yates written out, so the
// order does not depend on the standard library's shuffle.
std::vector<std::size_t> epoch_order(std::size_t count, std::uint64_t seed, int epoch) {
  std::vector<std::size_t> order(count);
  for (std::size_t i = 0; i < count; ++i) {
    order[i] = i;
  }
  std::mt19937_64 rng(mix(seed, static_cast<std::uint64_t>(epoch)));
  for (std::size_t i = count; i > 1; --i) {
    const std::size_t j = static_cast<std::size_t>(rng() % i);
    std::swap(order[i - 1], order[j]);
  }
  return order;
}

// All parameters as views into one flat buffer, their gradients into another: AdamW becomes one
// pass over memory and a checkpoint is three flat arrays.
struct FlatParameters {
  torch::Tensor values, grads, exp_avg, exp_avg_sq;
  std::int64_t numel = 0;
};

FlatParameters flatten(torch::nn::Module& model) {
  FlatParameters flat;
  std::vector<torch::Tensor> parameters = model.parameters();
  for (const torch::Tensor& p : parameters) {
    flat.numel += p.numel();
  }
  flat.values = torch::empty({flat.numel});
  flat.grads = torch::zeros({flat.numel});
  flat.exp_avg = torch::zeros({flat.numel});
  flat.exp_avg_sq = torch::zeros({flat.numel});
  torch::NoGradGuard no_grad;
  std::int64_t offset = 0;
  for (torch::Tensor& p : parameters) {
    const std::int64_t n = p.numel();
    torch::Tensor value = flat.values.narrow(0, offset, n).view(p.sizes());
    value.copy_(p);
    p.set_data(value);
    p.mutable_grad() = flat.grads.narrow(0, offset, n).view(p.sizes());
    offset += n;
  }
  return flat;
}

std::span<float> span_of(torch::Tensor& t) {
  return {t.data_ptr<float>(), static_cast<std::size_t>(t.numel())};
}

torch::Tensor gather(const ExampleSet& set, const std::vector<std::size_t>& order,
                     std::size_t first, std::size_t count) {
  torch::Tensor batch = torch::empty({static_cast<std::int64_t>(count), set.rows, set.columns});
  float* out = batch.data_ptr<float>();
  for (std::size_t i = 0; i < count; ++i) {
    const std::span<const float> example = set.example(order[first + i]);
    std::copy(example.begin(), example.end(), out + i * set.example_size());
  }
  return batch;
}

// Where the time goes inside an epoch.
struct Timing {
  double data = 0, forward = 0, backward = 0, optimiser = 0;
};

// Column layout of the examples of each family (clips.h).
constexpr int kMpnetInputs = kFeatureColumns;   // 11, then 3 labels
constexpr int kUgnetInputs = kPoseColumns + 8;  // 32, then the 24-value target
constexpr int kWindowRows = 30;

class Run {
 public:
  Run(const TrainOptions& options, const TrainingData& data, std::ostream& log)
      : options_(options), data_(data), log_(log), family_(family_of(options.network)) {}

  TrainOutcome execute();

 private:
  struct Loss {
    double sum = 0;
    std::int64_t count = 0;
  };

  std::string fingerprint() const;
  void validate_data() const;
  void resume_or_start();
  void save_checkpoint();
  Loss process_batch(torch::Tensor batch, bool training, double teacher_forcing,
                     std::uint64_t stream, Timing& timing);
  Loss process_batch_moe(torch::Tensor& batch, bool training, double teacher_forcing,
                         std::uint64_t stream, Timing& timing);
  void optimiser_step(Timing& timing);
  double validation_loss(int epoch);
  void train_epoch(int epoch);
  TrainOutcome finish(const std::filesystem::path& dir);
  TrainOutcome export_checkpoint();
  void report_reconstruction(Manifest& m);

  const TrainOptions& options_;
  const TrainingData& data_;
  std::ostream& log_;
  Family family_;
  std::shared_ptr<TrainableNetwork> model_;
  FlatParameters flat_;
  // MPNet(MoE) and UGNet(MoE) train through moe_step.h, the autoencoder through
  // autoencoder_step.h, on the flat buffers' memory, on --threads members (parallel_steps.h).
  std::optional<ParallelMoeStep> moe_;
  std::optional<ParallelAutoencoderStep> autoencoder_;
  Checkpoint state_;
  Clock::time_point last_save_ = Clock::now();
  Clock::time_point segment_start_ = Clock::now();  // since state_ times were last updated
  bool resumed_ = false;
  std::filesystem::path checkpoint_path_;
  std::string initial_weights_hash_;  // SHA-256 of options_.initial_weights, if any
};

std::string Run::fingerprint() const {
  std::ostringstream s;
  const Schedule& k = options_.schedule;
  s << network_name(options_.network) << "|" << variant_tag(options_.variant) << "|"
    << hand_name(options_.hand) << "|seed " << options_.seed << "|epochs " << k.epochs << "|batch "
    << k.batch_size << "|lr " << k.learning_rate << " x" << k.learning_rate_decay << "|wd "
    << k.weight_decay << "|ss " << k.scheduled_sampling << " " << k.teacher_forcing_epochs << " "
    << k.autoregressive_from_epoch << "|max batches " << options_.max_batches << "|data "
    << options_.dataset_hash << " " << data_.train.count << "/" << data_.validation.count;
  if (!initial_weights_hash_.empty()) {
    s << "|from " << initial_weights_hash_;
  }
  return s.str();
}

void Run::validate_data() const {
  const int want_columns = family_ == Family::kMpnet   ? kMpnetClipColumns
                           : family_ == Family::kUgnet ? kUgnetClipColumns
                                                       : kMotionColumns;
  const int want_rows = family_ == Family::kMotionAutoencoder ? kSegmentRows : kClipRows;
  for (const ExampleSet* set : {&data_.train, &data_.validation}) {
    if (set->count > 0 && (set->columns != want_columns || set->rows != want_rows)) {
      throw Error("training examples have " + std::to_string(set->rows) + "×" +
                  std::to_string(set->columns) + " values, " +
                  std::string(network_name(options_.network)) + " needs " +
                  std::to_string(want_rows) + "×" + std::to_string(want_columns));
    }
  }
  if (data_.train.count < static_cast<std::size_t>(options_.schedule.batch_size)) {
    throw Error("only " + std::to_string(data_.train.count) +
                " training examples, fewer than one batch of " +
                std::to_string(options_.schedule.batch_size));
  }
}

void Run::resume_or_start() {
  if (options_.export_to.empty()) {
    std::filesystem::create_directories(options_.out_dir);  // an export only reads it
  }
  checkpoint_path_ = options_.out_dir / "checkpoint.safetensors";
  torch::manual_seed(options_.seed);
  model_ = make_network(options_.network);
  model_->train();
  if (!options_.initial_weights.empty()) {
    // Before flattening, which copies the parameters into the flat buffer. A resumed run's
    // checkpoint overwrites them below.
    load_weights(*model_, SafetensorsFile::read(options_.initial_weights));
    initial_weights_hash_ = sha256_file(options_.initial_weights);
  }
  flat_ = flatten(*model_);
  const bool moe = options_.network == Network::kMpnetMoe || options_.network == Network::kUgnetMoe;
  if (moe && !options_.autograd) {
    const MoeShape shape =
        options_.network == Network::kMpnetMoe ? MoeShape::mpnet() : MoeShape::ugnet();
    if (shape.parameter_count() != static_cast<std::size_t>(flat_.numel)) {
      throw Error("the MoE step expects " + std::to_string(shape.parameter_count()) +
                  " parameters, the network has " + std::to_string(flat_.numel));
    }
    moe_.emplace(shape, options_.schedule.batch_size, options_.threads, moe_buffers(*model_, false),
                 moe_buffers(*model_, true));
  }
  if (options_.network == Network::kMotionAutoencoder && !options_.autograd) {
    if (AutoencoderStep::parameter_count() != static_cast<std::size_t>(flat_.numel)) {
      throw Error("the autoencoder step expects " +
                  std::to_string(AutoencoderStep::parameter_count()) +
                  " parameters, the network has " + std::to_string(flat_.numel));
    }
    autoencoder_.emplace(options_.schedule.batch_size, options_.threads,
                         autoencoder_buffers(*model_, false), autoencoder_buffers(*model_, true),
                         span_of(flat_.grads));
  }
  state_.fingerprint = fingerprint();
  if (options_.restart || !std::filesystem::exists(checkpoint_path_)) {
    return;
  }
  Checkpoint saved = read_checkpoint(checkpoint_path_);
  if (saved.fingerprint != state_.fingerprint) {
    throw Error(checkpoint_path_.string() +
                ": checkpoint of a different run (network, seed, schedule or data differ):\n  "
                "saved: " +
                saved.fingerprint + "\n  now:   " + state_.fingerprint +
                "\nUse --restart to discard it, or another --out directory.");
  }
  if (static_cast<std::int64_t>(saved.parameters.size()) != flat_.numel) {
    throw Error(checkpoint_path_.string() + ": tensor 'parameters' has " +
                std::to_string(saved.parameters.size()) + " values, the network has " +
                std::to_string(flat_.numel));
  }
  auto copy_in = [&](const std::vector<float>& from, torch::Tensor& to) {
    std::copy(from.begin(), from.end(), to.data_ptr<float>());
  };
  copy_in(saved.parameters, flat_.values);
  copy_in(saved.exp_avg, flat_.exp_avg);
  copy_in(saved.exp_avg_sq, flat_.exp_avg_sq);
  saved.parameters.clear();
  saved.exp_avg.clear();
  saved.exp_avg_sq.clear();
  state_ = std::move(saved);
  resumed_ = true;
  log_ << "resuming from " << checkpoint_path_.string() << ": epoch " << state_.epoch << ", batch "
       << state_.batch << ", " << state_.history.size() << " epochs done\n";
}

void Run::save_checkpoint() {
  const double elapsed = seconds_since(segment_start_);
  state_.epoch_seconds += elapsed;
  state_.train_seconds += elapsed;
  segment_start_ = Clock::now();
  auto copy_out = [](const torch::Tensor& t) {
    return std::vector<float>(t.data_ptr<float>(), t.data_ptr<float>() + t.numel());
  };
  Checkpoint c = state_;
  c.parameters = copy_out(flat_.values);
  c.exp_avg = copy_out(flat_.exp_avg);
  c.exp_avg_sq = copy_out(flat_.exp_avg_sq);
  write_checkpoint(checkpoint_path_, c);
  last_save_ = Clock::now();
}

void Run::optimiser_step(Timing& timing) {
  const auto t0 = Clock::now();
  ++state_.step;
  const AdamWBuffers flat{span_of(flat_.values), span_of(flat_.grads), span_of(flat_.exp_avg),
                          span_of(flat_.exp_avg_sq)};
  const double lr = options_.schedule.learning_rate_at(state_.epoch);
  // AdamW also zeroes the gradients; the team's adds its members' gradients first.
  if (moe_) {
    moe_->optimiser_step(flat, options_.schedule, lr, state_.step);
  } else if (autoencoder_) {
    autoencoder_->optimiser_step(flat, options_.schedule, lr, state_.step);
  } else {
    adamw_step(flat, options_.schedule, lr, state_.step);
  }
  timing.optimiser += seconds_since(t0);
}

// process_batch for the MoE networks through moe_step.h (parallel_steps.h with --threads): the
// same windows, the same draws for scheduled sampling (the stream's third generator) and the same
// optimiser steps.
Run::Loss Run::process_batch_moe(torch::Tensor& batch, bool training, double teacher_forcing,
                                 std::uint64_t stream, Timing& timing) {
  Loss loss;
  std::mt19937_64 rng(mix(stream, 3));
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const auto count = static_cast<int>(batch.size(0));
  float* clips = batch.data_ptr<float>();
  for (int t = 0; t < kWindowsPerClip; ++t) {
    // UGNet's scheduled sampling, as process_batch: the newest pose row becomes the previous
    // window's prediction, still in the step's output.
    const bool feed_back =
        family_ == Family::kUgnet && t > 0 && uniform(rng) < 1.0 - teacher_forcing;
    loss.sum += moe_->window(clips, static_cast<int>(batch.size(2)), t, count, feed_back, training);
    ++loss.count;
    timing.forward += moe_->forward_seconds();
    timing.backward += moe_->backward_seconds();
    if (training) {
      optimiser_step(timing);
    }
  }
  return loss;
}

// One batch: the 16 windows of each clip in turn (MPNet, UGNet) or one step (autoencoder).
Run::Loss Run::process_batch(torch::Tensor batch, bool training, double teacher_forcing,
                             std::uint64_t stream, Timing& timing) {
  if (moe_) {
    return process_batch_moe(batch, training, teacher_forcing, stream, timing);
  }
  Loss loss;
  if (autoencoder_) {
    loss.sum +=
        autoencoder_->batch(batch.data_ptr<float>(), static_cast<int>(batch.size(0)), training);
    ++loss.count;
    timing.forward += autoencoder_->forward_seconds();
    timing.backward += autoencoder_->backward_seconds();
    if (training) {
      optimiser_step(timing);
    }
    return loss;
  }

  // Dropout (Transformers) draws from the global generator, the diffusion noise from its own:
  // both are seeded from (seed, epoch, batch), so a resumed run draws the same numbers.
  torch::manual_seed(mix(stream, 1));
  torch::Generator generator = at::detail::createCPUGenerator(mix(stream, 2));
  std::mt19937_64 rng(mix(stream, 3));
  std::uniform_real_distribution<double> uniform(0.0, 1.0);

  auto step = [&](const torch::Tensor& prediction, const torch::Tensor& target) {
    const auto t0 = Clock::now();
    const torch::Tensor l = torch::l1_loss(prediction, target);
    loss.sum += l.item<double>();
    ++loss.count;
    if (training) {
      l.backward();
      timing.backward += seconds_since(t0);
      optimiser_step(timing);
    }
  };

  if (family_ == Family::kMotionAutoencoder) {
    const auto t0 = Clock::now();
    const torch::Tensor reconstruction = model_->forward(batch);
    timing.forward += seconds_since(t0);
    step(reconstruction, batch);
    return loss;
  }

  torch::Tensor previous;
  for (int t = 0; t < kWindowsPerClip; ++t) {
    const auto t0 = Clock::now();
    const torch::Tensor rows = batch.slice(1, t, t + kWindowRows);
    if (family_ == Family::kMpnet) {
      const torch::Tensor x = rows.slice(2, 0, kMpnetInputs);
      const torch::Tensor y = batch.select(1, kWindowRows - 1 + t).slice(1, kMpnetInputs);
      const torch::Tensor prediction = model_->forward(x);
      timing.forward += seconds_since(t0);
      step(prediction, y);
      continue;
    }
    // UGNet. Scheduled sampling (train_UGNet.py): from the second window on, with probability
    // 1 − P the newest pose row is the previous window's (detached) prediction. Like the
    // authors, the clip tensor itself is overwritten: later windows never read that row's pose.
    if (t > 0 && uniform(rng) < 1.0 - teacher_forcing) {
      batch.select(1, kWindowRows - 1 + t).slice(1, 0, kPoseColumns).copy_(previous);
    }
    const torch::Tensor x = rows.slice(2, 0, kUgnetInputs);
    const torch::Tensor y = batch.select(1, kWindowRows - 1 + t).slice(1, kUgnetInputs);
    const torch::Tensor prediction = model_->training_prediction(x, y, generator);
    timing.forward += seconds_since(t0);
    step(prediction, y);
    previous = prediction.detach();
  }
  return loss;
}

// Validation on held-out subjects: the same windows without optimiser steps, in eval mode
// (no dropout); UGNet fully autoregressive inside each clip (P = 0, as at runtime); the
// diffusion model with its training objective, noise seeded per batch.
double Run::validation_loss(int epoch) {
  const ExampleSet& set = data_.validation;
  if (set.count == 0) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  torch::NoGradGuard no_grad;
  model_->eval();
  std::vector<std::size_t> order(set.count);
  for (std::size_t i = 0; i < set.count; ++i) {
    order[i] = i;
  }
  Loss total;
  Timing ignored;
  const auto batch_size = static_cast<std::size_t>(options_.schedule.batch_size);
  for (std::size_t first = 0; first < set.count; first += batch_size) {
    const std::size_t n = std::min(batch_size, set.count - first);
    const Loss l = process_batch(gather(set, order, first, n), false, 0.0,
                                 mix(mix(options_.seed, 0xba1), first), ignored);
    total.sum += l.sum;
    total.count += l.count;
  }
  model_->train();
  (void)epoch;
  return total.sum / static_cast<double>(total.count);
}

void Run::train_epoch(int epoch) {
  const std::vector<std::size_t> order = epoch_order(data_.train.count, options_.seed, epoch);
  const auto batch_size = static_cast<std::size_t>(options_.schedule.batch_size);
  auto batches = static_cast<std::int64_t>(data_.train.count / batch_size);  // drop_last
  if (options_.max_batches > 0) {
    batches = std::min(batches, options_.max_batches);
  }
  const double teacher_forcing = options_.schedule.teacher_forcing_at(epoch);
  Timing timing;
  Clock::time_point last_line = Clock::now();
  for (std::int64_t b = state_.batch; b < batches; ++b) {
    const auto t0 = Clock::now();
    torch::Tensor batch =
        gather(data_.train, order, static_cast<std::size_t>(b) * batch_size, batch_size);
    timing.data += seconds_since(t0);
    const Loss l = process_batch(
        std::move(batch), true, teacher_forcing,
        mix(mix(options_.seed, static_cast<std::uint64_t>(epoch)), static_cast<std::uint64_t>(b)),
        timing);
    state_.loss_sum += l.sum;
    state_.loss_count += l.count;
    state_.batch = b + 1;
    const bool by_batches =
        options_.checkpoint_batches > 0 && state_.batch % options_.checkpoint_batches == 0;
    if (by_batches || seconds_since(last_save_) > options_.checkpoint_seconds) {
      save_checkpoint();
    }
    if (seconds_since(last_line) > 30) {
      last_line = Clock::now();
      log_ << "  epoch " << epoch << ": " << state_.batch << "/" << batches << " batches, loss "
           << state_.loss_sum / static_cast<double>(state_.loss_count) << std::endl;
    }
  }
  const double total = timing.data + timing.forward + timing.backward + timing.optimiser;
  if (total > 0) {
    char line[160];
    std::snprintf(line, sizeof line,
                  "  time: forward %.0f%%  backward %.0f%%  optimiser %.0f%%  data %.0f%%  "
                  "(%.2f ms per step)",
                  100 * timing.forward / total, 100 * timing.backward / total,
                  100 * timing.optimiser / total, 100 * timing.data / total,
                  1e3 * total / static_cast<double>(std::max<std::int64_t>(1, state_.loss_count)));
    log_ << line << "\n";
  }
}

// The paper reports its FMD encoder's per-frame reconstruction error on the training subject and
// on the validation subjects (§V); the final weights' figures go to the log and the manifest.
void Run::report_reconstruction(Manifest& m) {
  m.training_reconstruction = reconstruction_error(*model_, data_.train);
  if (data_.validation.count > 0) {
    m.validation_reconstruction = reconstruction_error(*model_, data_.validation);
  }
  char line[200];
  std::snprintf(line, sizeof line, "reconstruction per frame: training %.2f cm, %.2f deg",
                m.training_reconstruction->position_cm, m.training_reconstruction->rotation_deg);
  log_ << line;
  if (m.validation_reconstruction) {
    std::snprintf(line, sizeof line, "; validation %.2f cm, %.2f deg",
                  m.validation_reconstruction->position_cm,
                  m.validation_reconstruction->rotation_deg);
    log_ << line;
  }
  const bool left = options_.hand == Hand::kLeft;
  const nn::PaperReconstruction& paper =
      left ? nn::kPaperReconstructionLeft : nn::kPaperReconstructionRight;
  std::snprintf(line, sizeof line, " (paper, %s hand: %.2f cm, %.2f deg; %.2f cm, %.2f deg)",
                left ? "left" : "right", paper.training_cm, paper.training_deg, paper.validation_cm,
                paper.validation_deg);
  log_ << line << std::endl;
}

// Writes the current weights and their manifest into `dir`: the run's own directory when the
// schedule has ended, another one for --export-to.
TrainOutcome Run::finish(const std::filesystem::path& dir) {
  const std::string stem = weights_stem(options_.network, options_.variant);
  std::filesystem::create_directories(dir);
  TrainOutcome outcome;
  outcome.weights = dir / (stem + ".safetensors");
  outcome.manifest = dir / (stem + ".manifest.json");
  SafetensorsWriter writer = export_weights(*model_);
  writer.set_metadata("network", std::string(network_name(options_.network)));
  writer.set_metadata("variant", std::string(variant_tag(options_.variant)));
  writer.set_metadata("hand", std::string(hand_name(options_.hand)));
  writer.set_metadata("epochs", std::to_string(state_.history.size()));
  writer.set_metadata("seed", std::to_string(options_.seed));
  writer.set_metadata("producer", "deixis-train");
  writer.write(outcome.weights);

  Manifest m;
  m.weights_file = outcome.weights.filename().string();
  m.network = network_name(options_.network);
  m.variant = variant_tag(options_.variant);
  m.hand = hand_name(options_.hand);
  m.command_line = options_.command_line;
  m.seed = options_.seed;
  m.threads = options_.threads;
  m.commit = build_commit();
  m.trained_by = state_.trainers;
  m.dataset_hash = options_.dataset_hash;
  m.dataset_files = options_.dataset_files;
  if (!options_.initial_weights.empty()) {
    m.initial_weights = {options_.initial_weights.string(), initial_weights_hash_};
  }
  m.train_examples = data_.train.count;
  m.validation_examples = data_.validation.count;
  m.parameter_count = static_cast<std::size_t>(flat_.numel);
  m.schedule = options_.schedule;
  m.train_seconds = state_.train_seconds;
  m.history = state_.history;
  m.complete = state_.epoch > options_.schedule.epochs;
  m.stopped_at_epoch = state_.epoch;
  m.stopped_at_batch = state_.batch;
  if (family_ == Family::kMotionAutoencoder) {
    report_reconstruction(m);
  }
  write_manifest(outcome.manifest, m);

  outcome.history = state_.history;
  outcome.train_seconds = state_.train_seconds;
  outcome.resumed = resumed_;
  log_ << "wrote " << outcome.weights.string() << " and " << outcome.manifest.filename().string()
       << " (training time " << format_duration(state_.train_seconds) << ")" << std::endl;
  return outcome;
}

// --export-to: the checkpoint's weights as they are, e.g. to evaluate a run in progress. Nothing
// in the run's directory is written, so the run itself can go on (or be resumed) undisturbed.
TrainOutcome Run::export_checkpoint() {
  if (!resumed_) {
    throw Error(checkpoint_path_.string() +
                ": no checkpoint to export (--export-to exports the "
                "checkpoint of the run in --out; start the run first)");
  }
  log_ << "exporting the checkpoint at epoch " << state_.epoch << ", batch " << state_.batch << " ("
       << state_.history.size() << " of " << options_.schedule.epochs << " epochs done) to "
       << options_.export_to.string() << std::endl;
  return finish(options_.export_to);
}

TrainOutcome Run::execute() {
  validate_data();
  torch::set_num_threads(options_.threads);
  if (!options_.export_to.empty() && options_.restart) {
    throw Error("--export-to exports an existing checkpoint; it cannot be combined with --restart");
  }
  resume_or_start();
  if (!options_.export_to.empty()) {
    return export_checkpoint();
  }
  // This binary, on this machine, trains from here on (unless the schedule has already ended and
  // the run is only re-exported): the manifest will name it among the run's trainers, so that
  // its wall time can be read against the CPUs that spent it.
  const bool trains = state_.epoch <= options_.schedule.epochs;
  const std::string trainer = build_commit() + " on " + machine_description();
  if (trains && (state_.trainers.empty() || state_.trainers.back() != trainer)) {
    state_.trainers.push_back(trainer);
  }
  const Schedule& schedule = options_.schedule;
  const std::size_t batches = data_.train.count / static_cast<std::size_t>(schedule.batch_size);
  const int steps_per_batch = family_ == Family::kMotionAutoencoder ? 1 : kWindowsPerClip;
  log_ << network_name(options_.network) << "(" << variant_tag(options_.variant) << ") "
       << hand_name(options_.hand) << ": " << flat_.numel << " parameters, " << data_.train.count
       << " training and " << data_.validation.count << " validation examples, " << batches
       << " batches of " << schedule.batch_size << " per epoch ("
       << batches * static_cast<std::size_t>(steps_per_batch) << " optimiser steps), "
       << schedule.epochs << " epochs, " << options_.threads << " thread(s)" << std::endl;

  segment_start_ = Clock::now();
  last_save_ = Clock::now();
  while (state_.epoch <= schedule.epochs) {
    const int epoch = state_.epoch;
    train_epoch(epoch);
    EpochReport report;
    report.epoch = epoch;
    report.train_loss =
        state_.loss_sum / static_cast<double>(std::max<std::int64_t>(1, state_.loss_count));
    report.validation_loss = validation_loss(epoch);
    report.learning_rate = schedule.learning_rate_at(epoch);
    report.teacher_forcing = schedule.teacher_forcing_at(epoch);
    const double elapsed = seconds_since(segment_start_);
    state_.train_seconds += elapsed;
    report.seconds = state_.epoch_seconds + elapsed;
    segment_start_ = Clock::now();
    state_.history.push_back(report);
    state_.epoch = epoch + 1;
    state_.batch = 0;
    state_.loss_sum = 0;
    state_.loss_count = 0;
    state_.epoch_seconds = 0;
    save_checkpoint();
    log_ << epoch_line(report, schedule.epochs, eta_seconds(state_.history, schedule.epochs))
         << std::endl;
  }
  return finish(options_.out_dir);
}

}  // namespace

TrainOutcome train(const TrainOptions& options, const TrainingData& data, std::ostream& log) {
  Run run(options, data, log);
  return run.execute();
}

}  // namespace deixis::train
