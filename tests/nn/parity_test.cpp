// Parity of our networks with the authors' PyTorch code: every single-network fixture in
// ../shared/reference/fixtures (right and left) must match within NOTES §10.1's tolerances, and a
// perturbed checkpoint must not.

#include "gesture/parity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "gesture/error.h"
#include "gesture/io/safetensors.h"
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
