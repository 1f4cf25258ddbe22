#include "gesture/nn/ugnet_architectures.h"

#include <algorithm>

namespace deixis::nn {

namespace {

// Windows per pass of run_batch: 32 windows are 992 token rows, enough for the products to run
// at the kernel's rate, while a layer's 992 × 480 projections (1.9 MB) still sit in cache.
constexpr std::size_t kBatchChunk = 32;

}  // namespace

bool UgnetTransformer::recognises(const SafetensorsFile& file) {
  return file.contains("linear_input_pose.weight") &&
         file.contains("transformer.layers.0.self_attn.in_proj_weight");
}

void UgnetTransformer::load(const SafetensorsFile& file) {
  linear_input_pose.load(file, "linear_input_pose");
  linear_input_feature.load(file, "linear_input_feature");
  for (int l = 0; l < kLayers; ++l) {
    layers[l].load(file, "transformer.layers." + std::to_string(l));
  }
  linear_output.load(file, "linear_output");
  // F and g in double, rounded once.
  const Eigen::MatrixXd w_in = layers[0].in_proj_weight.view().cast<double>();
  Eigen::Map<Eigen::Matrix<float, 3 * kDim, kConditionColumns, Eigen::RowMajor>>(
      feature_qkv_weight.storage().data()) =
      (w_in * linear_input_feature.weight.view().cast<double>()).cast<float>();
  Eigen::Map<Eigen::Matrix<float, 3 * kDim, 1>>(feature_qkv_bias.storage().data()) =
      (w_in * linear_input_feature.bias.view().cast<double>() +
       layers[0].in_proj_bias.view().cast<double>())
          .cast<float>();
}

template <typename Tokens, typename Qkv>
void UgnetTransformer::embed(UgnetWindow window, Tokens&& tokens, Qkv&& qkv) const {
  const Eigen::Map<const UgnetWindowMatrix> x(window.data());
  const auto features = x.rightCols<kConditionColumns>();
  tokens.template topRows<kWindowRows>() = linear_input_feature.run_rows<kWindowRows>(features);
  tokens.row(kTokens - 1) =
      linear_input_pose.run(x.row(kWindowRows - 1).head<kPoseSize>().transpose()).transpose();
  auto feature_qkv = qkv.template topRows<kWindowRows>();
  feature_qkv.noalias() = features * feature_qkv_weight.view().transpose();
  feature_qkv.rowwise() += feature_qkv_bias.view().transpose();
}

PoseVector UgnetTransformer::run(UgnetWindow window) const {
  Layer::TokenMatrix tokens;
  {  // qkv (60 KB) leaves the stack before the other layers put theirs on it
    Layer::QkvMatrix qkv;
    embed(window, tokens, qkv);
    qkv.row(kTokens - 1).noalias() =
        tokens.row(kTokens - 1) * layers[0].in_proj_weight.view().transpose();
    qkv.row(kTokens - 1) += layers[0].in_proj_bias.view().transpose();
    layers[0].run_projected(qkv, tokens);
  }
  for (int l = 1; l + 1 < kLayers; ++l) {
    layers[l].run(tokens);
  }
  const Eigen::Matrix<float, 1, kDim> pose_token = layers[kLayers - 1].run_last_token(tokens);
  PoseVector out;
  Eigen::Map<Eigen::Matrix<float, kPoseSize, 1>>(out.data()) =
      linear_output.run(pose_token.transpose());
  return out;
}

void UgnetTransformer::run_batch(std::span<const float> windows, std::span<float> out) const {
  const std::size_t count = out.size() / kPoseSize;
  Layer::TokenRows tokens, pose_tokens;
  Layer::QkvRows qkv, pose_qkv;
  for (std::size_t first = 0; first < count; first += kBatchChunk) {
    const auto n = static_cast<Eigen::Index>(std::min(kBatchChunk, count - first));
    tokens.resize(n * kTokens, kDim);
    qkv.resize(n * kTokens, 3 * kDim);
    pose_tokens.resize(n, kDim);
    for (Eigen::Index j = 0; j < n; ++j) {
      const std::size_t window = first + static_cast<std::size_t>(j);
      embed(UgnetWindow(windows.subspan(window * kUgnetWindowSize, kUgnetWindowSize)),
            tokens.middleRows(j * kTokens, kTokens), qkv.middleRows(j * kTokens, kTokens));
      pose_tokens.row(j) = tokens.row(j * kTokens + kTokens - 1);
    }
    pose_qkv.noalias() = pose_tokens * layers[0].in_proj_weight.view().transpose();
    pose_qkv.rowwise() += layers[0].in_proj_bias.view().transpose();
    for (Eigen::Index j = 0; j < n; ++j) {
      qkv.row(j * kTokens + kTokens - 1) = pose_qkv.row(j);
    }
    layers[0].run_batch_projected(qkv, tokens);
    for (int l = 1; l + 1 < kLayers; ++l) {
      layers[l].run_batch(tokens);
    }
    pose_tokens = layers[kLayers - 1].run_last_token_batch(tokens);
    Eigen::Map<Eigen::Matrix<float, Eigen::Dynamic, kPoseSize, Eigen::RowMajor>> poses(
        out.data() + first * kPoseSize, n, kPoseSize);
    poses.noalias() = pose_tokens * linear_output.weight.view().transpose();
    poses.rowwise() += linear_output.bias.view().transpose();
  }
}

}  // namespace deixis::nn
