// The FMD encoder against a direct double-precision convolution (PyTorch's Conv1d definition:
// out[o][p] = b[o] + Σ_i Σ_k w[o][i][k] · in[i][p + k]) on random weights.

#include "gesture/nn/motion_encoder.h"

#include <gtest/gtest.h>

#include <random>

#include "core/error.h"
#include "test_support.h"

namespace deixis {
namespace {

struct RandomEncoder {
  std::vector<float> w1, b1, w2, b2;
  explicit RandomEncoder(unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-0.1f, 0.1f);
    const auto fill = [&](std::size_t n) {
      std::vector<float> v(n);
      for (float& x : v) {
        x = u(rng);
      }
      return v;
    };
    w1 = fill(256 * 18 * 15);
    b1 = fill(256);
    w2 = fill(128 * 256 * 16);
    b2 = fill(128);
  }
  SafetensorsFile file() const {
    SafetensorsWriter writer;
    writer.add_f32("conv_encode1.weight", {256, 18, 15}, w1);
    writer.add_f32("conv_encode1.bias", {256}, b1);
    writer.add_f32("conv_encode2.weight", {128, 256, 16}, w2);
    writer.add_f32("conv_encode2.bias", {128}, b2);
    return SafetensorsFile::from_bytes("random-encoder", writer.serialize());
  }
  // Channels-first convolutions in double, as torch.nn.Conv1d defines them.
  std::vector<double> reference(const std::vector<float>& segment) const {
    std::vector<double> hidden(256 * 16);
    for (int o = 0; o < 256; ++o) {
      for (int p = 0; p < 16; ++p) {
        double sum = b1[o];
        for (int i = 0; i < 18; ++i) {
          for (int k = 0; k < 15; ++k) {
            sum += double(w1[(o * 18 + i) * 15 + k]) * double(segment[(p + k) * 18 + i]);
          }
        }
        hidden[o * 16 + p] = std::max(sum, 0.0);
      }
    }
    std::vector<double> code(128);
    for (int o = 0; o < 128; ++o) {
      double sum = b2[o];
      for (int i = 0; i < 256; ++i) {
        for (int k = 0; k < 16; ++k) {
          sum += double(w2[(o * 256 + i) * 16 + k]) * hidden[i * 16 + k];
        }
      }
      code[o] = sum;
    }
    return code;
  }
};

TEST(MotionEncoder, MatchesTheConvolutionDefinition) {
  const RandomEncoder random(17);
  const nn::MotionEncoder encoder = nn::MotionEncoder::load(random.file());
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<float> segment(nn::kMotionSegmentSize);
    for (float& v : segment) {
      v = u(rng);
    }
    const nn::MotionCode code =
        encoder.run(std::span<const float, nn::kMotionSegmentSize>(segment.data(), segment.size()));
    const std::vector<double> expected = random.reference(segment);
    for (int i = 0; i < nn::kMotionCodeSize; ++i) {
      EXPECT_NEAR(code[i], expected[i], 1e-4 * (1.0 + std::abs(expected[i]))) << i;
    }
  }
}

TEST(MotionEncoder, AWrongShapeIsNamed) {
  SafetensorsWriter writer;
  const std::vector<float> w(256 * 18 * 14);
  writer.add_f32("conv_encode1.weight", {256, 18, 14}, w);
  try {
    nn::MotionEncoder::load(SafetensorsFile::from_bytes("enc.safetensors", writer.serialize()));
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("conv_encode1.weight': expected shape [256, 18, 15]"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace deixis
