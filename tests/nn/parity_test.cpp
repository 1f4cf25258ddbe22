// Parity of our networks with the authors' PyTorch code: every single-network fixture in
// ../shared/reference/fixtures (right and left) must match within the tolerances of
// docs/conventions.md#parity, and a perturbed checkpoint must not.

#include "gesture/parity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <random>
#include <stdexcept>

#include "core/error.h"
#include "core/io/safetensors.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "test_support.h"

namespace deixis {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> single_network_fixtures() {
  std::vector<std::string> names;
  const fs::path dir = testing::reference_dir() / "fixtures";
  if (fs::is_directory(dir)) {
    for (const auto& entry : fs::directory_iterator(dir)) {
      const std::string name = entry.path().filename().string();
      if (entry.path().extension() == ".safetensors" && name.rfind("rollout_", 0) != 0) {
        names.push_back(entry.path().stem().string());
      }
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

class FixtureParity : public ::testing::TestWithParam<std::string> {};

TEST_P(FixtureParity, MatchesTheAuthorsWithinTolerance) {
  const fs::path fixture = testing::reference_dir() / "fixtures" / (GetParam() + ".safetensors");
  const ParityReport report = check_parity(fixture, testing::reference_dir());
  EXPECT_GT(report.windows, 0);
  for (const ParityCheck& check : report.checks) {
    EXPECT_TRUE(check.passed()) << report.network << ": " << check.tensor << " max |error| "
                                << check.max_abs_error << " > " << check.tolerance;
  }
  // Every fixture holds a float32 and a float64 output, and both are compared.
  const auto has = [&](const std::string& tensor) {
    return std::any_of(report.checks.begin(), report.checks.end(),
                       [&](const ParityCheck& c) { return c.tensor == tensor; });
  };
  EXPECT_TRUE(has("output"));
  EXPECT_TRUE(has("output_f64"));
  if (GetParam().rfind("MPNet", 0) == 0) {
    EXPECT_TRUE(has("output_preclamp"));
  }
  if (GetParam().rfind("MPNet_MoE", 0) == 0) {
    EXPECT_TRUE(has("omega"));
    EXPECT_TRUE(has("z"));
  }
  if (GetParam().rfind("UGNet_Diffusion", 0) == 0) {
    EXPECT_TRUE(has("x0_steps"));
  }
}

INSTANTIATE_TEST_SUITE_P(AuthorsFixtures, FixtureParity,
                         ::testing::ValuesIn(single_network_fixtures()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

TEST(FixtureDiscovery, FindsAllSixteenPublicFixtures) {
  EXPECT_EQ(single_network_fixtures().size(), 16u) << "is ../shared/reference there?";
}

// Copies a checkpoint with one weight nudged by `delta`.
fs::path perturbed_copy(const fs::path& checkpoint, const std::string& tensor, float delta,
                        const fs::path& dir) {
  const SafetensorsFile file = SafetensorsFile::read(checkpoint);
  SafetensorsWriter writer;
  for (const TensorInfo& t : file.tensors()) {
    std::vector<float> values = file.read_f32(t.name, t.shape);
    if (t.name == tensor) {
      values[0] += delta;
    }
    writer.add_f32(t.name, t.shape, values);
  }
  const fs::path out =
      dir / "weights" / checkpoint.parent_path().filename() / checkpoint.filename();
  fs::create_directories(out.parent_path());
  writer.write(out);
  return out;
}

TEST(FixtureParity, DetectsAPerturbedWeight) {
  // The same fixture against a checkpoint whose first recurrent-GRU weight moved by 1e-2 must fail:
  // parity is a test that can fail.
  testing::ScratchDir scratch;
  const fs::path reference = testing::reference_dir();
  perturbed_copy(reference / "weights/right/MPNet(MoE)(AC)80.safetensors", "gru.weight_ih_l0",
                 1e-2f, scratch.path());
  const ParityReport report =
      check_parity(reference / "fixtures/MPNet_MoE_right.safetensors", scratch.path());
  EXPECT_FALSE(report.passed());
}

TEST(FixtureParity, RejectsAFileThatIsNotAFixture) {
  testing::ScratchDir scratch;
  SafetensorsWriter writer;
  const float values[] = {1, 2, 3};
  writer.add_f32("something", {3}, values);
  writer.set_metadata("checkpoint", "weights/right/MPNet(MoE)(AC)80.safetensors");
  writer.write(scratch.path() / "odd.safetensors");
  try {
    check_parity(scratch.path() / "odd.safetensors", testing::reference_dir());
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("odd.safetensors: not a parity fixture"),
              std::string::npos)
        << e.what();
  }
}

TEST(NetworkLoading, AUgnetCheckpointIsNotAnMpnet) {
  const fs::path ugnet = testing::reference_dir() / "weights/right/UGNet(MoE)(AC)120.safetensors";
  try {
    nn::Mpnet::load(ugnet);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("not an MPNet checkpoint"), std::string::npos) << e.what();
  }
  const fs::path mpnet = testing::reference_dir() / "weights/right/MPNet(MoE)(AC)80.safetensors";
  EXPECT_THROW(nn::Ugnet::load(mpnet), Error);
}

TEST(NetworkLoading, RecognisesEveryArchitecture) {
  const fs::path w = testing::reference_dir() / "weights/left";
  EXPECT_EQ(nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors").architecture(),
            nn::MpnetArchitecture::kGruMoe);
  EXPECT_EQ(nn::Mpnet::load(w / "MPNet(MoE)(DG)80.safetensors").architecture(),
            nn::MpnetArchitecture::kGruMoe);
  EXPECT_EQ(nn::Mpnet::load(w / "MPNet(MLP)(AC)80.safetensors").architecture(),
            nn::MpnetArchitecture::kMlp);
  EXPECT_EQ(nn::Mpnet::load(w / "MPNet(Transformer)(AC)80.safetensors").architecture(),
            nn::MpnetArchitecture::kTransformer);
  EXPECT_EQ(nn::Ugnet::load(w / "UGNet(MoE)(AC)120.safetensors").architecture(),
            nn::UgnetArchitecture::kMoe);
  EXPECT_EQ(nn::Ugnet::load(w / "UGNet(MoE)(DG)120.safetensors").architecture(),
            nn::UgnetArchitecture::kMoe);
  EXPECT_EQ(nn::Ugnet::load(w / "UGNet(MLP)(AC)120.safetensors").architecture(),
            nn::UgnetArchitecture::kMlp);
  EXPECT_EQ(nn::Ugnet::load(w / "UGNet(Transformer)(AC)120.safetensors").architecture(),
            nn::UgnetArchitecture::kTransformer);
  EXPECT_EQ(nn::Ugnet::load(w / "UGNet(Diffusion)(AC)120.safetensors").architecture(),
            nn::UgnetArchitecture::kDiffusion);
}

// Ugnet::run_batch is run() on each window: the diffusion variant's batched products over 70
// windows (a chunk of 64 and a partial one), each with its own draws, and the others' loop.
TEST(UgnetBatch, EqualsRunOnEachWindow) {
  constexpr std::size_t kCount = 70;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  std::normal_distribution<float> draw(0.0f, 1.0f);
  std::vector<float> windows(kCount * nn::kUgnetWindowSize),
      noise(kCount * nn::kDiffusionNoiseSize);
  std::ranges::generate(windows, [&] { return value(rng); });
  std::ranges::generate(noise, [&] { return draw(rng); });
  const fs::path w = testing::reference_dir() / "weights/right";
  for (const char* name : {"UGNet(MoE)(AC)120", "UGNet(MLP)(AC)120", "UGNet(Transformer)(AC)120",
                           "UGNet(Diffusion)(AC)120"}) {
    const nn::Ugnet ugnet = nn::Ugnet::load(w / (std::string(name) + ".safetensors"));
    for (const bool with_noise : {true, false}) {
      std::vector<float> out(kCount * nn::kPoseSize, std::nanf(""));
      ugnet.run_batch(windows,
                      with_noise ? std::span<const float>(noise) : std::span<const float>{}, out);
      float worst = 0.0f;
      for (std::size_t i = 0; i < kCount; ++i) {
        const nn::PoseVector one =
            ugnet.run(nn::UgnetWindow(std::span<const float>(windows).subspan(
                          i * nn::kUgnetWindowSize, nn::kUgnetWindowSize)),
                      with_noise ? std::span<const float>(noise).subspan(
                                       i * nn::kDiffusionNoiseSize, nn::kDiffusionNoiseSize)
                                 : std::span<const float>{});
        for (int k = 0; k < nn::kPoseSize; ++k) {
          const float batched = out[i * nn::kPoseSize + k];
          worst = std::isfinite(batched) ? std::max(worst, std::abs(batched - one[k])) : INFINITY;
        }
      }
      std::printf("[ measured ] %s run_batch vs run (%s draws): max |error| %.2g\n", name,
                  with_noise ? "with" : "without", static_cast<double>(worst));
      EXPECT_LT(worst, 1e-5f) << name;
    }
  }
}

TEST(UgnetBatch, SizesThatDoNotFitTogetherAreRefused) {
  const nn::Ugnet ugnet = nn::Ugnet::load(testing::reference_dir() /
                                          "weights/left/UGNet(Diffusion)(AC)120.safetensors");
  std::vector<float> windows(2 * nn::kUgnetWindowSize), noise(nn::kDiffusionNoiseSize);
  std::vector<float> out(2 * nn::kPoseSize), odd(2 * nn::kPoseSize + 1);
  EXPECT_THROW(ugnet.run_batch(windows, noise, out), std::invalid_argument);  // draws for one
  EXPECT_THROW(ugnet.run_batch(windows, {}, odd), std::invalid_argument);     // not whole poses
  EXPECT_THROW(
      ugnet.run_batch(std::span<const float>(windows).first(nn::kUgnetWindowSize), {}, out),
      std::invalid_argument);  // one window for two poses
  EXPECT_NO_THROW(ugnet.run_batch(windows, {}, out));
}

TEST(NetworkLoading, AMissingTensorIsNamed) {
  testing::ScratchDir scratch;
  const SafetensorsFile file = SafetensorsFile::read(testing::reference_dir() /
                                                     "weights/right/MPNet(MoE)(AC)80.safetensors");
  SafetensorsWriter writer;
  for (const TensorInfo& t : file.tensors()) {
    if (t.name != "moe_network.b_l2") {
      writer.add_f32(t.name, t.shape, file.read_f32(t.name, t.shape));
    }
  }
  writer.write(scratch.path() / "broken.safetensors");
  try {
    nn::Mpnet::load(scratch.path() / "broken.safetensors");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("broken.safetensors: tensor 'moe_network.b_l2': missing"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace deixis
