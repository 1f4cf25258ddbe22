// Weight interpolation (train/interpolate.h): the blend is (1 − α)·a + α·b per tensor, α = 0 and
// 1 give the files themselves, the manifest names both files; files of different networks, a
// non-finite value or α outside [0, 1] are errors naming the file and tensor.

#include "train/interpolate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "error_of.h"
#include "test_support.h"
#include "train/manifest.h"

namespace deixis::train {
namespace {

namespace fs = std::filesystem;

fs::path write_weights(const fs::path& path, float base, std::vector<std::int64_t> shape = {2, 3}) {
  SafetensorsWriter w;
  std::vector<float> values(6);
  for (std::size_t i = 0; i < values.size(); ++i) {
    values[i] = base + static_cast<float>(i);
  }
  w.add_f32("gru.weight", std::move(shape), values);
  w.add_f32("bias", {2}, std::vector<float>{base, -base});
  w.set_metadata("network", "MPNet(MoE)");
  w.write(path);
  return path;
}

const std::vector<std::int64_t> kWeightShape = {2, 3};
const std::vector<std::int64_t> kBiasShape = {2};

using deixis::testing::error_of;

TEST(Interpolate, BlendsTensorByTensor) {
  deixis::testing::ScratchDir dir;
  const fs::path a = write_weights(dir.path() / "a.safetensors", 1.0f);
  const fs::path b = write_weights(dir.path() / "b.safetensors", 3.0f);
  std::ofstream(dir.path() / "b.manifest.json") << R"({"weights": "b.safetensors", "seed": 7})";
  const fs::path out = dir.path() / "set" / "c.safetensors";
  write_interpolation(a, b, 0.25, out);
  const SafetensorsFile c = SafetensorsFile::read(out);
  const std::vector<float> w = c.read_f32("gru.weight", kWeightShape);
  for (std::size_t i = 0; i < w.size(); ++i) {
    const auto k = static_cast<float>(i);
    EXPECT_FLOAT_EQ(w[i], 0.75f * (1.0f + k) + 0.25f * (3.0f + k)) << i;
  }
  EXPECT_EQ(c.read_f32("bias", kBiasShape), (std::vector<float>{1.5f, -1.5f}));
  EXPECT_EQ(c.metadata().at("network"), "MPNet(MoE)");
  EXPECT_EQ(c.metadata().at("interpolation_alpha"), "0.25");

  std::ifstream in(dir.path() / "set" / "c.manifest.json");
  const nlohmann::json m = nlohmann::json::parse(in);
  EXPECT_EQ(m["weights"], "c.safetensors");
  EXPECT_EQ(m["seed"], 7);  // b's manifest carried over
  EXPECT_EQ(m["interpolation"]["alpha"].get<double>(), 0.25);
  EXPECT_EQ(m["interpolation"]["from"]["sha256"], sha256_file(a));
  EXPECT_EQ(m["interpolation"]["to"]["sha256"], sha256_file(b));

  // The ends are the files themselves.
  const SafetensorsFile fa = SafetensorsFile::read(a), fb = SafetensorsFile::read(b);
  for (const double alpha : {0.0, 1.0}) {
    const fs::path end = dir.path() / "end.safetensors";
    interpolate_weights(fa, fb, alpha).write(end);
    EXPECT_EQ(SafetensorsFile::read(end).read_f32("gru.weight", kWeightShape),
              (alpha == 0.0 ? fa : fb).read_f32("gru.weight", kWeightShape));
  }
}

TEST(Interpolate, OtherNetworksNonFiniteValuesAndBadAlphaAreErrors) {
  deixis::testing::ScratchDir dir;
  const SafetensorsFile a = SafetensorsFile::read(write_weights(dir.path() / "a.safetensors", 1));
  const SafetensorsFile other =
      SafetensorsFile::read(write_weights(dir.path() / "other.safetensors", 1, {3, 2}));
  EXPECT_NE(error_of([&] {
              interpolate_weights(a, other, 0.5);
            }).find("other.safetensors: tensor 'gru.weight': expected shape [2, 3], found [3, 2]"),
            std::string::npos);

  SafetensorsWriter fewer;
  fewer.add_f32("bias", {2}, std::vector<float>{1, 2});
  fewer.add_f32("extra", {2}, std::vector<float>{1, 2});
  fewer.write(dir.path() / "fewer.safetensors");
  EXPECT_NE(error_of([&] {
              interpolate_weights(a, SafetensorsFile::read(dir.path() / "fewer.safetensors"), 0.5);
            }).find("fewer.safetensors: tensor 'gru.weight': missing"),
            std::string::npos);

  SafetensorsWriter nan;
  nan.add_f32("gru.weight", {2, 3}, std::vector<float>(6, std::numeric_limits<float>::quiet_NaN()));
  nan.add_f32("bias", {2}, std::vector<float>{1, 2});
  nan.write(dir.path() / "nan.safetensors");
  EXPECT_NE(error_of([&] {
              interpolate_weights(a, SafetensorsFile::read(dir.path() / "nan.safetensors"), 0.5);
            }).find("nan.safetensors: tensor 'gru.weight': element 0 is NaN"),
            std::string::npos);

  for (const double alpha : {-0.1, 1.5, std::nan("")}) {
    EXPECT_NE(error_of([&] { interpolate_weights(a, a, alpha); }).find("alpha must be in [0, 1]"),
              std::string::npos)
        << alpha;
  }
}

}  // namespace
}  // namespace deixis::train
