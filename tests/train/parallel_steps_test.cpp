// deixis-train --threads N for the direct steps (train/parallel_steps.h): the MoE
// networks' experts shared out among a team, and the autoencoder's batch cut into slices, give
// the loss, the gradients and the predictions of the whole step on one thread, to float
// rounding — for unequal shares, partial batches, validation (no backward pass) and a slice left
// empty after a full batch — and the same bits on every run. Torch-free, so it also runs under
// ASan and UBSan.

#include "train/parallel_steps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.h"
#include "flat_buffers.h"

namespace deixis::train {
namespace {

// Parameters, gradients and moments as the trainer keeps them: one flat buffer each.
struct Flat {
  AlignedFloats values, grads, exp_avg, exp_avg_sq;
  explicit Flat(std::size_t n) : values(n), grads(n, 0.0f), exp_avg(n, 0.0f), exp_avg_sq(n, 0.0f) {}
  AdamWBuffers adamw() { return {values, grads, exp_avg, exp_avg_sq}; }
};

// Every tensor of `b` against `a` on its own scale: a wrong gradient of a small tensor (the
// gating GRU's) must not hide under the experts' larger ones.
void expect_close_per_tensor(const AlignedFloats& a, const AlignedFloats& b,
                             const std::vector<test_data::TensorRange>& tensors, double tolerance,
                             const std::string& what) {
  for (std::size_t t = 0; t < tensors.size(); ++t) {
    double difference = 0, scale = 0;
    for (std::size_t i = tensors[t].offset; i < tensors[t].offset + tensors[t].count; ++i) {
      difference = std::max(difference, static_cast<double>(std::abs(a[i] - b[i])));
      scale = std::max(scale, static_cast<double>(std::abs(b[i])));
    }
    EXPECT_GT(scale, 0.0) << what << ", tensor " << t << " has nothing to compare";
    EXPECT_LE(difference, tolerance * scale) << what << ", tensor " << t;
  }
}

// Three windows of `count` clips (UGNet feeding its predictions back from the second on), each
// with its optimiser step, on 1 and on `members` threads from the same parameters: the same
// losses, the same gradients (read from AdamW's first moment, which is linear in them; the
// parameters themselves are not compared, since Adam's first steps move a parameter by ±lr
// whatever the size of its gradient, so rounding can flip a near-zero one) and the same
// predictions fed back; then a validation window (no backward pass) with the same loss.
void expect_expert_team_is_whole(const MoeShape& shape, int batch_size, int count, int members) {
  Flat one(shape.parameter_count()), team(shape.parameter_count());
  test_data::fill_random(one.values, 0.3f, 7);
  team.values = one.values;  // same size: the buffers stay where they are
  const auto columns = shape.window_columns + shape.expert_out;
  std::vector<float> clips_one = test_data::random_values(
      static_cast<std::size_t>(count) * 45 * static_cast<std::size_t>(columns), 1.0f, 8);
  std::vector<float> clips_team = clips_one;
  const test_data::FlatMoe layout_one(shape, one.values.data()), grads_one(shape, one.grads.data());
  const test_data::FlatMoe layout_team(shape, team.values.data()),
      grads_team(shape, team.grads.data());
  ParallelMoeStep single(shape, batch_size, 1, layout_one.buffers, grads_one.buffers);
  ParallelMoeStep shared(shape, batch_size, members, layout_team.buffers, grads_team.buffers);
  Schedule schedule;
  const std::string team_of = std::to_string(members) + " threads, window ";
  for (int window = 0; window < 3; ++window) {  // feed predictions back from the second on
    const bool feed_back = shape.pose_columns > 0 && window > 0;
    const double l1 = single.window(clips_one.data(), columns, window, count, feed_back, true);
    const double l2 = shared.window(clips_team.data(), columns, window, count, feed_back, true);
    EXPECT_NEAR(l2, l1, 1e-6 * l1) << team_of << window;
    single.optimiser_step(one.adamw(), schedule, 1e-3, window + 1);
    shared.optimiser_step(team.adamw(), schedule, 1e-3, window + 1);
    expect_close_per_tensor(team.exp_avg, one.exp_avg, layout_one.tensors, 1e-5,
                            team_of + std::to_string(window));
    double fed = 0, fed_scale = 0;
    for (std::size_t i = 0; i < clips_one.size(); ++i) {
      fed = std::max(fed, static_cast<double>(std::abs(clips_team[i] - clips_one[i])));
      fed_scale = std::max(fed_scale, static_cast<double>(std::abs(clips_one[i])));
    }
    EXPECT_LT(fed, 1e-5 * fed_scale) << team_of << window;
  }
  const double v1 = single.window(clips_one.data(), columns, 5, count, false, false);
  const double v2 = shared.window(clips_team.data(), columns, 5, count, false, false);
  EXPECT_NEAR(v2, v1, 1e-6 * v1) << members << " threads, validation";
}

// 2 members: experts 0–3 and 4–8; 3: three each; 4: two or three; 9: one each (UGNet's
// first-layer products then all run before the gating is done).
TEST(ParallelSteps, UgnetExpertTeamsGiveTheWholeStep) {
  expect_expert_team_is_whole(MoeShape::ugnet(), 32, 32, 2);
  expect_expert_team_is_whole(MoeShape::ugnet(), 32, 13, 3);
  expect_expert_team_is_whole(MoeShape::ugnet(), 32, 20, 4);
  expect_expert_team_is_whole(MoeShape::ugnet(), 32, 7, 9);
}

TEST(ParallelSteps, MpnetExpertTeamsGiveTheWholeStep) {
  expect_expert_team_is_whole(MoeShape::mpnet(), 16, 16, 2);
  expect_expert_team_is_whole(MoeShape::mpnet(), 5, 3, 9);
}

// Two runs of the same team from the same state give the same bits, however the threads ran.
TEST(ParallelSteps, ATeamComputesTheSameBitsEveryTime) {
  const MoeShape shape = MoeShape::ugnet();
  std::vector<AlignedFloats> moments;
  for (int run = 0; run < 2; ++run) {
    Flat f(shape.parameter_count());
    test_data::fill_random(f.values, 0.3f, 7);
    std::vector<float> clips = test_data::random_values(32 * 45 * 56, 1.0f, 8);
    const test_data::FlatMoe p(shape, f.values.data()), g(shape, f.grads.data());
    ParallelMoeStep step(shape, 32, 2, p.buffers, g.buffers);
    for (int window = 0; window < 4; ++window) {
      step.window(clips.data(), 56, window, 32, window > 0, true);
      step.optimiser_step(f.adamw(), Schedule{}, 1e-3, window + 1);
    }
    moments.push_back(f.exp_avg);
  }
  EXPECT_TRUE(moments[0] == moments[1]);
}

// Batches of 8, then 4 over three members (slices of 2, 2 and 0: the third member must add
// nothing, whatever its buffers hold from the full batch), then 3, on the same objects.
TEST(ParallelSteps, AutoencoderSlicesAddUpToTheBatch) {
  const std::size_t n = AutoencoderStep::parameter_count();
  Flat one(n), team(n);
  test_data::fill_random(one.values, 0.05f, 9);
  team.values = one.values;
  const std::vector<float> segments = test_data::random_values(8 * 30 * 18, 1.0f, 10);
  const test_data::FlatAutoencoder p1(one.values.data()), g1(one.grads.data());
  const test_data::FlatAutoencoder p2(team.values.data()), g2(team.grads.data());
  ParallelAutoencoderStep single(8, 1, p1.buffers, g1.buffers, one.grads);
  ParallelAutoencoderStep sliced(8, 3, p2.buffers, g2.buffers, team.grads);
  int step = 0;
  for (const int count : {8, 4, 3}) {
    const double l1 = single.batch(segments.data(), count, true);
    const double l2 = sliced.batch(segments.data(), count, true);
    EXPECT_NEAR(l2, l1, 1e-6 * l1) << count;
    ++step;
    single.optimiser_step(one.adamw(), Schedule{}, 1e-3, step);
    sliced.optimiser_step(team.adamw(), Schedule{}, 1e-3, step);
    expect_close_per_tensor(team.exp_avg, one.exp_avg, p1.tensors, 1e-5,
                            std::to_string(count) + " segments");
  }
}

TEST(ParallelSteps, TeamsTheWorkCannotBeSharedByAreRefused) {
  Flat f(MoeShape::mpnet().parameter_count());
  const test_data::FlatMoe p(MoeShape::mpnet(), f.values.data());
  const test_data::FlatMoe g(MoeShape::mpnet(), f.grads.data());
  // Nine experts cannot be shared by ten threads, nor eight segments by nine.
  EXPECT_THROW(ParallelMoeStep(MoeShape::mpnet(), 16, 10, p.buffers, g.buffers), Error);
  Flat a(AutoencoderStep::parameter_count());
  const test_data::FlatAutoencoder pa(a.values.data()), ga(a.grads.data());
  EXPECT_THROW(ParallelAutoencoderStep(8, 9, pa.buffers, ga.buffers, a.grads), Error);
  // A window larger than the step, checked before any thread starts.
  ParallelMoeStep step(MoeShape::mpnet(), 4, 2, p.buffers, g.buffers);
  std::vector<float> clips(5 * 45 * 14, 0.0f);
  EXPECT_THROW(step.window(clips.data(), 14, 0, 5, false, false), Error);
}

}  // namespace
}  // namespace deixis::train
