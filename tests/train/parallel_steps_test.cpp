// deixis-train --threads N for the direct steps (gesture/train/parallel_steps.h): the MoE
// networks' experts shared out among a team, and the autoencoder's batch cut into slices, give
// the loss, the gradients and the predictions of the whole step on one thread, to float
// rounding — for unequal shares, partial batches and a slice left empty. Torch-free, so it also
// runs under ASan and UBSan.

#include "gesture/train/parallel_steps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "flat_buffers.h"
#include "gesture/error.h"

namespace deixis::train {
namespace {

// Parameters, gradients and moments as the trainer keeps them: one flat buffer each.
struct Flat {
  AlignedFloats values, grads, exp_avg, exp_avg_sq;
  explicit Flat(std::size_t n) : values(n), grads(n, 0.0f), exp_avg(n, 0.0f), exp_avg_sq(n, 0.0f) {}
  AdamWBuffers adamw() { return {values, grads, exp_avg, exp_avg_sq}; }
};

double largest_difference(const AlignedFloats& a, const AlignedFloats& b, double& scale) {
  double d = 0;
  scale = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    d = std::max(d, static_cast<double>(std::abs(a[i] - b[i])));
    scale = std::max(scale, static_cast<double>(std::abs(b[i])));
  }
  return d;
}

// Three windows of `count` clips (UGNet feeding its predictions back from the second on), each
// with its optimiser step, on 1 and on `members` threads from the same parameters: the same
// losses, the same gradients (read from AdamW's first moment, which is linear in them; the
// parameters themselves are not compared, since Adam's first steps move a parameter by ±lr
// whatever the size of its gradient, so rounding can flip a near-zero one) and the same
// predictions fed back.
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
  ParallelMoeStep sliced(shape, batch_size, members, layout_team.buffers, grads_team.buffers);
  Schedule schedule;
  for (int window = 0; window < 3; ++window) {  // feed predictions back from the second on
    const bool feed_back = shape.pose_columns > 0 && window > 0;
    const double l1 = single.window(clips_one.data(), columns, window, count, feed_back, true);
    const double l2 = sliced.window(clips_team.data(), columns, window, count, feed_back, true);
    EXPECT_NEAR(l2, l1, 1e-6 * l1) << "window " << window;
    single.optimiser_step(one.adamw(), schedule, 1e-3, window + 1);
    sliced.optimiser_step(team.adamw(), schedule, 1e-3, window + 1);
    double scale = 0;
    const double d = largest_difference(team.exp_avg, one.exp_avg, scale);
    EXPECT_LT(d, 1e-5 * scale) << "window " << window;
    EXPECT_GT(scale, 0.0);
    double fed = 0, fed_scale = 0;
    for (std::size_t i = 0; i < clips_one.size(); ++i) {
      fed = std::max(fed, static_cast<double>(std::abs(clips_team[i] - clips_one[i])));
      fed_scale = std::max(fed_scale, static_cast<double>(std::abs(clips_one[i])));
    }
    EXPECT_LT(fed, 1e-5 * fed_scale) << "window " << window;
  }
}

// 2 members: experts 0–3 and 4–8; 4: two or three each; 9: one each.
TEST(ParallelSteps, UgnetExpertTeamsGiveTheWholeStep) {
  expect_expert_team_is_whole(MoeShape::ugnet(), 32, 32, 2);
  expect_expert_team_is_whole(MoeShape::ugnet(), 32, 13, 4);
}

TEST(ParallelSteps, MpnetExpertTeamsGiveTheWholeStep) {
  expect_expert_team_is_whole(MoeShape::mpnet(), 16, 16, 2);
  expect_expert_team_is_whole(MoeShape::mpnet(), 5, 3, 9);
}

TEST(ParallelSteps, AutoencoderSlicesAddUpToTheBatch) {
  for (const int count : {8, 3}) {
    const std::size_t n = AutoencoderStep::parameter_count();
    Flat one(n), team(n);
    test_data::fill_random(one.values, 0.05f, 9);
    team.values = one.values;
    const std::vector<float> segments =
        test_data::random_values(static_cast<std::size_t>(count) * 30 * 18, 1.0f, 10);
    const test_data::FlatAutoencoder p1(one.values.data()), g1(one.grads.data());
    const test_data::FlatAutoencoder p2(team.values.data()), g2(team.grads.data());
    ParallelAutoencoderStep single(8, 1, p1.buffers, g1.buffers, one.grads);
    ParallelAutoencoderStep sliced(8, 3, p2.buffers, g2.buffers, team.grads);
    const double l1 = single.batch(segments.data(), count, true);
    const double l2 = sliced.batch(segments.data(), count, true);
    EXPECT_NEAR(l2, l1, 1e-6 * l1);
    Schedule schedule;
    single.optimiser_step(one.adamw(), schedule, 1e-3, 1);
    sliced.optimiser_step(team.adamw(), schedule, 1e-3, 1);
    double scale = 0;
    const double d = largest_difference(team.exp_avg, one.exp_avg, scale);
    EXPECT_LT(d, 1e-5 * scale) << count;
    EXPECT_GT(scale, 0.0);
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
}

}  // namespace
}  // namespace deixis::train
