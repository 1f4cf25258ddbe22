// Three checks per single-network fixture in ../shared/reference/fixtures (right and left; found by
// listing the directory, so new fixtures are picked up):
//   a. the double-precision reference (reference_networks.h) against the authors' float64 PyTorch
//      output, to rounding, and against their float32 outputs and intermediates within the
//      tolerances of docs/conventions.md#parity;
//   b. the fast float32 path (gesture/nn) against the reference on the fixture's windows;
//   c. the same on random windows, in and out of the training distribution. The fixtures hold 64
//      plausible windows per network; this is what guards the fast path everywhere else.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <variant>
#include <vector>

#include "core/io/safetensors.h"
#include "gesture/nn/amnet.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "gesture/parity.h"
#include "reference/reference_networks.h"
#include "test_support.h"

namespace deixis {
namespace {

namespace fs = std::filesystem;
namespace ref = reference;
using ref::Architecture;

// ---- tolerances ---------------------------------------------------------------------------------

struct Tolerance {
  double absolute = 0;
  double relative = 0;  // 0: absolute only
  double allowance(double expected) const {
    return std::max(absolute, relative * std::abs(expected));
  }
};

// Reference (double) against PyTorch float64 on the same float32 weights and inputs: both compute
// the same function in double, so they differ only by rounding order (and libm). Measured max on
// the public fixtures (right, left): MPNet GRU-MoE 9.4e-16, 8.4e-15; MLP 2.0e-15, 1.3e-15;
// Transformer 8.3e-16, 1.1e-15; UGNet MoE 1.3e-15, 1.1e-15; MLP 1.1e-15, 8.9e-16; Transformer
// 1.2e-15, 1.1e-15; Diffusion 3.9e-15, 1.3e-15; AMNet 1.0e-15, 1.6e-15. 1e-13 is 12× the worst:
// room for another libm's last-bit differences, while a float32 step anywhere (≥ 1e-8 here) or any
// change of formula fails.
constexpr Tolerance kReferenceVsFloat64{1e-13};

// A float32 implementation against double: the tolerances of docs/conventions.md#parity (the
// authors' own float32 run is that far from their float64 one).
Tolerance float32_tolerance(Architecture architecture) {
  switch (architecture) {
    case Architecture::kMpnetGruMoe:
    case Architecture::kMpnetMlp:
    case Architecture::kMpnetTransformer:
      return {kMpnetTolerance};
    case Architecture::kUgnetDiffusion:
      return {kDiffusionTolerance};
    case Architecture::kAmnet:
      return {kAmnetTolerance};
    case Architecture::kUgnetMoe:
    case Architecture::kUgnetMlp:
    case Architecture::kUgnetTransformer:
      return {kUgnetTolerance};
  }
  return {};
}

// Out-of-distribution windows (every input uniform in ±10) drive some outputs to |y| ≈ 20-40 (UGNet
// MLP and MoE, MPNet MLP before the clamp), where float32 rounding grows with the magnitudes
// summed: measured up to 7.7e-6 at |y| ≈ 37 (2e-7 relative), 0.77 of the absolute 1e-5 alone. The
// relative term 2e-6 (≈ 17 float32 ulps) scales the allowance with the output; below |y| = 5 the
// absolute tolerance still decides.
Tolerance out_of_distribution_tolerance(Architecture architecture) {
  Tolerance t = float32_tolerance(architecture);
  t.relative = 2e-6;
  return t;
}

// ---- inputs and outputs -------------------------------------------------------------------------

// One network input in float32, as the fast path takes it (converting to double is exact).
struct Sample {
  std::vector<float> window;  // MPNet or UGNet window, or AMNet's local window
  std::vector<float> remote;  // AMNet only
  std::vector<float> noise;   // UGNet Diffusion only: 30 × 24 draws (initial x, then t = 29 … 1)
};

// Outputs of one window by the fixtures' tensor names: "output" (MPNet: clamped),
// "output_preclamp", "omega", "z", "x0_steps" (the 30 denoised steps, 30 × 24).
using Outputs = std::map<std::string, std::vector<double>>;

constexpr int kMpnetColumns = nn::kMpnetFeatures;
constexpr int kUgnetColumns = nn::kUgnetColumns;
constexpr int kAmnetColumns = nn::kAmnetColumns;

bool is_mpnet(Architecture a) {
  return a == Architecture::kMpnetGruMoe || a == Architecture::kMpnetMlp ||
         a == Architecture::kMpnetTransformer;
}

ref::Rows to_rows(const std::vector<float>& values, int columns) {
  ref::Rows rows;
  for (std::size_t first = 0; first < values.size(); first += static_cast<std::size_t>(columns)) {
    ref::Vector row(static_cast<std::size_t>(columns));
    for (std::size_t c = 0; c < row.size(); ++c) {
      row[c] = static_cast<double>(values[first + c]);
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

template <typename Floats>
std::vector<double> to_doubles(const Floats& values) {
  std::vector<double> out;
  for (float v : values) {
    out.push_back(static_cast<double>(v));
  }
  return out;
}

Outputs run_reference(const ref::Weights& weights, Architecture architecture,
                      const Sample& sample) {
  Outputs out;
  if (is_mpnet(architecture)) {
    const ref::Rows window = to_rows(sample.window, kMpnetColumns);
    const ref::MpnetResult r =
        architecture == Architecture::kMpnetGruMoe ? ref::mpnet_gru_moe(weights, window)
        : architecture == Architecture::kMpnetMlp  ? ref::mpnet_mlp(weights, window)
                                                   : ref::mpnet_transformer(weights, window);
    out["output"] = r.progression;
    out["output_preclamp"] = r.preclamp;
    if (architecture == Architecture::kMpnetGruMoe) {
      out["omega"] = r.omega;
      out["z"] = r.z;
    }
    return out;
  }
  if (architecture == Architecture::kAmnet) {
    out["output"] = ref::amnet(weights, to_rows(sample.window, kAmnetColumns),
                               to_rows(sample.remote, kAmnetColumns));
    return out;
  }
  const ref::Rows window = to_rows(sample.window, kUgnetColumns);
  ref::UgnetResult r;
  switch (architecture) {
    case Architecture::kUgnetMoe:
      r = ref::ugnet_moe(weights, window);
      out["omega"] = r.omega;
      break;
    case Architecture::kUgnetMlp:
      r = ref::ugnet_mlp(weights, window);
      break;
    case Architecture::kUgnetTransformer:
      r = ref::ugnet_transformer(weights, window);
      break;
    default:
      r = ref::ugnet_diffusion(weights, window, to_rows(sample.noise, nn::kPoseSize));
      out["x0_steps"] = ref::concat(r.denoised_steps);
      break;
  }
  out["output"] = r.pose;
  return out;
}

using FastNetwork = std::variant<nn::Mpnet, nn::Ugnet, nn::Amnet>;

// The fast path's network for `checkpoint`, checked to be the architecture the reference sees.
FastNetwork load_fast(const fs::path& checkpoint, Architecture architecture) {
  if (is_mpnet(architecture)) {
    nn::Mpnet net = nn::Mpnet::load(checkpoint);
    EXPECT_EQ("MPNet " + std::string(nn::architecture_name(net.architecture())),
              std::string(ref::architecture_name(architecture)));
    return net;
  }
  if (architecture == Architecture::kAmnet) {
    return nn::Amnet::load(checkpoint);
  }
  nn::Ugnet net = nn::Ugnet::load(checkpoint);
  EXPECT_EQ("UGNet " + std::string(nn::architecture_name(net.architecture())),
            std::string(ref::architecture_name(architecture)));
  return net;
}

Outputs run_fast(const FastNetwork& network, const Sample& sample) {
  Outputs out;
  if (const auto* mpnet = std::get_if<nn::Mpnet>(&network)) {
    nn::MpnetTrace trace;
    const nn::MpnetOutput y =
        mpnet->run(nn::MpnetWindow(sample.window.data(), nn::kMpnetWindowSize), &trace);
    out["output"] = to_doubles(y.progression);
    out["output_preclamp"] = to_doubles(y.preclamp);
    if (mpnet->architecture() == nn::MpnetArchitecture::kGruMoe) {
      out["omega"] = to_doubles(trace.omega);
      out["z"] = to_doubles(trace.z);
    }
  } else if (const auto* ugnet = std::get_if<nn::Ugnet>(&network)) {
    nn::UgnetTrace trace;
    out["output"] = to_doubles(ugnet->run(
        nn::UgnetWindow(sample.window.data(), nn::kUgnetWindowSize), sample.noise, &trace));
    if (ugnet->architecture() == nn::UgnetArchitecture::kMoe) {
      out["omega"] = to_doubles(trace.omega);
    }
    if (ugnet->needs_noise()) {
      out["x0_steps"] = to_doubles(trace.denoised_steps);
    }
  } else {
    using Window = std::span<const float, nn::kAmnetWindowSize>;
    out["output"] = to_doubles(
        std::get<nn::Amnet>(network).run(Window(sample.window.data(), nn::kAmnetWindowSize),
                                         Window(sample.remote.data(), nn::kAmnetWindowSize)));
  }
  return out;
}

// ---- comparison ---------------------------------------------------------------------------------

// The worst element of one tensor over all windows compared.
struct Worst {
  double abs_error = 0;
  double ratio = 0;  // |error| / allowance; > 1 fails
  std::string where;
  std::size_t values = 0;
  double largest_expected = 0;  // max |expected|: the scale the errors are relative to
};

class Agreement {
 public:
  void compare(const std::string& tensor, std::size_t window, const std::vector<double>& actual,
               const std::vector<double>& expected, Tolerance tolerance) {
    Worst& worst = worst_[tensor];
    if (actual.size() != expected.size()) {
      ADD_FAILURE() << tensor << " window " << window << ": " << actual.size() << " values against "
                    << expected.size();
      return;
    }
    for (std::size_t i = 0; i < actual.size(); ++i) {
      const double error = std::abs(actual[i] - expected[i]);
      const double ratio = std::isnan(error) ? std::numeric_limits<double>::infinity()
                                             : error / tolerance.allowance(expected[i]);
      worst.values += 1;
      worst.largest_expected = std::max(worst.largest_expected, std::abs(expected[i]));
      if (ratio > worst.ratio || (std::isnan(error) && worst.where.empty())) {
        std::ostringstream where;
        where.precision(17);
        where << "window " << window << " [" << i << "]: " << actual[i] << " vs " << expected[i];
        worst.ratio = ratio;
        worst.where = where.str();
      }
      worst.abs_error = std::max(worst.abs_error, std::isnan(error) ? ratio : error);
    }
  }

  // One EXPECT per tensor, and a line per tensor with the measured maximum.
  void expect_within(const std::string& label, Tolerance tolerance) const {
    for (const auto& [tensor, worst] : worst_) {
      std::cout << "[ measured ] " << label << " " << tensor << ": max |error| " << worst.abs_error
                << " over " << worst.values << " values up to |" << worst.largest_expected
                << "| (allowance " << tolerance.absolute;
      if (tolerance.relative > 0) {
        std::cout << " or " << tolerance.relative << "·|expected|";
      }
      std::cout << ", worst at " << worst.ratio << " of it: " << worst.where << ")\n";
      EXPECT_LE(worst.ratio, 1.0) << label << " " << tensor << ": max |error| " << worst.abs_error
                                  << "; worst " << worst.where;
    }
  }

  bool has(const std::string& tensor) const { return worst_.count(tensor) != 0; }

 private:
  std::map<std::string, Worst> worst_;
};

// ---- fixtures -----------------------------------------------------------------------------------

fs::path fixture_dir() {
  return testing::reference_dir() / "fixtures";
}

std::vector<std::string> single_network_fixtures() {
  std::vector<std::string> names;
  if (fs::is_directory(fixture_dir())) {
    for (const auto& entry : fs::directory_iterator(fixture_dir())) {
      const std::string name = entry.path().stem().string();
      if (entry.path().extension() == ".safetensors" && name.rfind("rollout_", 0) != 0) {
        names.push_back(name);
      }
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<double> read_as_double(const SafetensorsFile& file, const std::string& name) {
  const TensorInfo* info = file.find(name);
  if (info->dtype == DType::kF64) {
    return file.read_f64(name, info->shape);
  }
  return to_doubles(file.read_f32(name, info->shape));
}

struct FixtureCase {
  fs::path checkpoint;
  ref::Weights weights;
  Architecture architecture{};
  std::vector<Sample> samples;
  std::vector<Outputs> expected;  // the fixture's tensors per window ("output_f64", "omega", …)
};

FixtureCase read_fixture(const std::string& name) {
  const SafetensorsFile file = SafetensorsFile::read(fixture_dir() / (name + ".safetensors"));
  FixtureCase fixture;
  fixture.checkpoint = testing::reference_dir() / file.metadata_value("checkpoint");
  fixture.weights = ref::Weights::load(fixture.checkpoint);
  fixture.architecture = ref::architecture_of(fixture.weights);

  const bool amnet = fixture.architecture == Architecture::kAmnet;
  const std::string input_name = amnet ? "local" : "input";
  const std::vector<std::int64_t>& input_shape = file.shape_of(input_name);
  const std::size_t k = static_cast<std::size_t>(input_shape.at(0));
  const std::size_t window_size = static_cast<std::size_t>(input_shape.at(1) * input_shape.at(2));
  const std::vector<float> input = file.read_f32(input_name, input_shape);
  std::vector<float> remote, noise_init, noise;
  if (amnet) {
    remote = file.read_f32("remote", input_shape);
  }
  const bool diffusion = fixture.architecture == Architecture::kUgnetDiffusion;
  if (diffusion) {
    noise_init = file.read_f32("noise_init", file.shape_of("noise_init"));
    noise = file.read_f32("noise", file.shape_of("noise"));  // [29, K, 24]
  }
  constexpr std::size_t kPose = nn::kPoseSize;
  for (std::size_t i = 0; i < k; ++i) {
    Sample sample;
    sample.window.assign(input.begin() + static_cast<std::ptrdiff_t>(i * window_size),
                         input.begin() + static_cast<std::ptrdiff_t>((i + 1) * window_size));
    if (amnet) {
      sample.remote.assign(remote.begin() + static_cast<std::ptrdiff_t>(i * window_size),
                           remote.begin() + static_cast<std::ptrdiff_t>((i + 1) * window_size));
    }
    if (diffusion) {
      // Draw 0: the initial x; draw s + 1: the fixture's noise[s], added after t = 29 − s.
      sample.noise.assign(noise_init.begin() + static_cast<std::ptrdiff_t>(i * kPose),
                          noise_init.begin() + static_cast<std::ptrdiff_t>((i + 1) * kPose));
      for (std::size_t s = 0; s + 1 < nn::kDiffusionSteps; ++s) {
        const auto first = noise.begin() + static_cast<std::ptrdiff_t>((s * k + i) * kPose);
        sample.noise.insert(sample.noise.end(), first, first + kPose);
      }
    }
    fixture.samples.push_back(std::move(sample));
  }

  fixture.expected.resize(k);
  for (const std::string tensor : {"output", "output_f64", "output_preclamp", "omega", "z"}) {
    if (!file.contains(tensor)) {
      continue;
    }
    const std::vector<double> values = read_as_double(file, tensor);  // [K, n]
    const std::size_t n = values.size() / k;
    for (std::size_t i = 0; i < k; ++i) {
      fixture.expected[i][tensor].assign(values.begin() + static_cast<std::ptrdiff_t>(i * n),
                                         values.begin() + static_cast<std::ptrdiff_t>((i + 1) * n));
    }
  }
  if (file.contains("x0_steps")) {
    const std::vector<double> values = read_as_double(file, "x0_steps");  // [30, K, 24]
    for (std::size_t i = 0; i < k; ++i) {
      std::vector<double>& steps = fixture.expected[i]["x0_steps"];
      for (std::size_t s = 0; s < nn::kDiffusionSteps; ++s) {
        const auto first = values.begin() + static_cast<std::ptrdiff_t>((s * k + i) * kPose);
        steps.insert(steps.end(), first, first + kPose);
      }
    }
  }
  return fixture;
}

// A fixture read once per process, with the reference's outputs for its windows: the UGNet
// Transformer and Diffusion references take a while, and tests a and b both need them.
struct LoadedFixture {
  FixtureCase fixture;
  std::vector<Outputs> reference;
};

const LoadedFixture& load_fixture(const std::string& name) {
  static std::map<std::string, LoadedFixture> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    LoadedFixture loaded{read_fixture(name), {}};
    for (const Sample& sample : loaded.fixture.samples) {
      loaded.reference.push_back(
          run_reference(loaded.fixture.weights, loaded.fixture.architecture, sample));
    }
    it = cache.emplace(name, std::move(loaded)).first;
  }
  return it->second;
}

// ---- random windows -----------------------------------------------------------------------------

class RandomWindows {
 public:
  explicit RandomWindows(std::uint32_t seed) : rng_(seed) {}

  float uniform(double lo, double hi) {
    return static_cast<float>(std::uniform_real_distribution<double>(lo, hi)(rng_));
  }

  // A random direction: normalised Gaussian draws.
  void unit_vector(std::vector<float>& row) {
    double x[3], norm = 0;
    for (double& v : x) {
      v = std::normal_distribution<double>(0.0, 1.0)(rng_);
      norm += v * v;
    }
    for (double v : x) {
      row.push_back(static_cast<float>(v / std::sqrt(norm)));
    }
  }

  // The target feature (θH, φH, θR, φR, rR), docs/conventions.md#target-feature ranges.
  void target_feature(std::vector<float>& row) {
    row.push_back(uniform(-1.5, 1.5));
    row.push_back(uniform(0.5, 3.0));
    row.push_back(uniform(-1.5, 1.5));
    row.push_back(uniform(0.5, 3.0));
    row.push_back(uniform(0.0, 1.0));
  }

  // One plausible row of each network's input.
  std::vector<float> row(Architecture architecture) {
    std::vector<float> row;
    if (is_mpnet(architecture)) {  // docs/conventions.md#mpnet-features
      for (int i = 0; i < 5; ++i) {
        row.push_back(uniform(0.0, std::numbers::pi));  // unsigned angles
      }
      row.push_back(uniform(0.0, 1.0) < 0.5f ? 0.0f : 1.0f);  // d
      target_feature(row);
    } else if (architecture == Architecture::kAmnet) {  // docs/conventions.md#amnet
      for (int i = 0; i < 6; ++i) {
        row.push_back(uniform(-std::numbers::pi, std::numbers::pi));  // signed angles
      }
      for (int i = 0; i < 6; ++i) {
        row.push_back(uniform(0.0, std::numbers::pi));  // unsigned angles
      }
      row.push_back(uniform(-1.5, 1.5));  // θ
      row.push_back(uniform(0.5, 3.0));   // φ
      row.push_back(uniform(0.0, 1.0));   // r
      row.push_back(uniform(0.9, 1.1));   // scale
    } else {                              // UGNet, docs/conventions.md#end-effectors
      unit_vector(row);                   // gaze
      unit_vector(row);                   // head forward
      unit_vector(row);                   // head up
      for (int i = 0; i < 3; ++i) {
        row.push_back(uniform(-0.1, 0.1));  // head position (m)
      }
      unit_vector(row);  // hand forward
      unit_vector(row);  // hand up
      for (int i = 0; i < 3; ++i) {
        row.push_back(uniform(-0.6, 0.6));  // hand position (m)
      }
      for (int i = 0; i < 3; ++i) {
        row.push_back(uniform(-0.2, 0.2));  // fingertip (m)
      }
      target_feature(row);
      for (int i = 0; i < 3; ++i) {
        row.push_back(uniform(0.0, 1.0));  // progression
      }
    }
    return row;
  }

  // A window of `rows` rows. Half the windows move smoothly from one random row to another (d
  // switches once), as real windows do; the other half are independent rows, which exercise the
  // GRUs and attention harder.
  std::vector<float> window(Architecture architecture, int rows) {
    std::vector<float> out;
    if (uniform(0.0, 1.0) < 0.5f) {
      const std::vector<float> from = row(architecture);
      const std::vector<float> to = row(architecture);
      for (int r = 0; r < rows; ++r) {
        const float s = static_cast<float>(r) / static_cast<float>(rows - 1);
        for (std::size_t c = 0; c < from.size(); ++c) {
          float v = from[c] + s * (to[c] - from[c]);
          if (is_mpnet(architecture) && c == 5) {
            v = v < 0.5f ? 0.0f : 1.0f;
          }
          out.push_back(v);
        }
      }
    } else {
      for (int r = 0; r < rows; ++r) {
        const std::vector<float> one = row(architecture);
        out.insert(out.end(), one.begin(), one.end());
      }
    }
    return out;
  }

  // Every input uniform in [−10, 10]: far outside anything the networks were trained on.
  std::vector<float> out_of_distribution_window(std::size_t size) {
    std::vector<float> out(size);
    for (float& v : out) {
      v = uniform(-10.0, 10.0);
    }
    return out;
  }

  std::vector<float> gaussian(std::size_t size) {
    std::vector<float> out(size);
    for (float& v : out) {
      v = std::normal_distribution<float>(0.0f, 1.0f)(rng_);
    }
    return out;
  }

  Sample sample(Architecture architecture, bool out_of_distribution) {
    const bool amnet = architecture == Architecture::kAmnet;
    const int rows = amnet ? nn::kAmnetWindowRows : nn::kWindowRows;
    const int columns = is_mpnet(architecture) ? kMpnetColumns
                        : amnet                ? kAmnetColumns
                                               : kUgnetColumns;
    const std::size_t size = static_cast<std::size_t>(rows * columns);
    Sample s;
    s.window = out_of_distribution ? out_of_distribution_window(size) : window(architecture, rows);
    if (amnet) {
      s.remote =
          out_of_distribution ? out_of_distribution_window(size) : window(architecture, rows);
    }
    if (architecture == Architecture::kUgnetDiffusion) {
      s.noise = gaussian(nn::kDiffusionNoiseSize);
    }
    return s;
  }

 private:
  std::mt19937 rng_;
};

// FNV-1a of the fixture name: a fixed, portable seed per test.
std::uint32_t seed_of(const std::string& name) {
  std::uint32_t hash = 2166136261u;
  for (char c : name) {
    hash = (hash ^ static_cast<std::uint8_t>(c)) * 16777619u;
  }
  return hash;
}

// 32 plausible windows per network (half smooth, half independent rows) and 4 out of distribution.
constexpr int kRandomWindows = 32;
constexpr int kOutOfDistributionWindows = 4;

// ---- tests --------------------------------------------------------------------------------------

class ReferenceNetworks : public ::testing::TestWithParam<std::string> {};

// a. The reference is the authors' function: to rounding against PyTorch float64, and within
// float32 tolerance against PyTorch's own float32 outputs and intermediates.
TEST_P(ReferenceNetworks, MatchesPyTorch) {
  const LoadedFixture& loaded = load_fixture(GetParam());
  const FixtureCase& fixture = loaded.fixture;
  ASSERT_FALSE(fixture.samples.empty());
  Agreement float64, float32;
  for (std::size_t i = 0; i < fixture.samples.size(); ++i) {
    const Outputs& ours = loaded.reference[i];
    const Outputs& theirs = fixture.expected[i];
    ASSERT_TRUE(theirs.count("output_f64")) << "every fixture holds output_f64";
    float64.compare("output_f64", i, ours.at("output"), theirs.at("output_f64"),
                    kReferenceVsFloat64);
    for (const auto& [tensor, values] : theirs) {
      if (tensor != "output_f64") {
        float32.compare(tensor, i, ours.at(tensor), values,
                        float32_tolerance(fixture.architecture));
      }
    }
  }
  const std::string name(ref::architecture_name(fixture.architecture));
  float64.expect_within(name + " reference vs PyTorch float64", kReferenceVsFloat64);
  float32.expect_within(name + " reference vs PyTorch float32",
                        float32_tolerance(fixture.architecture));
}

// b. The fast path against the reference on the fixture's windows, every traced tensor included.
TEST_P(ReferenceNetworks, FastPathMatchesReferenceOnFixtureWindows) {
  const LoadedFixture& loaded = load_fixture(GetParam());
  const FixtureCase& fixture = loaded.fixture;
  const FastNetwork fast = load_fast(fixture.checkpoint, fixture.architecture);
  const Tolerance tolerance = float32_tolerance(fixture.architecture);
  Agreement agreement;
  for (std::size_t i = 0; i < fixture.samples.size(); ++i) {
    for (const auto& [tensor, values] : run_fast(fast, fixture.samples[i])) {
      agreement.compare(tensor, i, values, loaded.reference[i].at(tensor), tolerance);
    }
  }
  agreement.expect_within(
      std::string(ref::architecture_name(fixture.architecture)) + " fast vs reference (fixture)",
      tolerance);
  EXPECT_TRUE(agreement.has("output"));
  if (is_mpnet(fixture.architecture)) {
    EXPECT_TRUE(agreement.has("output_preclamp"));
  }
  if (fixture.architecture == Architecture::kMpnetGruMoe) {
    EXPECT_TRUE(agreement.has("omega") && agreement.has("z"));
  }
  if (fixture.architecture == Architecture::kUgnetMoe) {
    EXPECT_TRUE(agreement.has("omega"));
  }
  if (fixture.architecture == Architecture::kUgnetDiffusion) {
    EXPECT_TRUE(agreement.has("x0_steps"));
  }
}

// c. The fast path against the reference on random windows of the fixture's checkpoint.
TEST_P(ReferenceNetworks, FastPathMatchesReferenceOnRandomWindows) {
  const fs::path fixture_path = fixture_dir() / (GetParam() + ".safetensors");
  const fs::path checkpoint =
      testing::reference_dir() / SafetensorsFile::read(fixture_path).metadata_value("checkpoint");
  const ref::Weights weights = ref::Weights::load(checkpoint);
  const Architecture architecture = ref::architecture_of(weights);
  const FastNetwork fast = load_fast(checkpoint, architecture);
  RandomWindows random(seed_of(GetParam()));

  Agreement plausible, out_of_distribution;
  for (int i = 0; i < kRandomWindows; ++i) {
    const Sample sample = random.sample(architecture, false);
    const Outputs reference = run_reference(weights, architecture, sample);
    for (const auto& [tensor, values] : run_fast(fast, sample)) {
      plausible.compare(tensor, static_cast<std::size_t>(i), values, reference.at(tensor),
                        float32_tolerance(architecture));
    }
  }
  for (int i = 0; i < kOutOfDistributionWindows; ++i) {
    const Sample sample = random.sample(architecture, true);
    const Outputs reference = run_reference(weights, architecture, sample);
    for (const auto& [tensor, values] : run_fast(fast, sample)) {
      out_of_distribution.compare(tensor, static_cast<std::size_t>(i), values, reference.at(tensor),
                                  out_of_distribution_tolerance(architecture));
    }
  }
  const std::string name(ref::architecture_name(architecture));
  plausible.expect_within(name + " fast vs reference (random)", float32_tolerance(architecture));
  out_of_distribution.expect_within(name + " fast vs reference (out of distribution)",
                                    out_of_distribution_tolerance(architecture));
}

// Test names are the fixture names, e.g. Fixtures/ReferenceNetworks.MatchesPyTorch/MPNet_MoE_right.
std::string fixture_name(const ::testing::TestParamInfo<std::string>& fixture) {
  return fixture.param;
}

INSTANTIATE_TEST_SUITE_P(Fixtures, ReferenceNetworks,
                         ::testing::ValuesIn(single_network_fixtures()), fixture_name);

TEST(ReferenceNetworksDiscovery, FindsEveryNetworkForBothHands) {
  // 8 networks × right and left; more are welcome (new fixtures are picked up), fewer mean
  // ../shared/reference is missing or incomplete.
  EXPECT_GE(single_network_fixtures().size(), 16u) << "is " << fixture_dir() << " there?";
}

}  // namespace
}  // namespace deixis
