#include "gesture/parity.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/io/safetensors.h"
#include "gesture/nn/amnet.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "gesture/translation_loop.h"

namespace deixis {

bool ParityReport::passed() const {
  return !checks.empty() &&
         std::all_of(checks.begin(), checks.end(), [](const ParityCheck& c) { return c.passed(); });
}

namespace {

// Our outputs, one vector per reference tensor name, filled window by window.
struct Outputs {
  std::vector<std::pair<std::string, std::vector<float>>> tensors;
  std::vector<float>& operator[](const std::string& name) {
    for (auto& [n, values] : tensors) {
      if (n == name) {
        return values;
      }
    }
    return tensors.emplace_back(name, std::vector<float>{}).second;
  }
};

// Reads the batch size K from a tensor that must have the shape [K, rest...].
std::int64_t batch_of(const SafetensorsFile& fixture, const std::string& name,
                      std::vector<std::int64_t> rest) {
  const auto& shape = fixture.shape_of(name);
  std::vector<std::int64_t> expected = {shape.empty() ? 0 : shape[0]};
  expected.insert(expected.end(), rest.begin(), rest.end());
  if (shape != expected || shape[0] <= 0) {
    throw Error(fixture.source() + ": tensor '" + name + "': expected shape [K, " +
                shape_string(rest).substr(1) + " with K > 0, found " + shape_string(shape));
  }
  return shape[0];
}

// Compares `ours` with the fixture's `name` (F32 or F64) and its `name`_f64 twin if present.
void compare(const SafetensorsFile& fixture, const std::string& name,
             const std::vector<float>& ours, double tolerance, ParityReport& report) {
  const TensorInfo* info = fixture.find(name);
  if (info == nullptr) {
    return;
  }
  std::vector<double> reference;
  if (info->dtype == DType::kF64) {
    reference = fixture.read_f64(name, info->shape);
  } else {
    const std::vector<float> values = fixture.read_f32(name, info->shape);
    reference.assign(values.begin(), values.end());
  }
  if (reference.size() != ours.size()) {
    throw Error(fixture.source() + ": tensor '" + name + "': holds " +
                std::to_string(reference.size()) + " values, the network produced " +
                std::to_string(ours.size()));
  }
  ParityCheck check{name, 0.0, tolerance, reference.size()};
  for (std::size_t i = 0; i < reference.size(); ++i) {
    const double error = std::abs(static_cast<double>(ours[i]) - reference[i]);
    check.max_abs_error = std::isnan(error) ? std::numeric_limits<double>::infinity()
                                            : std::max(check.max_abs_error, error);
  }
  report.checks.push_back(check);
}

void compare_all(const SafetensorsFile& fixture, Outputs& outputs, double tolerance,
                 ParityReport& report) {
  for (auto& [name, values] : outputs.tensors) {
    compare(fixture, name, values, tolerance, report);
    if (name == "output") {
      compare(fixture, "output_f64", values, tolerance, report);
    }
  }
}

template <typename Array>
void append(std::vector<float>& out, const Array& values) {
  out.insert(out.end(), values.begin(), values.end());
}

void run_mpnet(const SafetensorsFile& fixture, const std::filesystem::path& checkpoint,
               ParityReport& report) {
  const std::int64_t k = batch_of(fixture, "input", {nn::kWindowRows, nn::kMpnetFeatures});
  const std::vector<float> input = fixture.read_f32("input", fixture.shape_of("input"));
  const nn::Mpnet net = nn::Mpnet::load(checkpoint);
  report.network = "MPNet " + std::string(architecture_name(net.architecture()));
  const bool traced = net.architecture() == nn::MpnetArchitecture::kGruMoe;
  Outputs out;
  for (std::int64_t i = 0; i < k; ++i) {
    nn::MpnetTrace trace;
    const nn::MpnetOutput y = net.run(
        nn::MpnetWindow(input.data() + i * nn::kMpnetWindowSize, nn::kMpnetWindowSize), &trace);
    append(out["output"], y.progression);
    append(out["output_preclamp"], y.preclamp);
    if (traced) {
      append(out["omega"], trace.omega);
      append(out["z"], trace.z);
    }
  }
  report.windows = static_cast<int>(k);
  compare_all(fixture, out, kMpnetTolerance, report);
}

void run_ugnet(const SafetensorsFile& fixture, const std::filesystem::path& checkpoint,
               ParityReport& report) {
  const std::int64_t k = batch_of(fixture, "input", {nn::kWindowRows, nn::kUgnetColumns});
  const std::vector<float> input = fixture.read_f32("input", fixture.shape_of("input"));
  const nn::Ugnet net = nn::Ugnet::load(checkpoint);
  report.network = "UGNet " + std::string(architecture_name(net.architecture()));

  std::vector<float> noise_init, noise;
  const bool diffusion = net.needs_noise();
  if (diffusion) {
    const std::int64_t init_shape[] = {k, nn::kPoseSize};
    const std::int64_t noise_shape[] = {nn::kDiffusionSteps - 1, k, nn::kPoseSize};
    noise_init = fixture.read_f32("noise_init", init_shape);
    noise = fixture.read_f32("noise", noise_shape);
  }
  Outputs out;
  std::vector<std::vector<float>> steps(nn::kDiffusionSteps);
  std::vector<float> draws(nn::kDiffusionNoiseSize);
  for (std::int64_t i = 0; i < k; ++i) {
    if (diffusion) {
      // Row 0: the initial sample; row s + 1: the fixture's noise[s] (added after t = 29 − s).
      std::copy_n(noise_init.begin() + i * nn::kPoseSize, nn::kPoseSize, draws.begin());
      for (int s = 0; s + 1 < nn::kDiffusionSteps; ++s) {
        std::copy_n(noise.begin() + (s * k + i) * nn::kPoseSize, nn::kPoseSize,
                    draws.begin() + (s + 1) * nn::kPoseSize);
      }
    }
    nn::UgnetTrace trace;
    const nn::PoseVector y =
        net.run(nn::UgnetWindow(input.data() + i * nn::kUgnetWindowSize, nn::kUgnetWindowSize),
                draws, &trace);
    append(out["output"], y);
    if (net.architecture() == nn::UgnetArchitecture::kMoe) {
      append(out["omega"], trace.omega);
    }
    if (diffusion) {
      for (int s = 0; s < nn::kDiffusionSteps; ++s) {
        steps[s].insert(steps[s].end(), trace.denoised_steps.begin() + s * nn::kPoseSize,
                        trace.denoised_steps.begin() + (s + 1) * nn::kPoseSize);
      }
    }
  }
  if (diffusion) {
    std::vector<float>& x0 = out["x0_steps"];  // fixture layout [30, K, 24]
    for (const auto& step : steps) {
      x0.insert(x0.end(), step.begin(), step.end());
    }
  }
  report.windows = static_cast<int>(k);
  compare_all(fixture, out, diffusion ? kDiffusionTolerance : kUgnetTolerance, report);
}

void run_amnet(const SafetensorsFile& fixture, const std::filesystem::path& checkpoint,
               ParityReport& report) {
  const std::int64_t k = batch_of(fixture, "local", {nn::kAmnetWindowRows, nn::kAmnetColumns});
  const std::int64_t k_remote =
      batch_of(fixture, "remote", {nn::kAmnetWindowRows, nn::kAmnetColumns});
  if (k_remote != k) {
    throw Error(fixture.source() + ": 'local' holds " + std::to_string(k) + " windows, 'remote' " +
                std::to_string(k_remote));
  }
  const std::vector<float> local = fixture.read_f32("local", fixture.shape_of("local"));
  const std::vector<float> remote = fixture.read_f32("remote", fixture.shape_of("remote"));
  const nn::Amnet net = nn::Amnet::load(checkpoint);
  report.network = "AMNet (ISMAR 2023)";
  Outputs out;
  for (std::int64_t i = 0; i < k; ++i) {
    using Window = std::span<const float, nn::kAmnetWindowSize>;
    append(out["output"],
           net.run(Window(local.data() + i * nn::kAmnetWindowSize, nn::kAmnetWindowSize),
                   Window(remote.data() + i * nn::kAmnetWindowSize, nn::kAmnetWindowSize)));
  }
  report.windows = static_cast<int>(k);
  compare_all(fixture, out, kAmnetTolerance, report);
}

// A chained rollout fixture (docs/conventions.md#parity): the translation loop over 120 steps.
// Arrays with 150 rows are padded-frame indexed (rows 0–29 copy the first real frame); step t reads
// rows t…t+29 and writes the avatar's row t+30.
void run_rollout(const SafetensorsFile& fixture, const std::filesystem::path& reference_dir,
                 ParityReport& report) {
  const std::string& checkpoints = fixture.metadata_value("checkpoints");
  const std::size_t plus = checkpoints.find(" + ");
  if (plus == std::string::npos) {
    throw Error(fixture.source() +
                ": __metadata__.checkpoints: expected \"<MPNet> + <UGNet>\", found \"" +
                checkpoints + "\"");
  }
  const nn::Mpnet mpnet = nn::Mpnet::load(reference_dir / checkpoints.substr(0, plus));
  const nn::Ugnet ugnet = nn::Ugnet::load(reference_dir / checkpoints.substr(plus + 3));
  report.checkpoint = checkpoints;
  report.network = "translation loop: MPNet " +
                   std::string(architecture_name(mpnet.architecture())) + " + UGNet " +
                   std::string(architecture_name(ugnet.architecture()));

  const std::int64_t steps = batch_of(fixture, "mpnet_output", {nn::kProgressionSize});
  const std::int64_t rows = steps + nn::kWindowRows;
  const auto read = [&](const char* name, std::vector<std::int64_t> shape) {
    return fixture.read_f32(name, shape);
  };
  const std::vector<float> features = read("user_features", {rows, nn::kMpnetFeatures});
  const std::vector<float> user_pose = read("user_pose", {rows, nn::kPoseSize});
  const std::vector<float> targets = read("avatar_target_feature", {rows, kTargetFeatureSize});
  const std::vector<float> initial = read("avatar_pose_init", {nn::kPoseSize});
  const float scale = read("scale", {1})[0];
  if (!(scale > 0.0f)) {
    throw Error(fixture.source() + ": tensor 'scale': expected a positive size ratio");
  }
  const auto frame = [&](std::int64_t row) {
    TranslationInput in;
    std::copy_n(features.begin() + row * nn::kMpnetFeatures, nn::kMpnetFeatures,
                in.user_features.begin());
    std::copy_n(user_pose.begin() + row * nn::kPoseSize, nn::kPoseSize, in.user_x.begin());
    std::copy_n(targets.begin() + row * kTargetFeatureSize, kTargetFeatureSize,
                in.avatar_target.begin());
    return in;
  };

  TranslationLoop loop(mpnet, ugnet, scale);
  EndEffectors avatar_initial;
  std::copy(initial.begin(), initial.end(), avatar_initial.begin());
  loop.reset(frame(0), avatar_initial);
  Outputs out;
  // The padded first rows of the avatar pose are the initial pose itself.
  for (int r = 0; r < nn::kWindowRows; ++r) {
    append(out["avatar_pose"], avatar_initial);
  }
  for (std::int64_t t = 0; t < steps; ++t) {
    // What the networks read and produced at the authors' step t: our reset (t = 0) or the end
    // of our previous step.
    append(out["mpnet_input"], loop.mpnet_window());
    append(out["ugnet_input"], loop.ugnet_window());
    append(out["mpnet_output"], loop.progression());
    append(out["ugnet_output"], loop.prediction());
    const float* progression_column =
        loop.ugnet_window().data() + nn::kPoseSize + kTargetFeatureSize;
    for (int r = 0; r < nn::kWindowRows; ++r) {
      out["progression_window"].insert(out["progression_window"].end(),
                                       progression_column + r * nn::kUgnetColumns,
                                       progression_column + r * nn::kUgnetColumns + 3);
    }
    const TranslationStep step = loop.step(frame(t + nn::kWindowRows));
    append(out["avatar_pose"], step.avatar_x);
    out["head_blend"].push_back(step.head_weight);
    out["hand_blend"].push_back(step.hand_weight);
  }
  report.windows = static_cast<int>(steps);
  for (auto& [name, values] : out.tensors) {
    const double tolerance = name == "mpnet_output" || name == "progression_window"
                                 ? kMpnetTolerance
                                 : kRolloutTolerance;
    compare(fixture, name, values, tolerance, report);
    if (name == "avatar_pose") {
      compare(fixture, "avatar_pose_f64", values, tolerance, report);
    }
  }
}

}  // namespace

ParityReport check_parity(const std::filesystem::path& fixture_path,
                          const std::filesystem::path& reference_dir) {
  const SafetensorsFile fixture = SafetensorsFile::read(fixture_path);
  ParityReport report;
  report.fixture = fixture_path.string();
  if (fixture.metadata().count("checkpoints") != 0) {
    run_rollout(fixture, reference_dir, report);
    return report;
  }
  const std::filesystem::path checkpoint = reference_dir / fixture.metadata_value("checkpoint");
  report.checkpoint = checkpoint.string();
  if (fixture.contains("local") && fixture.contains("remote")) {
    run_amnet(fixture, checkpoint, report);
  } else if (fixture.contains("input")) {
    const auto& shape = fixture.shape_of("input");
    if (shape.size() == 3 && shape[2] == nn::kMpnetFeatures) {
      run_mpnet(fixture, checkpoint, report);
    } else {
      run_ugnet(fixture, checkpoint, report);
    }
  } else {
    throw Error(fixture.source() +
                ": not a parity fixture: expected an 'input' tensor (MPNet, UGNet) or 'local' and "
                "'remote' (AMNet)");
  }
  if (report.checks.empty()) {
    throw Error(fixture.source() + ": holds no reference output ('output', 'output_f64', ...)");
  }
  return report;
}

}  // namespace deixis
