#include "gesture/nn/ugnet_architectures.h"

namespace deixis::nn {

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
}

PoseVector UgnetTransformer::run(UgnetWindow window) const {
  const Eigen::Map<const UgnetWindowMatrix> x(window.data());
  Layer::TokenMatrix tokens;
  tokens.topRows<kWindowRows>() =
      linear_input_feature.run_rows<kWindowRows>(x.rightCols<kConditionColumns>());
  tokens.row(kTokens - 1) =
      linear_input_pose.run(x.row(kWindowRows - 1).head<kPoseSize>().transpose()).transpose();
  for (int l = 0; l + 1 < kLayers; ++l) {
    layers[l].run(tokens);
  }
  const Eigen::Matrix<float, 1, kDim> pose_token = layers[kLayers - 1].run_last_token(tokens);
  PoseVector out;
  Eigen::Map<Eigen::Matrix<float, kPoseSize, 1>>(out.data()) =
      linear_output.run(pose_token.transpose());
  return out;
}

}  // namespace deixis::nn
