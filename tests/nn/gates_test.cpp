// The GRUs' gate functions (gesture/nn/gates.h): the AVX-512 logistic and tanh give, value by
// value, the bits of Eigen's packet operations that the build's own kernel runs, over every float
// of the functions' working range and a sample of all the rest (infinities, NaN, subnormals), in
// buffers of any length, beside values that take Eigen's e^x branch, and in a whole GRU step with
// people in lanes; and the padding is evaluated.
// On a CPU without AVX-512 (or in a build without the kernel) there is one kernel and nothing to
// compare: those tests skip and say so.

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "gesture/nn/gates.h"
#include "gesture/nn/params.h"

namespace deixis::nn {
namespace {

using InPlace = void (*)(ProductKernel, float*, std::size_t) noexcept;

struct Gate {
  const char* name;
  InPlace function;
};

constexpr Gate kGates[] = {{"logistic", logistic_in_place}, {"tanh", tanh_in_place}};

bool same_bits(float a, float b) {
  return std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b) ||
         (std::isnan(a) && std::isnan(b));
}

// The first value whose result differs between the two kernels, as a message; empty when none.
// `build` and `wide` are working memory, reused from call to call.
std::string first_difference(const Gate& gate, const std::vector<float>& x, AlignedFloats& build,
                             AlignedFloats& wide) {
  build.resize(padded_to_packets(x.size()));
  wide.resize(build.size());
  std::copy(x.begin(), x.end(), build.begin());
  std::copy(x.begin(), x.end(), wide.begin());
  gate.function(ProductKernel::kBuild, build.data(), x.size());
  gate.function(ProductKernel::kAvx512, wide.data(), x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!same_bits(build[i], wide[i])) {
      std::ostringstream message;
      message << gate.name << '(' << std::hexfloat << x[i] << ") = " << build[i]
              << " by the build's kernel, " << wide[i] << " by AVX-512 (value " << i << " of "
              << x.size() << ')';
      return message.str();
    }
  }
  return {};
}

std::string first_difference(const Gate& gate, const std::vector<float>& x) {
  AlignedFloats build;
  AlignedFloats wide;
  return first_difference(gate, x, build, wide);
}

bool have_avx512() {
  return product_kernel_available(ProductKernel::kAvx512);
}

