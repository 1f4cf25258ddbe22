// The FMD autoencoder's direct training step (train/autoencoder_step.h) is libtorch's
// autograd through the training model (train/models.cpp, whose convolutions
// conv_as_matmul_test checks against libtorch's own): the same loss, the same reconstruction and
// the same gradient for every parameter, for a full and a partial batch, with both ReLUs cutting
// some units and passing others.

#include "train/autoencoder_step.h"

#include <gtest/gtest.h>
#include <torch/torch.h>

#include <map>
#include <string>

#include "train/models.h"

namespace deixis::train {
namespace {

struct Result {
  double loss = 0;
  torch::Tensor reconstruction;
  std::map<std::string, torch::Tensor> gradients;
};

Result through_autograd(TrainableNetwork& model, const torch::Tensor& segments) {
  for (auto& p : model.parameters()) {
    p.mutable_grad() = torch::Tensor();
  }
  const torch::Tensor reconstruction = model.forward(segments);
  const torch::Tensor loss = torch::l1_loss(reconstruction, segments);
  loss.backward();
  Result r;
  r.loss = loss.item<double>();
  r.reconstruction = reconstruction.detach().clone();
  for (const auto& item : model.named_parameters()) {
    r.gradients[item.key()] = item.value().grad().clone();
  }
  return r;
}

Result through_direct_step(TrainableNetwork& model, const torch::Tensor& segments, int max_batch) {
  for (auto& p : model.parameters()) {
    p.mutable_grad() = torch::full_like(p, 123.0f);  // every value must be overwritten
  }
  AutoencoderStep step(max_batch);
  const auto count = static_cast<int>(segments.size(0));
  Result r;
  r.loss = step.forward(autoencoder_buffers(model, false), segments.data_ptr<float>(), count);
  step.backward(autoencoder_buffers(model, false), autoencoder_buffers(model, true));
  const std::span<const float> y = step.reconstruction();
  r.reconstruction = torch::from_blob(const_cast<float*>(y.data()), segments.sizes()).clone();
  for (const auto& item : model.named_parameters()) {
    r.gradients[item.key()] = item.value().grad().clone();
  }
  return r;
}

void expect_same(int count, int max_batch) {
  torch::manual_seed(3);
  std::shared_ptr<TrainableNetwork> model = make_network(Network::kMotionAutoencoder);
  model->train();
  const torch::Tensor segments = torch::randn({count, 30, 18});
  const Result reference = through_autograd(*model, segments);
  const Result direct = through_direct_step(*model, segments, max_batch);
  EXPECT_NEAR(direct.loss, reference.loss, 1e-6 * reference.loss);
  EXPECT_LT((direct.reconstruction - reference.reconstruction).abs().max().item<double>(), 1e-5);
  ASSERT_EQ(direct.gradients.size(), 8u);
  for (const auto& [name, want] : reference.gradients) {
    const torch::Tensor& got = direct.gradients.at(name);
    ASSERT_EQ(got.sizes(), want.sizes()) << name;
    const double scale = want.abs().max().item<double>();
    EXPECT_GT(scale, 1e-9) << name << " has no gradient to compare";
    EXPECT_LT((got - want).abs().max().item<double>() / scale, 1e-4) << name;
  }
}

TEST(AutoencoderStep, MatchesAutograd) {
  expect_same(8, 8);
}

TEST(AutoencoderStep, PartialBatchMatchesAutograd) {
  expect_same(3, 8);
}

// Both ReLUs must cut some units and pass others for the comparison above to cover them.
TEST(AutoencoderStep, BothReluBranchesAreExercised) {
  torch::manual_seed(3);
  std::shared_ptr<TrainableNetwork> model = make_network(Network::kMotionAutoencoder);
  const torch::Tensor segments = torch::randn({8, 30, 18});
  auto params = model->named_parameters();
  torch::NoGradGuard no_grad;
  // The encoder's hidden layer and the decoder's, before their ReLUs, with libtorch's own
  // convolutions (channels first).
  const torch::Tensor encoded = torch::conv1d(
      segments.transpose(1, 2), params["conv_encode1.weight"], params["conv_encode1.bias"]);
  const torch::Tensor code = torch::conv1d(torch::relu(encoded), params["conv_encode2.weight"],
                                           params["conv_encode2.bias"]);
  const torch::Tensor decoded =
      torch::conv_transpose1d(code, params["conv_decode2.weight"], params["conv_decode2.bias"]);
  for (const torch::Tensor& hidden : {encoded, decoded}) {
    const auto positive = (hidden > 0).sum().item<std::int64_t>();
    EXPECT_GT(positive, 0);
    EXPECT_LT(positive, hidden.numel());
  }
}

TEST(AutoencoderStep, RefusesBatchesItCannotHold) {
  std::shared_ptr<TrainableNetwork> model = make_network(Network::kMotionAutoencoder);
  const std::vector<float> segments(9 * 30 * 18, 0.0f);
  AutoencoderStep step(8);
  EXPECT_THROW(step.forward(autoencoder_buffers(*model, false), segments.data(), 9),
               std::exception);
  EXPECT_THROW(AutoencoderStep(0), std::exception);
  std::shared_ptr<TrainableNetwork> moe = make_network(Network::kUgnetMoe);
  EXPECT_THROW(autoencoder_buffers(*moe, false), std::exception);
}

}  // namespace
}  // namespace deixis::train
