// The networks' batch path (nn/batch.h) against one window at a time: for every person of a batch
// of 1, 3 and 64, run_batch() gives what run() gives on that person's window, on the authors'
// checkpoints (../shared/reference) and the shipped weights (assets/weights), on the fixtures'
// real windows and on random ones. The requirement is 1e-5; run() and run_batch() share their
// code and nn/batch.h's products give a row the same bits alone or in a batch, so the MoE
// networks agree bit for bit, and that is what is checked (a change that breaks it should be a
// decision, not an accident). Architectures without a batched path go window by window.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "core/io/safetensors.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "test_support.h"

namespace deixis::nn {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kBatchSizes[] = {1, 3, 64};

fs::path authors(const std::string& hand) {
  return testing::reference_dir() / "weights" / hand;
}
fs::path shipped(const std::string& hand) {
  return testing::source_dir() / "assets/weights" / hand;
}

// The 64 windows a fixture of the authors' networks holds ("input" [64, 30, columns]).
std::vector<float> fixture_windows(const std::string& name) {
  const SafetensorsFile file =
      SafetensorsFile::read(testing::reference_dir() / "fixtures" / (name + ".safetensors"));
  return file.read_f32("input", file.shape_of("input"));
}

// `count` windows of `size` values: rows that drift smoothly (like tracking) around random
// levels in [low, high].
std::vector<float> random_windows(std::size_t count, int columns, float low, float high,
                                  unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> level(low, high);
  std::normal_distribution<float> step(0.0f, 0.02f * (high - low));
  std::vector<float> windows(count * kWindowRows * static_cast<std::size_t>(columns));
  for (std::size_t w = 0; w < count; ++w) {
    std::vector<float> row(static_cast<std::size_t>(columns));
    for (float& v : row) {
      v = level(rng);
    }
    for (int r = 0; r < kWindowRows; ++r) {
      for (int c = 0; c < columns; ++c) {
        row[static_cast<std::size_t>(c)] += step(rng);
        windows[(w * kWindowRows + static_cast<std::size_t>(r)) * columns +
                static_cast<std::size_t>(c)] = row[static_cast<std::size_t>(c)];
      }
    }
  }
  return windows;
}

// Random windows that stay plausible: the fixture's real windows, every value moved by Gaussian
// noise (σ = 0.05). Far out of distribution (uniform levels in ±1 everywhere) UGNet's outputs reach
// |y| ≈ 25, where float32's own spacing is 2e-6; their differences, if any, are taken relative.
std::vector<float> perturbed(std::vector<float> windows, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> noise(0.0f, 0.05f);
  for (float& v : windows) {
    v += noise(rng);
  }
  return windows;
}

// The first `count` windows of `pool`, cycling through it when it holds fewer.
std::vector<float> take(const std::vector<float>& pool, std::size_t window_size, std::size_t count,
                        std::size_t start) {
  const std::size_t available = pool.size() / window_size;
  std::vector<float> out;
  out.reserve(count * window_size);
  for (std::size_t i = 0; i < count; ++i) {
    const auto from =
        pool.begin() + static_cast<std::ptrdiff_t>(((start + i) % available) * window_size);
    out.insert(out.end(), from, from + static_cast<std::ptrdiff_t>(window_size));
  }
  return out;
}

// Largest |batch − alone| over every output of every window and batch size.
float mpnet_batch_error(const Mpnet& mpnet, const std::vector<float>& pool) {
  BatchBuffers buffers;
  float worst = 0.0f;
  for (const std::size_t count : kBatchSizes) {
    const std::vector<float> windows = take(pool, kMpnetWindowSize, count, count);
    std::vector<MpnetOutput> batch(count);
    mpnet.run_batch(windows, batch, buffers);
    for (std::size_t i = 0; i < count; ++i) {
      const MpnetOutput alone =
          mpnet.run(MpnetWindow(windows.data() + i * kMpnetWindowSize, kMpnetWindowSize));
      for (int k = 0; k < kProgressionSize; ++k) {
        worst = std::max(worst, std::abs(batch[i].progression[k] - alone.progression[k]));
        worst = std::max(worst, std::abs(batch[i].preclamp[k] - alone.preclamp[k]));
      }
    }
  }
  return worst;
}

// With `relative`, each difference is divided by max(1, |alone|).
float ugnet_batch_error(const Ugnet& ugnet, const std::vector<float>& pool, bool with_noise = false,
                        bool relative = false) {
  BatchBuffers buffers;
  float worst = 0.0f;
  for (const std::size_t count : kBatchSizes) {
    const std::vector<float> windows = take(pool, kUgnetWindowSize, count, 2 * count);
    const std::vector<float> noise =
        with_noise ? random_windows(count, kPoseSize, -2.0f, 2.0f, 7) : std::vector<float>{};
    std::vector<float> batch(count * kPoseSize);
    ugnet.run_batch(windows, noise, batch, buffers);
    for (std::size_t i = 0; i < count; ++i) {
      const PoseVector alone = ugnet.run(
          UgnetWindow(windows.data() + i * kUgnetWindowSize, kUgnetWindowSize),
          with_noise
              ? std::span<const float>(noise).subspan(i * kDiffusionNoiseSize, kDiffusionNoiseSize)
              : std::span<const float>{});
      for (int k = 0; k < kPoseSize; ++k) {
        const float scale = relative ? std::max(1.0f, std::abs(alone[k])) : 1.0f;
        worst = std::max(worst, std::abs(batch[i * kPoseSize + k] - alone[k]) / scale);
      }
    }
  }
  return worst;
}

class MoeBatches : public ::testing::TestWithParam<std::string> {};

TEST_P(MoeBatches, MpnetBatchEqualsOneByOne) {
  const std::string hand = GetParam();
  const std::vector<float> real = fixture_windows("MPNet_MoE_" + hand);
  // Beside perturbed real windows, random levels over the whole range of MPNet's inputs (angles
  // in [0, π], d in {0, 1}, the target feature within about ±3): its outputs stay small.
  const std::vector<float> random = perturbed(real, 10);
  const std::vector<float> far = random_windows(64, kMpnetFeatures, 0.0f, 3.0f, 11);
  for (const fs::path& file : {authors(hand) / "MPNet(MoE)(AC)80.safetensors",
                               authors(hand) / "MPNet(MoE)(DG)80.safetensors",
                               shipped(hand) / "MPNet(MoE)(AC)80.safetensors",
                               shipped(hand) / "MPNet(MoE)(DG)80.safetensors"}) {
    const Mpnet mpnet = Mpnet::load(file);
    ASSERT_EQ(mpnet.architecture(), MpnetArchitecture::kGruMoe);
    const float real_error = mpnet_batch_error(mpnet, real);
    const float random_error = mpnet_batch_error(mpnet, random);
    const float far_error = mpnet_batch_error(mpnet, far);
    std::cout << "[ measured ] " << file.filename() << " " << hand << ": max |batch - alone| "
              << real_error << " (fixture windows), " << random_error << " (random, plausible), "
              << far_error << " (random levels)\n";
    EXPECT_EQ(real_error, 0.0f) << file;
    EXPECT_EQ(random_error, 0.0f) << file;
    EXPECT_EQ(far_error, 0.0f) << file;
  }
}

TEST_P(MoeBatches, UgnetBatchEqualsOneByOne) {
  const std::string hand = GetParam();
  const std::vector<float> real = fixture_windows("UGNet_MoE_" + hand);
  const std::vector<float> random = perturbed(real, 12);
  const std::vector<float> far = random_windows(64, kUgnetColumns, -1.0f, 1.0f, 13);
  for (const fs::path& file : {authors(hand) / "UGNet(MoE)(AC)120.safetensors",
                               authors(hand) / "UGNet(MoE)(DG)120.safetensors",
                               shipped(hand) / "UGNet(MoE)(AC)120.safetensors",
                               shipped(hand) / "UGNet(MoE)(DG)120.safetensors"}) {
    const Ugnet ugnet = Ugnet::load(file);
    ASSERT_EQ(ugnet.architecture(), UgnetArchitecture::kMoe);
    const float real_error = ugnet_batch_error(ugnet, real);
    const float random_error = ugnet_batch_error(ugnet, random);
    const float far_error = ugnet_batch_error(ugnet, far, false, true);
    std::cout << "[ measured ] " << file.filename() << " " << hand << ": max |batch - alone| "
              << real_error << " (fixture windows), " << random_error
              << " (random, plausible); relative " << far_error << " (far out of distribution)\n";
    EXPECT_EQ(real_error, 0.0f) << file;
    EXPECT_EQ(random_error, 0.0f) << file;
    EXPECT_EQ(far_error, 0.0f) << file;
  }
}

INSTANTIATE_TEST_SUITE_P(Hands, MoeBatches, ::testing::Values("right", "left"));

// A batch after a larger one reuses the buffers without stale values leaking in.
TEST(MoeBatch, SmallerBatchAfterLargerIsUnaffected) {
  const Ugnet ugnet = Ugnet::load(authors("right") / "UGNet(MoE)(AC)120.safetensors");
  const std::vector<float> pool = fixture_windows("UGNet_MoE_right");
  BatchBuffers buffers;
  std::vector<float> big(64 * kPoseSize), small(2 * kPoseSize), fresh(2 * kPoseSize);
  ugnet.run_batch(take(pool, kUgnetWindowSize, 64, 5), {}, big, buffers);
  const std::vector<float> two = take(pool, kUgnetWindowSize, 2, 40);
  ugnet.run_batch(two, {}, small, buffers);
  BatchBuffers other;
  ugnet.run_batch(two, {}, fresh, other);
  EXPECT_EQ(small, fresh);
}

TEST(OtherArchitectures, GoWindowByWindowThroughTheBatchApi) {
  const fs::path w = authors("left");
  for (const char* name :
       {"MPNet(MLP)(AC)80.safetensors", "MPNet(Transformer)(AC)80.safetensors"}) {
    const Mpnet mpnet = Mpnet::load(w / name);
    EXPECT_EQ(mpnet_batch_error(mpnet, random_windows(8, kMpnetFeatures, 0.0f, 3.0f, 13)), 0.0f)
        << name;
  }
  for (const char* name :
       {"UGNet(MLP)(AC)120.safetensors", "UGNet(Transformer)(AC)120.safetensors"}) {
    const Ugnet ugnet = Ugnet::load(w / name);
    EXPECT_EQ(ugnet_batch_error(ugnet, random_windows(8, kUgnetColumns, -1.0f, 1.0f, 14)), 0.0f)
        << name;
  }
}

TEST(OtherArchitectures, DiffusionTakesEachPersonsDraws) {
  const Ugnet ugnet = Ugnet::load(authors("right") / "UGNet(Diffusion)(AC)120.safetensors");
  EXPECT_EQ(ugnet_batch_error(ugnet, random_windows(8, kUgnetColumns, -1.0f, 1.0f, 15), true),
            0.0f);
}

// The AVX-512 kernels (chosen at run time where the CPU has them) give the build's kernels' bits
// for every shape the networks use and the awkward ones around them: rows that fill no block or
// several, columns that leave 8- and 1-wide remainders, strided rows.
TEST(Products, Avx512KernelsGiveTheBuildKernelsBits) {
  if (!product_kernel_available(ProductKernel::kAvx512)) {
    GTEST_SKIP() << "no AVX-512 kernels here: they need a build with FMA (not the sanitizer "
                    "builds) and a CPU with AVX-512F; the build's kernels are the only ones";
  }
  std::mt19937 random(21);
  std::uniform_real_distribution<float> value(-2.0f, 2.0f);
  for (const int rows : {1, 2, 5, 7, 8, 9, 13, 64}) {
    for (const int cols : {8, 16, 27, 32, 40, 48, 64, 72, 96, 112}) {
      const int depth = 37;
      const std::size_t lda = depth + 3, ldc = static_cast<std::size_t>(cols) + 5;
      std::vector<float> a(rows * lda), w(static_cast<std::size_t>(depth) * cols);
      std::generate(a.begin(), a.end(), [&] { return value(random); });
      std::generate(w.begin(), w.end(), [&] { return value(random); });
      std::vector<float> build(rows * ldc, -1.0f), wide(rows * ldc, -1.0f);
      multiply_rows(ProductKernel::kBuild, a.data(), lda, w.data(), cols, build.data(), ldc, rows,
                    depth, cols);
      multiply_rows(ProductKernel::kAvx512, a.data(), lda, w.data(), cols, wide.data(), ldc, rows,
                    depth, cols);
      // Bits, not values: -1 in the padding stays, and every product agrees exactly.
      EXPECT_EQ(std::memcmp(build.data(), wide.data(), build.size() * sizeof(float)), 0)
          << rows << " rows × " << cols << " columns";
      EXPECT_NE(build[0], -1.0f);
    }
  }
}

TEST(Batch, SameWeightsTellsHandlesApart) {
  const Mpnet a = Mpnet::load(authors("right") / "MPNet(MoE)(AC)80.safetensors");
  const Mpnet b = Mpnet::load(authors("right") / "MPNet(MoE)(AC)80.safetensors");
  const Mpnet copy = a;  // NOLINT(performance-unnecessary-copy-initialization): the point
  EXPECT_TRUE(a.same_weights(copy));
  EXPECT_FALSE(a.same_weights(b));
}

TEST(Batch, SizesThatDoNotFitAreRefused) {
  const Mpnet mpnet = Mpnet::load(authors("right") / "MPNet(MoE)(AC)80.safetensors");
  BatchBuffers buffers;
  std::vector<float> windows(2 * kMpnetWindowSize + 1);
  std::vector<MpnetOutput> out(2);
  EXPECT_THROW(mpnet.run_batch(windows, out, buffers), std::invalid_argument);
}

}  // namespace
}  // namespace deixis::nn
