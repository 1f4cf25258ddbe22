// The libtorch training models are the authors' architectures, and what they export means the
// same thing to the C++ runtime:
//   1. the authors' own checkpoints, loaded into deixis-train's libtorch models, reproduce the
//      authors' PyTorch outputs in ../shared/reference/fixtures
//      (tolerances: docs/conventions.md#parity);
//   2. weights exported from libtorch load in nn::Mpnet / nn::Ugnet / nn::MotionEncoder
//      unchanged and give the same outputs within 1e-5 on windows the weights never saw.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/io/safetensors.h"
#include "gesture/nn/motion_encoder.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "test_support.h"
#include "train/forward.h"

namespace deixis::train {
namespace {

namespace fs = std::filesystem;

float max_abs_difference(std::span<const float> a, std::span<const float> b) {
  EXPECT_EQ(a.size(), b.size());
  float worst = 0;
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i) {
    worst = std::max(worst, std::abs(a[i] - b[i]));
  }
  return worst;
}

struct FixtureCase {
  const char* fixture;  // stem under fixtures/, without the hand
  Network network;
  float tolerance;  // docs/conventions.md#parity
};

class AuthorsCheckpoint : public ::testing::TestWithParam<std::tuple<FixtureCase, const char*>> {};

TEST_P(AuthorsCheckpoint, ReproducesTheAuthorsOutputs) {
  const auto& [c, hand] = GetParam();
  const fs::path fixture_path = testing::reference_dir() / "fixtures" /
                                (std::string(c.fixture) + "_" + hand + ".safetensors");
  const SafetensorsFile fixture = SafetensorsFile::read(fixture_path);
  const SafetensorsFile weights =
      SafetensorsFile::read(testing::reference_dir() / fixture.metadata_value("checkpoint"));
  const std::vector<std::int64_t>& shape = fixture.shape_of("input");
  const std::int64_t k = shape[0];
  const std::vector<float> input = fixture.read_f32("input", shape);

  std::vector<float> noise;
  if (c.network == Network::kUgnetDiffusion) {
    // Per window: row 0 the initial sample, row s + 1 the fixture's noise[s].
    const std::int64_t init_shape[] = {k, 24};
    const std::int64_t noise_shape[] = {29, k, 24};
    const std::vector<float> init = fixture.read_f32("noise_init", init_shape);
    const std::vector<float> steps = fixture.read_f32("noise", noise_shape);
    noise.resize(static_cast<std::size_t>(k) * 30 * 24);
    for (std::int64_t i = 0; i < k; ++i) {
      std::copy_n(init.begin() + i * 24, 24, noise.begin() + i * 30 * 24);
      for (std::int64_t s = 0; s < 29; ++s) {
        std::copy_n(steps.begin() + (s * k + i) * 24, 24, noise.begin() + (i * 30 + s + 1) * 24);
      }
    }
  }
  const ForwardOutputs out = libtorch_forward(c.network, weights, input, k, noise);
  const std::vector<float> expected = fixture.read_f32("output", fixture.shape_of("output"));
  EXPECT_LE(max_abs_difference(out.output, expected), c.tolerance);
  if (!out.preclamp.empty()) {
    const std::vector<float> preclamp =
        fixture.read_f32("output_preclamp", fixture.shape_of("output_preclamp"));
    EXPECT_LE(max_abs_difference(out.preclamp, preclamp), c.tolerance);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Fixtures, AuthorsCheckpoint,
    ::testing::Combine(
        ::testing::Values(FixtureCase{"MPNet_MoE", Network::kMpnetMoe, 5e-5f},
                          FixtureCase{"MPNet_MLP", Network::kMpnetMlp, 5e-5f},
                          FixtureCase{"MPNet_Transformer", Network::kMpnetTransformer, 5e-5f},
                          FixtureCase{"UGNet_MoE", Network::kUgnetMoe, 1e-5f},
                          FixtureCase{"UGNet_MLP", Network::kUgnetMlp, 1e-5f},
                          FixtureCase{"UGNet_Transformer", Network::kUgnetTransformer, 1e-5f},
                          FixtureCase{"UGNet_Diffusion", Network::kUgnetDiffusion, 5e-5f}),
        ::testing::Values("right", "left")),
    [](const auto& test_info) {
      return std::string(std::get<0>(test_info.param).fixture) + "_" + std::get<1>(test_info.param);
    });

// A loaded authors' checkpoint with one value changed must no longer match: the comparison above
// can fail.
TEST(AuthorsCheckpoint, APerturbedCheckpointDoesNotMatch) {
  const SafetensorsFile fixture =
      SafetensorsFile::read(testing::reference_dir() / "fixtures" / "MPNet_MoE_right.safetensors");
  const SafetensorsFile original =
      SafetensorsFile::read(testing::reference_dir() / fixture.metadata_value("checkpoint"));
  SafetensorsWriter writer;
  for (const TensorInfo& t : original.tensors()) {
    std::vector<float> v = original.read_f32(t.name, t.shape);
    if (t.name == "moe_network.w_l3") {
      v[0] += 0.05f;
    }
    writer.add_f32(t.name, t.shape, v);
  }
  const SafetensorsFile perturbed = SafetensorsFile::from_bytes("perturbed", writer.serialize());
  const std::vector<std::int64_t>& shape = fixture.shape_of("input");
  const ForwardOutputs out =
      libtorch_forward(Network::kMpnetMoe, perturbed, fixture.read_f32("input", shape), shape[0]);
  EXPECT_GT(max_abs_difference(out.preclamp, fixture.read_f32("output_preclamp",
                                                              fixture.shape_of("output_preclamp"))),
            1e-3f);
}

// Windows the exported weights never saw: the public fixtures' inputs (docs/conventions.md#parity:
// a mix of plausible and off-manifold windows).
std::vector<float> held_out_windows(const char* fixture, std::int64_t& count) {
  const SafetensorsFile f = SafetensorsFile::read(testing::reference_dir() / "fixtures" / fixture);
  const std::vector<std::int64_t>& shape = f.shape_of("input");
  count = shape[0];
  return f.read_f32("input", shape);
}

class ExportedWeights : public ::testing::TestWithParam<Network> {};

TEST_P(ExportedWeights, GiveTheSameOutputsInTheRuntime) {
  const Network network = GetParam();
  const SafetensorsWriter writer = initial_weights(network, 7);
  const SafetensorsFile file = SafetensorsFile::from_bytes("exported", writer.serialize());
  std::int64_t k = 0;
  if (family_of(network) == Family::kMpnet) {
    const std::vector<float> input = held_out_windows("MPNet_MoE_right.safetensors", k);
    const ForwardOutputs expected = libtorch_forward(network, file, input, k);
    const nn::Mpnet runtime = nn::Mpnet::load(file);
    std::vector<float> got, got_preclamp;
    for (std::int64_t i = 0; i < k; ++i) {
      const nn::MpnetOutput o = runtime.run(
          nn::MpnetWindow(input.data() + i * nn::kMpnetWindowSize, nn::kMpnetWindowSize));
      got.insert(got.end(), o.progression.begin(), o.progression.end());
      got_preclamp.insert(got_preclamp.end(), o.preclamp.begin(), o.preclamp.end());
    }
    EXPECT_LE(max_abs_difference(got, expected.output), 1e-5f);
    EXPECT_LE(max_abs_difference(got_preclamp, expected.preclamp), 1e-5f);
  } else {
    const std::vector<float> input = held_out_windows("UGNet_MoE_right.safetensors", k);
    std::vector<float> noise;
    if (network == Network::kUgnetDiffusion) {
      std::mt19937 rng(3);
      std::normal_distribution<float> normal;
      noise.resize(static_cast<std::size_t>(k) * nn::kDiffusionNoiseSize);
      for (float& v : noise) {
        v = normal(rng);
      }
    }
    const ForwardOutputs expected = libtorch_forward(network, file, input, k, noise);
    const nn::Ugnet runtime = nn::Ugnet::load(file);
    std::vector<float> got;
    for (std::int64_t i = 0; i < k; ++i) {
      const std::span<const float> draws =
          noise.empty()
              ? std::span<const float>()
              : std::span<const float>(noise).subspan(
                    static_cast<std::size_t>(i) * nn::kDiffusionNoiseSize, nn::kDiffusionNoiseSize);
      const nn::PoseVector y = runtime.run(
          nn::UgnetWindow(input.data() + i * nn::kUgnetWindowSize, nn::kUgnetWindowSize), draws);
      got.insert(got.end(), y.begin(), y.end());
    }
    EXPECT_LE(max_abs_difference(got, expected.output), 1e-5f);
  }
}

INSTANTIATE_TEST_SUITE_P(Networks, ExportedWeights,
                         ::testing::Values(Network::kMpnetMoe, Network::kMpnetMlp,
                                           Network::kMpnetTransformer, Network::kUgnetMoe,
                                           Network::kUgnetMlp, Network::kUgnetTransformer,
                                           Network::kUgnetDiffusion),
                         [](const auto& test_info) {
                           std::string name(network_name(test_info.param));
                           std::erase_if(name, [](char ch) { return ch == '(' || ch == ')'; });
                           return name;
                         });

// The FMD autoencoder's encoder half, exported, is the runtime's MotionEncoder.
TEST(ExportedWeights, AutoencoderEncodesLikeTheRuntimeMotionEncoder) {
  const SafetensorsWriter writer = initial_weights(Network::kMotionAutoencoder, 11);
  const SafetensorsFile file = SafetensorsFile::from_bytes("exported", writer.serialize());
  const std::int64_t k = 16;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  std::vector<float> segments(static_cast<std::size_t>(k) * nn::kMotionSegmentSize);
  for (float& v : segments) {
    v = uniform(rng);
  }
  const ForwardOutputs expected = libtorch_forward(Network::kMotionAutoencoder, file, segments, k);
  const nn::MotionEncoder runtime = nn::MotionEncoder::load(file);
  std::vector<float> got;
  for (std::int64_t i = 0; i < k; ++i) {
    const nn::MotionCode code = runtime.run(std::span<const float, nn::kMotionSegmentSize>(
        segments.data() + i * nn::kMotionSegmentSize, nn::kMotionSegmentSize));
    got.insert(got.end(), code.begin(), code.end());
  }
  EXPECT_LE(max_abs_difference(got, expected.output), 1e-5f);
}

}  // namespace
}  // namespace deixis::train
