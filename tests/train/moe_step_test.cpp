// The MoE networks' direct training step (train/moe_step.h) is libtorch's autograd
// through the training models (train/models.cpp): the same loss, the same prediction and
// the same gradient for every parameter, at MPNet's and UGNet's sizes, for full and partial
// batches, with MPNet's clamp cutting some outputs and passing others.

#include "train/moe_step.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <map>
#include <string>

#include "train/models.h"

namespace deixis::train {
namespace {

constexpr int kClipRows = 45;

struct Case {
  Network network;
  MoeShape shape;
  int targets;  // columns after the inputs: 3 progressions, or UGNet's 24-value pose
};

Case mpnet_case() {
  return {Network::kMpnetMoe, MoeShape::mpnet(), 3};
}
Case ugnet_case() {
  return {Network::kUgnetMoe, MoeShape::ugnet(), 24};
}

// Clips as the trainer holds them: [batch, 45, inputs + targets]. MPNet's targets are
// progressions in [0, 1]; everything else is spread wide enough that MPNet's output leaves
// [0, 1] for some clips (its clamp passes no gradient there).
torch::Tensor random_clips(const Case& c, int count, std::uint64_t seed) {
  torch::manual_seed(seed);
  const int inputs = c.shape.window_columns;
  torch::Tensor clips = torch::randn({count, kClipRows, inputs + c.targets}) * 1.5;
  if (c.network == Network::kMpnetMoe) {
    clips.slice(2, inputs).uniform_(0.0, 1.0);
  }
  return clips;
}

struct Result {
  double loss = 0;
  torch::Tensor prediction;
  std::map<std::string, torch::Tensor> gradients;
};

// libtorch: forward, l1_loss and backward through the model's autograd graph.
Result through_autograd(TrainableNetwork& model, const torch::Tensor& clips, int window,
                        int inputs) {
  for (auto& p : model.parameters()) {
    p.mutable_grad() = torch::Tensor();
  }
  const torch::Tensor x = clips.slice(1, window, window + 30).slice(2, 0, inputs);
  const torch::Tensor y = clips.select(1, window + 29).slice(1, inputs);
  const torch::Tensor prediction = model.forward(x);
  const torch::Tensor loss = torch::l1_loss(prediction, y);
  loss.backward();
  Result r;
  r.loss = loss.item<double>();
  r.prediction = prediction.detach().clone();
  for (const auto& item : model.named_parameters()) {
    r.gradients[item.key()] = item.value().grad().clone();
  }
  return r;
}

// moe_step.h on the same memory: the gradients land in freshly zeroed .grad() tensors.
Result through_moe_step(TrainableNetwork& model, const Case& c, const torch::Tensor& clips,
                        int window, int max_batch) {
  for (auto& p : model.parameters()) {
    p.mutable_grad() = torch::full_like(p, 123.0f);  // every value must be overwritten
  }
  MoeStep step(c.shape, max_batch);
  const auto count = static_cast<int>(clips.size(0));
  const auto columns = static_cast<std::size_t>(clips.size(2));
  const float* first = clips.data_ptr<float>();
  const WindowBatch windows{first + static_cast<std::size_t>(window) * columns, kClipRows * columns,
                            columns};
  const TargetBatch targets{first + static_cast<std::size_t>(window + 29) * columns +
                                static_cast<std::size_t>(c.shape.window_columns),
                            kClipRows * columns};
  Result r;
  r.loss = step.forward(moe_buffers(model, false), windows, targets, count);
  step.backward(moe_buffers(model, false), moe_buffers(model, true));
  const std::span<const float> prediction = step.prediction();
  r.prediction =
      torch::from_blob(const_cast<float*>(prediction.data()), {count, c.shape.expert_out}).clone();
  for (const auto& item : model.named_parameters()) {
    r.gradients[item.key()] = item.value().grad().clone();
  }
  return r;
}

void expect_same(const Case& c, int count, int max_batch, int window) {
  torch::manual_seed(5);
  std::shared_ptr<TrainableNetwork> model = make_network(c.network);
  model->train();
  const torch::Tensor clips = random_clips(c, count, 17);
  const Result reference = through_autograd(*model, clips, window, c.shape.window_columns);
  const Result direct = through_moe_step(*model, c, clips, window, max_batch);

  EXPECT_NEAR(direct.loss, reference.loss, 1e-6 * std::max(1.0, reference.loss));
  EXPECT_LT((direct.prediction - reference.prediction).abs().max().item<double>(), 1e-5);
  ASSERT_EQ(direct.gradients.size(), reference.gradients.size());
  std::size_t checked = 0;
  for (const auto& [name, want] : reference.gradients) {
    const torch::Tensor& got = direct.gradients.at(name);
    ASSERT_EQ(got.sizes(), want.sizes()) << name;
    const double scale = std::max(want.abs().max().item<double>(), 1e-8);
    EXPECT_LT((got - want).abs().max().item<double>() / scale, 1e-4) << name;
    // A gradient that is all zero would compare equal to a step that never wrote it.
    EXPECT_GT(want.abs().max().item<double>(), 1e-9) << name << " has no gradient to compare";
    checked += static_cast<std::size_t>(want.numel());
  }
  EXPECT_EQ(checked, c.shape.parameter_count());
}

TEST(MoeStep, MpnetMatchesAutograd) {
  expect_same(mpnet_case(), 16, 16, 0);
}

TEST(MoeStep, UgnetMatchesAutograd) {
  expect_same(ugnet_case(), 32, 32, 7);
}

// Validation's last batch is smaller than the buffers; 20 windows are three vectors of lanes.
TEST(MoeStep, PartialBatchesMatchAutograd) {
  expect_same(mpnet_case(), 5, 16, 15);
  expect_same(ugnet_case(), 11, 32, 15);
  expect_same(ugnet_case(), 20, 32, 3);
}

// The clips are wide enough that MPNet's clamp cuts some outputs (its gradient is then 0 there)
// and passes others: both branches are in the comparison above.
TEST(MoeStep, MpnetClampIsExercised) {
  torch::manual_seed(5);
  std::shared_ptr<TrainableNetwork> model = make_network(Network::kMpnetMoe);
  const torch::Tensor clips = random_clips(mpnet_case(), 16, 17);
  const torch::Tensor raw = mpnet_preclamp(*model, clips.slice(1, 0, 30).slice(2, 0, 11));
  const auto inside = ((raw >= 0) & (raw <= 1)).sum().item<std::int64_t>();
  EXPECT_GT(inside, 0);
  EXPECT_LT(inside, raw.numel());
}

TEST(MoeStep, RefusesBatchesItCannotHold) {
  MoeStep step(MoeShape::ugnet(), 4);
  const std::vector<float> clips(5 * kClipRows * 56, 0.0f);
  const WindowBatch windows{clips.data(), kClipRows * 56, 56};
  const TargetBatch targets{clips.data() + 29 * 56 + 32, kClipRows * 56};
  std::shared_ptr<TrainableNetwork> model = make_network(Network::kUgnetMoe);
  EXPECT_THROW(step.forward(moe_buffers(*model, false), windows, targets, 5), std::exception);
  EXPECT_THROW(step.forward(moe_buffers(*model, false), windows, targets, 0), std::exception);
  EXPECT_THROW(MoeStep(MoeShape::mpnet(), 0), std::exception);
}

TEST(MoeStep, BuffersNameWhatIsMissing) {
  std::shared_ptr<TrainableNetwork> mlp = make_network(Network::kMpnetMlp);
  try {
    moe_buffers(*mlp, false);
    FAIL() << "an MLP has no MoE tensors";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("gating_network.gru.weight_ih_l0"), std::string::npos)
        << e.what();
  }
  std::shared_ptr<TrainableNetwork> moe = make_network(Network::kUgnetMoe);
  try {
    moe_buffers(*moe, true);  // no .grad() yet
    FAIL() << "undefined gradients must be refused";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("not defined"), std::string::npos) << e.what();
  }
}

TEST(MoeStep, ParameterCountsAreTheNetworks) {
  for (const Case& c : {mpnet_case(), ugnet_case()}) {
    std::shared_ptr<TrainableNetwork> model = make_network(c.network);
    std::int64_t n = 0;
    for (const auto& p : model->parameters()) {
      n += p.numel();
    }
    EXPECT_EQ(c.shape.parameter_count(), static_cast<std::size_t>(n));
  }
}

}  // namespace
}  // namespace deixis::train