TEST(Gates, Avx512GivesTheBuildsBitsForEveryFloatOfTheRange) {
  if (!have_avx512()) {
    GTEST_SKIP() << "one gate kernel here: no AVX-512 on this CPU or in this build";
  }
  // Every float of magnitude 2^-13 to 32, both signs: below, tanh returns its argument and the
  // logistic is 1/2 to the last bit's round-off; above, both are clamped. In chunks of 2^20.
  constexpr std::uint32_t kChunk = 1u << 20;
  const std::uint32_t first = std::bit_cast<std::uint32_t>(0x1p-13f);
  const std::uint32_t last = std::bit_cast<std::uint32_t>(32.0f);
  std::vector<float> x;
  AlignedFloats build;
  AlignedFloats wide;
  for (const std::uint32_t sign : {0u, 0x8000'0000u}) {
    for (std::uint32_t begin = first; begin < last; begin += kChunk) {
      x.clear();
      for (std::uint32_t bits = begin; bits < std::min(begin + kChunk, last); ++bits) {
        x.push_back(std::bit_cast<float>(bits | sign));
      }
      for (const Gate& gate : kGates) {
        const std::string difference = first_difference(gate, x, build, wide);
        ASSERT_TRUE(difference.empty()) << difference;
      }
    }
  }
}

TEST(Gates, Avx512GivesTheBuildsBitsForASampleOfAllFloats) {
  if (!have_avx512()) {
    GTEST_SKIP() << "one gate kernel here: no AVX-512 on this CPU or in this build";
  }
  // Every 997th bit pattern (a prime stride, so every exponent and sign is sampled at many
  // mantissas): subnormals, huge values, infinities and NaN among them.
  std::vector<float> x;
  for (std::uint64_t bits = 0; bits <= 0xffff'ffffu; bits += 997) {
    x.push_back(std::bit_cast<float>(static_cast<std::uint32_t>(bits)));
  }
  for (const float special : {0.0f, -0.0f, INFINITY, -INFINITY, NAN, -9.0f, 15.7243833541870117f,
                              7.99881172180175781f, -7.99881172180175781f, 0.0004f, -0.0004f}) {
    x.push_back(special);
  }
  for (const Gate& gate : kGates) {
    const std::string difference = first_difference(gate, x);
    EXPECT_TRUE(difference.empty()) << difference;
  }
}

TEST(Gates, Avx512GivesTheBuildsBitsInBuffersOfAnyLength) {
  if (!have_avx512()) {
    GTEST_SKIP() << "one gate kernel here: no AVX-512 on this CPU or in this build";
  }
  // Short buffers (a last vector of 8 values), and values below −9 beside others in the same
  // vector: the logistic hands such vectors to Eigen's own packets.
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> pre_activation(-12.0f, 12.0f);
  int below = 0;
  for (std::size_t n = 1; n <= 70; ++n) {
    for (int trial = 0; trial < 20; ++trial) {
      std::vector<float> x(n);
      for (float& v : x) {
        v = pre_activation(rng);
        below += v < -9.0f ? 1 : 0;
      }
      for (const Gate& gate : kGates) {
        const std::string difference = first_difference(gate, x);
        ASSERT_TRUE(difference.empty()) << difference;
      }
    }
  }
  EXPECT_GT(below, 1000);
}

TEST(Gates, Avx512GivesTheBuildsBitsForAGruStepInLanes) {
  if (!have_avx512()) {
    GTEST_SKIP() << "one gate kernel here: no AVX-512 on this CPU or in this build";
  }
  // The GRUs' hidden sizes (9, 24) and more, 16 to 64 people; projections spread so that some
  // r|z sums fall below −9 (Eigen's e^x branch) and some n arguments beyond tanh's clamp.
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> projection(-7.0f, 7.0f);
  std::uniform_real_distribution<float> state(-1.0f, 1.0f);
  for (const std::size_t hidden : {9u, 24u, 72u}) {
    for (const std::size_t lanes : {16u, 32u, 64u}) {
      const std::size_t values = hidden * lanes;
      std::vector<float> gi(3 * values);
      std::vector<float> gh(3 * values);
      std::vector<float> h(values);
      for (int trial = 0; trial < 5; ++trial) {
        for (float& v : gi) {
          v = projection(rng);
        }
        for (float& v : gh) {
          v = projection(rng);
        }
        for (float& v : h) {
          v = state(rng);
        }
        std::vector<float> gh_build = gh;
        std::vector<float> h_build = h;
        std::vector<float> gh_wide = gh;
        std::vector<float> h_wide = h;
        gru_gates_in_lanes(ProductKernel::kBuild, gi.data(), gh_build.data(), h_build.data(),
                           values);
        gru_gates_in_lanes(ProductKernel::kAvx512, gi.data(), gh_wide.data(), h_wide.data(),
                           values);
        for (std::size_t k = 0; k < values; ++k) {
          ASSERT_TRUE(same_bits(h_build[k], h_wide[k]))
              << "hidden " << hidden << ", lanes " << lanes << ", value " << k << ": " << h_build[k]
              << " against " << h_wide[k];
        }
        // The new state moved: the step did something.
        EXPECT_NE(h_build, h);
      }
    }
  }
}

TEST(Gates, ThePaddingIsZeroedAndEvaluated) {
  for (const ProductKernel kernel : {ProductKernel::kBuild, ProductKernel::kAvx512}) {
    if (!product_kernel_available(kernel)) {
      continue;
    }
    const std::size_t n = kGatePacketFloats + 1;
    const std::size_t padded = padded_to_packets(n);
    ASSERT_GT(padded, n);
    AlignedFloats logistic(padded, NAN);
    AlignedFloats tanh(padded, NAN);
    std::fill_n(logistic.begin(), n, 2.0f);
    std::fill_n(tanh.begin(), n, 2.0f);
    logistic_in_place(kernel, logistic.data(), n);
    tanh_in_place(kernel, tanh.data(), n);
    for (std::size_t i = 0; i < padded; ++i) {
      SCOPED_TRACE(i);
      EXPECT_NEAR(logistic[i], i < n ? 1.0f / (1.0f + std::exp(-2.0f)) : 0.5f, 1e-6f);
      EXPECT_NEAR(tanh[i], i < n ? std::tanh(2.0f) : 0.0f, 1e-6f);
    }
  }
}

}  // namespace
}  // namespace deixis::nn
