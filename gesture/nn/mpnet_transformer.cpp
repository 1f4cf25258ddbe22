#include "gesture/nn/mpnet_architectures.h"

namespace deixis::nn {

bool MpnetTransformer::recognises(const SafetensorsFile& file) {
  return file.contains("linear_input.weight") &&
         file.contains("transformer.layers.0.self_attn.in_proj_weight");
}

void MpnetTransformer::load(const SafetensorsFile& file) {
  linear_input.load(file, "linear_input");
  for (int l = 0; l < kLayers; ++l) {
    layers[l].load(file, "transformer.layers." + std::to_string(l));
  }
  linear_output.load(file, "linear_output");
}

MpnetOutput MpnetTransformer::run(MpnetWindow window) const {
  const Eigen::Map<const Eigen::Matrix<float, kWindowRows, kMpnetFeatures, Eigen::RowMajor>> x(
      window.data());
  Layer::TokenMatrix tokens = linear_input.run_rows<kWindowRows>(x);
  for (int l = 0; l + 1 < kLayers; ++l) {
    layers[l].run(tokens);
  }
  const Eigen::Matrix<float, 1, kDim> newest = layers[kLayers - 1].run_last_token(tokens);
  return clamp_progression(linear_output.run(newest.transpose()));
}

}  // namespace deixis::nn
