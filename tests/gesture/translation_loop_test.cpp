// The translation loop reproduces the authors' chained harness
// (docs/conventions.md#translation-loop, #parity): both rollout fixtures, 120 steps of MPNet MoE →
// progression window → UGNet MoE → blend, step by step.

#include "gesture/translation_loop.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "gesture/parity.h"
#include "test_support.h"

namespace deixis {
namespace {

namespace fs = std::filesystem;

class RolloutParity : public ::testing::TestWithParam<std::string> {};

TEST_P(RolloutParity, ReproducesTheAuthorsChainedHarness) {
  // check_parity runs the loop over the fixture's 120 steps and compares every recorded tensor:
  // network inputs and outputs per step, blend weights, and the avatar pose (float32 and
  // float64 rollouts) within 1e-5.
  const fs::path fixture = testing::reference_dir() / "fixtures" /
                           ("rollout_MPNet_MoE_UGNet_MoE_" + GetParam() + ".safetensors");
  const ParityReport report = check_parity(fixture, testing::reference_dir());
  EXPECT_EQ(report.windows, 120);
  std::vector<std::string> compared;
  for (const ParityCheck& check : report.checks) {
    compared.push_back(check.tensor);
    EXPECT_TRUE(check.passed()) << check.tensor << " max |error| " << check.max_abs_error << " > "
                                << check.tolerance;
    std::printf("[ measured ] %s %s: %.2g\n", GetParam().c_str(), check.tensor.c_str(),
                check.max_abs_error);
  }
  for (const char* tensor :
       {"avatar_pose", "avatar_pose_f64", "mpnet_input", "ugnet_input", "mpnet_output",
        "ugnet_output", "progression_window", "head_blend", "hand_blend"}) {
    EXPECT_NE(std::find(compared.begin(), compared.end(), tensor), compared.end()) << tensor;
  }
}

INSTANTIATE_TEST_SUITE_P(BothHands, RolloutParity, ::testing::Values("right", "left"),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

TEST(BlendCounters, RiseWhileFreeAndFallWhileGesturing) {
  BlendCounters c;
  for (int i = 0; i < 25; ++i) {
    c.update({0.1f, 0.1f, 0.0f});  // free-form: neither gaze nor deictic progression
  }
  EXPECT_EQ(c.head, BlendCounters::kMax);
  EXPECT_EQ(c.hand, BlendCounters::kMax);
  EXPECT_FLOAT_EQ(c.head_weight(), 1.0f);
  c.update({0.9f, 0.1f, 0.0f});  // gazing at a target: head falls, hand keeps rising (capped)
  EXPECT_EQ(c.head, BlendCounters::kMax - 1);
  EXPECT_EQ(c.hand, BlendCounters::kMax);
  c.update({0.1f, 0.1f, 0.5f});  // idle: both fall
  EXPECT_EQ(c.head, BlendCounters::kMax - 2);
  EXPECT_EQ(c.hand, BlendCounters::kMax - 1);
  for (int i = 0; i < 40; ++i) {
    c.update({1.0f, 1.0f, 0.0f});
  }
  EXPECT_EQ(c.head, 0);
  EXPECT_EQ(c.hand, 0);
}

TEST(Blend, WeightOneCopiesTheUserWeightZeroScalesThePrediction) {
  EndEffectors predicted{}, user{};
  for (int i = 0; i < kEndEffectorSize; ++i) {
    predicted[i] = 0.5f + 0.01f * static_cast<float>(i);
    user[i] = -0.3f + 0.02f * static_cast<float>(i);
  }
  const EndEffectors copied = blend_end_effectors(predicted, user, 1.0f, 1.0f, 1.25f);
  for (const int at : {ee::kHeadPosition, ee::kHandPosition, ee::kFingertip}) {
    EXPECT_TRUE(get_vec3(copied, at).isApprox(get_vec3(user, at), 1e-6f)) << at;
  }
  EXPECT_NEAR(get_vec3(copied, ee::kGaze).norm(), 1.0f, 1e-6f);  // renormalised
  const EndEffectors generated = blend_end_effectors(predicted, user, 0.0f, 0.0f, 1.25f);
  // With the hand weight 0 the hand position is the prediction scaled by 1/scale (user 25 %
  // larger than the avatar: the avatar's reach shrinks accordingly).
  EXPECT_TRUE(get_vec3(generated, ee::kHandPosition)
                  .isApprox(get_vec3(predicted, ee::kHandPosition) / 1.25f, 1e-6f));
  EXPECT_TRUE(get_vec3(generated, ee::kHeadPosition)
                  .isApprox(get_vec3(predicted, ee::kHeadPosition), 1e-6f));
}

// begin_step() + UGNet + end_step() is step(): two loops over the same 60 random frames, one
// stepping whole, one in halves (the way deixis eval batches its chains), stay bit-identical.
TEST(TranslationLoop, BeginAndEndStepMakeAWholeStep) {
  const fs::path w = testing::reference_dir() / "weights/right";
  const nn::Mpnet mpnet = nn::Mpnet::load(w / "MPNet(MoE)(AC)80.safetensors");
  const nn::Ugnet ugnet = nn::Ugnet::load(w / "UGNet(Diffusion)(AC)120.safetensors");
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> value(-1.0f, 1.0f);
  std::normal_distribution<float> draw(0.0f, 1.0f);
  const auto random_frame = [&] {
    TranslationInput f;
    std::ranges::generate(f.user_features, [&] { return value(rng); });
    std::ranges::generate(f.user_x, [&] { return value(rng); });
    std::ranges::generate(f.avatar_target, [&] { return value(rng); });
    return f;
  };
  std::vector<float> noise(nn::kDiffusionNoiseSize);
  const TranslationInput first = random_frame();
  TranslationLoop whole(mpnet, ugnet, 1.1f), halves(mpnet, ugnet, 1.1f);
  whole.reset(first, first.user_x);
  halves.reset(first, first.user_x);
  for (int k = 0; k < 60; ++k) {
    const TranslationInput frame = random_frame();
    std::ranges::generate(noise, [&] { return draw(rng); });
    const TranslationStep a = whole.step(frame, noise);
    TranslationStep b = halves.begin_step(frame);
    const nn::PoseVector prediction = ugnet.run(halves.ugnet_window(), noise);
    EXPECT_NE(b.prediction, prediction) << "begin_step() must leave the prediction to end_step()";
    halves.end_step(prediction, b);
    ASSERT_EQ(a.avatar_x, b.avatar_x) << "frame " << k;
    ASSERT_EQ(a.progression, b.progression) << "frame " << k;
    ASSERT_EQ(a.prediction, b.prediction) << "frame " << k;
    ASSERT_EQ(a.head_weight, b.head_weight) << "frame " << k;
    ASSERT_EQ(a.hand_weight, b.hand_weight) << "frame " << k;
    ASSERT_TRUE(std::ranges::equal(whole.ugnet_window(), halves.ugnet_window())) << "frame " << k;
    ASSERT_EQ(whole.prediction(), halves.prediction()) << "frame " << k;
  }
}

}  // namespace
}  // namespace deixis
