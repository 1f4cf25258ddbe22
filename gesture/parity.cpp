#include "gesture/parity.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gesture/error.h"
#include "gesture/io/safetensors.h"
#include "gesture/nn/amnet.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"

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

}  // namespace

ParityReport check_parity(const std::filesystem::path& fixture_path,
                          const std::filesystem::path& reference_dir) {
  const SafetensorsFile fixture = SafetensorsFile::read(fixture_path);
  ParityReport report;
  report.fixture = fixture_path.string();
  if (fixture.metadata().count("checkpoints") != 0) {
    throw Error(fixture.source() +
                ": a chained rollout fixture (MPNet → blend → UGNet); it is checked by the "
                "translator's parity (`deixis parity` supports single-network fixtures)");
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
