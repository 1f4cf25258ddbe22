// The direct training steps (train/moe_step.h, autoencoder_step.h) keep their buffers
// from batch to batch, and the trainer feeds them full batches, then validation's smaller last
// batch, then full batches again. One step object taken through batch sizes 32, 11, 20 and 32
// must give, bit for bit, what a fresh object gives for each batch: nothing may be read that
// this batch did not write. (Bit for bit holds because every buffer starts on a 64-byte
// boundary, in the steps and in the trainer's flat buffers alike: aligned_buffer.h says why.)
// Torch-free, so it also runs under ASan and UBSan, which check every buffer access of both steps.
// (Their maths is checked against libtorch's autograd in moe_step_test.cpp and
// autoencoder_step_test.cpp.)

#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "flat_buffers.h"
#include "train/autoencoder_step.h"
#include "train/moe_step.h"

namespace deixis::train {
namespace {

constexpr int kClipRows = 45;

// Parameters (or gradients) in one flat buffer, cut into the network's tensors.
struct FlatMoe {
  AlignedFloats values;  // never reallocated: the buffers point into it (aligned as torch's)
  MoeBuffers buffers;
  explicit FlatMoe(const MoeShape& s)
      : values(s.parameter_count(), 0.0f), buffers(test_data::FlatMoe(s, values.data()).buffers) {}
};

struct FlatAutoencoder {
  AlignedFloats values;  // never reallocated: the buffers point into it (aligned as torch's)
  AutoencoderBuffers buffers;
  FlatAutoencoder()
      : values(AutoencoderStep::parameter_count(), 0.0f),
        buffers(test_data::FlatAutoencoder(values.data()).buffers) {}
};

using test_data::fill_random;
using test_data::random_values;

struct Outcome {
  double loss = 0;
  std::vector<float> prediction;
  AlignedFloats gradients;
};

Outcome moe_batch(MoeStep& step, const FlatMoe& parameters, const std::vector<float>& clips,
                  int count, int window) {
  const MoeShape& s = step.shape();
  FlatMoe gradients(s);
  const auto columns = static_cast<std::size_t>(s.window_columns + s.expert_out);
  const float* first = clips.data() + static_cast<std::size_t>(window) * columns;
  Outcome o;
  o.loss = step.forward(
      parameters.buffers, {first, kClipRows * columns, columns},
      {first + 29 * columns + static_cast<std::size_t>(s.window_columns), kClipRows * columns},
      count);
  step.backward(parameters.buffers, gradients.buffers);
  o.prediction.assign(step.prediction().begin(), step.prediction().end());
  o.gradients = gradients.values;
  return o;
}

void expect_reuse_is_fresh(const MoeShape& shape) {
  FlatMoe parameters(shape);
  fill_random(parameters.values, 0.3f, 1);
  const auto columns = static_cast<std::size_t>(shape.window_columns + shape.expert_out);
  const std::vector<float> clips = random_values(32 * kClipRows * columns, 1.0f, 2);
  MoeStep reused(shape, 32);
  int window = 0;
  for (const int count : {32, 11, 20, 32}) {
    MoeStep fresh(shape, count);
    const Outcome a = moe_batch(reused, parameters, clips, count, window);
    const Outcome b = moe_batch(fresh, parameters, clips, count, window);
    EXPECT_EQ(a.loss, b.loss) << count << " windows";
    EXPECT_EQ(a.prediction, b.prediction) << count << " windows";
    EXPECT_EQ(a.gradients, b.gradients) << count << " windows";
    EXPECT_EQ(a.prediction.size(), static_cast<std::size_t>(count * shape.expert_out));
    window = (window + 5) % 16;
  }
}

TEST(DirectStepReuse, MpnetStepReadsOnlyWhatEachBatchWrote) {
  expect_reuse_is_fresh(MoeShape::mpnet());
}

TEST(DirectStepReuse, UgnetStepReadsOnlyWhatEachBatchWrote) {
  expect_reuse_is_fresh(MoeShape::ugnet());
}

TEST(DirectStepReuse, AutoencoderStepReadsOnlyWhatEachBatchWrote) {
  FlatAutoencoder parameters;
  fill_random(parameters.values, 0.05f, 3);
  const std::vector<float> segments = random_values(8 * 30 * 18, 1.0f, 4);
  AutoencoderStep reused(8);
  for (const int count : {8, 3, 5, 8}) {
    AutoencoderStep fresh(count);
    FlatAutoencoder ga, gb;
    const double la = reused.forward(parameters.buffers, segments.data(), count);
    reused.backward(parameters.buffers, ga.buffers);
    const double lb = fresh.forward(parameters.buffers, segments.data(), count);
    fresh.backward(parameters.buffers, gb.buffers);
    EXPECT_EQ(la, lb) << count << " segments";
    EXPECT_TRUE(std::equal(reused.reconstruction().begin(), reused.reconstruction().end(),
                           fresh.reconstruction().begin(), fresh.reconstruction().end()))
        << count << " segments";
    EXPECT_EQ(ga.values, gb.values) << count << " segments";
  }
}

}  // namespace
}  // namespace deixis::train
