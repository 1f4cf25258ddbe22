// The networks' batch path (nn/batch.h) against one window at a time: for every person of a batch
// of 1, 3, 17 and 64, run_batch() gives what run() gives on that person's window, on the authors'
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
#include "gesture/nn/gru.h"
#include "gesture/nn/lanewise_math.h"
#include "gesture/nn/mpnet.h"
#include "gesture/nn/ugnet.h"
#include "test_support.h"

namespace deixis::nn {
namespace {

namespace fs = std::filesystem;

// 3 runs the GRUs with people as rows, 64 with people in lanes, 17 both ways (a group of sixteen
// in lanes, one person as rows; nn/batch.h, people_in_lanes).
constexpr std::size_t kBatchSizes[] = {1, 3, 17, 64};

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

// A batch after a larger one reuses the buffers without stale values leaking in, whether it
// runs as rows (2) or partly in fewer lanes (19).
TEST(MoeBatch, SmallerBatchAfterLargerIsUnaffected) {
  const Ugnet ugnet = Ugnet::load(authors("right") / "UGNet(MoE)(AC)120.safetensors");
  const Mpnet mpnet = Mpnet::load(authors("right") / "MPNet(MoE)(AC)80.safetensors");
  const std::vector<float> pool = fixture_windows("UGNet_MoE_right");
  const std::vector<float> mpnet_pool = fixture_windows("MPNet_MoE_right");
  for (const std::size_t count : {std::size_t{2}, std::size_t{19}}) {
    BatchBuffers buffers;
    std::vector<float> big(64 * kPoseSize), small(count * kPoseSize), fresh(count * kPoseSize);
    ugnet.run_batch(take(pool, kUgnetWindowSize, 64, 5), {}, big, buffers);
    const std::vector<float> few = take(pool, kUgnetWindowSize, count, 40);
    ugnet.run_batch(few, {}, small, buffers);
    BatchBuffers other;
    ugnet.run_batch(few, {}, fresh, other);
    EXPECT_EQ(small, fresh) << count;

    std::vector<MpnetOutput> many(64), after(count), first(count);
    mpnet.run_batch(take(mpnet_pool, kMpnetWindowSize, 64, 5), many, buffers);
    const std::vector<float> few_windows = take(mpnet_pool, kMpnetWindowSize, count, 40);
    mpnet.run_batch(few_windows, after, buffers);
    BatchBuffers clean;
    mpnet.run_batch(few_windows, first, clean);
    for (std::size_t i = 0; i < count; ++i) {
      EXPECT_EQ(after[i].preclamp, first[i].preclamp) << count << " windows, window " << i;
    }
  }
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

// Inputs of a product c = a·w with strided rows: a is rows × depth with a row every depth + 3
// floats, w is depth × cols, values uniform in [−2, 2); c's rows are cols + 5 apart, so that a test
// can see what was written past the columns.
struct ProductInputs {
  std::size_t lda, ldc;
  std::vector<float> a, w;
};

ProductInputs random_product_inputs(int rows, int depth, int cols, std::mt19937& random) {
  std::uniform_real_distribution<float> value(-2.0f, 2.0f);
  ProductInputs in{static_cast<std::size_t>(depth) + 3, static_cast<std::size_t>(cols) + 5, {}, {}};
  in.a.resize(rows * in.lda);
  in.w.resize(static_cast<std::size_t>(depth) * cols);
  std::generate(in.a.begin(), in.a.end(), [&] { return value(random); });
  std::generate(in.w.begin(), in.w.end(), [&] { return value(random); });
  return in;
}

// Both kernels give, for every row and column, the bits of one fused multiply-add chain over the
// depth in order (what a person alone computes, one value at a time): rows that fill no block of
// six or twelve or several, columns that leave remainders of 8 and of 1 to 7 (masked vectors),
// strided rows; and they write nothing past the columns.
TEST(Products, KernelsGiveOneChainPerValue) {
  std::mt19937 random(20);
  for (const ProductKernel kernel : {ProductKernel::kBuild, ProductKernel::kAvx512}) {
    for (const int rows : {1, 2, 5, 6, 7, 11, 12, 13, 25, 64}) {
      for (const int cols : {1, 3, 7, 8, 12, 24, 27, 31, 56, 108}) {
        const int depth = 29;
        const auto [lda, ldc, a, w] = random_product_inputs(rows, depth, cols, random);
        std::vector<float> c(rows * ldc, -1.0f);
        multiply_rows(kernel, a.data(), lda, w.data(), cols, c.data(), ldc, rows, depth, cols);
        int differing = 0, written_past = 0;
        for (int r = 0; r < rows; ++r) {
          for (int j = 0; j < cols; ++j) {
            float chain = 0.0f;
            for (int i = 0; i < depth; ++i) {
              chain = lanewise::multiply_add(a[r * lda + i],
                                             w[static_cast<std::size_t>(i) * cols + j], chain);
            }
            differing += std::memcmp(&c[r * ldc + j], &chain, sizeof(float)) != 0;
          }
          for (std::size_t j = static_cast<std::size_t>(cols); j < ldc; ++j) {
            written_past += c[r * ldc + j] != -1.0f;
          }
        }
        EXPECT_EQ(differing, 0) << rows << " rows × " << cols << " columns, kernel "
                                << static_cast<int>(kernel);
        EXPECT_EQ(written_past, 0) << rows << " rows × " << cols << " columns";
      }
    }
  }
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
  for (const int rows : {1, 2, 5, 7, 8, 9, 13, 64}) {
    for (const int cols : {8, 16, 27, 32, 40, 48, 64, 72, 96, 112}) {
      const int depth = 37;
      const auto [lda, ldc, a, w] = random_product_inputs(rows, depth, cols, random);
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

// People in lanes (multiply_lanes) give the bits of people as rows (multiply_rows), with either
// kernel, with and without the bias added at the end: every shape the GRUs use (27 and 72 gates;
// depths 5, 8, 9, 11, 24; one step or a whole window of lanes) and awkward ones.
TEST(Products, LanesGiveTheRowsBits) {
  std::mt19937 random(22);
  std::uniform_real_distribution<float> value(-2.0f, 2.0f);
  for (const ProductKernel kernel : {ProductKernel::kBuild, ProductKernel::kAvx512}) {
    for (const int outputs : {1, 5, 6, 7, 27, 72}) {
      for (const int depth : {1, 5, 8, 9, 11, 24, 37}) {
        for (const int lanes : {16, 32, 48, 64, 80, 480}) {
          const std::size_t ldw = static_cast<std::size_t>(depth) + 1;
          const std::size_t ldx = static_cast<std::size_t>(lanes) + 16;
          std::vector<float> w(static_cast<std::size_t>(outputs) * ldw);
          std::vector<float> x(static_cast<std::size_t>(depth) * ldx);
          std::vector<float> bias(static_cast<std::size_t>(outputs));
          for (std::vector<float>* v : {&w, &x, &bias}) {
            std::generate(v->begin(), v->end(), [&] { return value(random); });
          }
          // The same product with people as rows: a = xᵀ (lanes × depth), wᵀ (depth × outputs).
          std::vector<float> a(static_cast<std::size_t>(lanes) * depth);
          std::vector<float> wt(static_cast<std::size_t>(depth) * outputs);
          for (int i = 0; i < depth; ++i) {
            for (int p = 0; p < lanes; ++p) {
              a[static_cast<std::size_t>(p) * depth + i] = x[i * ldx + p];
            }
            for (int j = 0; j < outputs; ++j) {
              wt[static_cast<std::size_t>(i) * outputs + j] = w[j * ldw + i];
            }
          }
          std::vector<float> rows(static_cast<std::size_t>(lanes) * outputs);
          multiply_rows(kernel, a.data(), depth, wt.data(), outputs, rows.data(), outputs, lanes,
                        depth, outputs);
          const std::size_t ldc = static_cast<std::size_t>(lanes) + 3;
          std::vector<float> plain(outputs * ldc, -1.0f), biased(outputs * ldc, -1.0f);
          multiply_lanes(kernel, w.data(), ldw, x.data(), ldx, plain.data(), ldc, outputs, depth,
                         lanes);
          multiply_lanes(kernel, w.data(), ldw, x.data(), ldx, biased.data(), ldc, outputs, depth,
                         lanes, bias.data());
          int differing = 0;
          for (int j = 0; j < outputs; ++j) {
            for (int p = 0; p < lanes; ++p) {
              const float row = rows[static_cast<std::size_t>(p) * outputs + j];
              const float with_bias = row + bias[static_cast<std::size_t>(j)];
              differing += std::memcmp(&plain[j * ldc + p], &row, sizeof(float)) != 0;
              differing += std::memcmp(&biased[j * ldc + p], &with_bias, sizeof(float)) != 0;
            }
            // Past the lanes nothing is written.
            EXPECT_EQ(plain[j * ldc + static_cast<std::size_t>(lanes)], -1.0f);
          }
          EXPECT_EQ(differing, 0) << outputs << " outputs, depth " << depth << ", " << lanes
                                  << " lanes, kernel " << static_cast<int>(kernel);
        }
      }
    }
  }
}

// Random weights for a GRU layer (what load() would fill), both layouts of them.
template <int In, int Hidden>
GruLayer<In, Hidden> random_gru(unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> value(-0.6f, 0.6f);
  GruLayer<In, Hidden> layer;
  for (std::span<float> v : {layer.weight_ih.storage(), layer.weight_hh.storage(),
                             layer.bias_ih.storage(), layer.bias_hh.storage()}) {
    std::generate(v.begin(), v.end(), [&] { return value(random); });
  }
  transpose_into(layer.weight_ih, layer.weight_ih_by_column);
  transpose_into(layer.weight_hh, layer.weight_hh_by_column);
  return layer;
}

// A GRU stepped with people in lanes keeps every person's state bit for bit as stepped with
// people as rows, over a whole window, inputs large enough to reach the gates' saturated ends.
template <int In, int Hidden>
void expect_lanes_step_like_rows(unsigned seed) {
  const GruLayer<In, Hidden> layer = random_gru<In, Hidden>(seed);
  // 21 people in 32 lanes: the lanes past them are computed too, and must not disturb them.
  constexpr int kPeople = 21, kLanes = 32, kGates = 3 * Hidden;
  std::mt19937 random(seed + 1);
  std::uniform_real_distribution<float> value(-12.0f, 12.0f);
  AlignedFloats h_rows(kPeople * Hidden, 0.0f), h_lanes(Hidden * kLanes, 0.0f);
  AlignedFloats gi_rows(kPeople * kGates), gh_rows(kPeople * kGates);
  AlignedFloats work(decltype(layer)::gate_work_floats(kPeople));
  AlignedFloats x_rows(kPeople * In), x_lanes(In * kLanes, 0.0f);
  AlignedFloats gi_lanes(kGates * kLanes), gh_lanes(kGates * kLanes);
  for (int t = 0; t < kWindowRows; ++t) {
    std::generate(x_rows.begin(), x_rows.end(), [&] { return value(random); });
    for (int p = 0; p < kPeople; ++p) {
      for (int i = 0; i < In; ++i) {
        x_lanes[static_cast<std::size_t>(i) * kLanes + p] = x_rows[p * In + i];
      }
    }
    layer.project_inputs_batch(x_rows.data(), In, kPeople, gi_rows.data());
    layer.step_batch(gi_rows.data(), kGates, h_rows.data(), gh_rows.data(), work.data(), kPeople);
    layer.project_inputs_lanes(x_lanes.data(), kLanes, kLanes, gi_lanes.data(), kLanes);
    layer.step_lanes(gi_lanes.data(), h_lanes.data(), gh_lanes.data(), kLanes);
  }
  std::vector<float> back(kPeople * Hidden);
  lanes_to_rows(h_lanes.data(), Hidden, kPeople, kLanes, back.data());
  EXPECT_EQ(std::memcmp(back.data(), h_rows.data(), back.size() * sizeof(float)), 0)
      << In << " inputs, hidden " << Hidden;
  EXPECT_NE(h_rows[0], 0.0f);
}

TEST(Gru, StepsInLanesAsInRows) {
  expect_lanes_step_like_rows<5, 9>(31);
  expect_lanes_step_like_rows<9, 9>(32);
  expect_lanes_step_like_rows<11, 24>(33);
  expect_lanes_step_like_rows<8, 9>(34);
}

// A window's row gathered into lanes: each person's values down a column, one lane each, and
// back into rows.
TEST(Lanes, WindowRowsGoDownColumns) {
  constexpr int kPeople = kLaneGroup, kColumns = 4, kWindow = 40;
  std::vector<float> windows(kPeople * kWindow);
  for (std::size_t i = 0; i < windows.size(); ++i) {
    windows[i] = static_cast<float>(i);
  }
  std::vector<float> x(kColumns * kPeople, -1.0f);
  window_row_to_lanes(windows.data(), kWindow, 10, kColumns, kPeople, x.data());
  for (int c = 0; c < kColumns; ++c) {
    for (int p = 0; p < kPeople; ++p) {
      EXPECT_EQ(x[static_cast<std::size_t>(c) * kPeople + p],
                static_cast<float>(p * kWindow + 10 + c))
          << c << ", " << p;
    }
  }
  std::vector<float> rows(kPeople * kColumns);
  lanes_to_rows(x.data(), kColumns, kPeople, kPeople, rows.data());
  for (int p = 0; p < kPeople; ++p) {
    for (int c = 0; c < kColumns; ++c) {
      EXPECT_EQ(rows[static_cast<std::size_t>(p) * kColumns + c],
                static_cast<float>(p * kWindow + 10 + c));
    }
  }
  EXPECT_EQ(people_in_lanes(15), 0);
  EXPECT_EQ(people_in_lanes(16), 16);
  EXPECT_EQ(people_in_lanes(47), 32);
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
