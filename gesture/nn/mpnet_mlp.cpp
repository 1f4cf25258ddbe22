#include "gesture/nn/mpnet_architectures.h"

namespace deixis::nn {

bool MpnetMlp::recognises(const SafetensorsFile& file) {
  const TensorInfo* first = file.find("linear1.weight");
  return first != nullptr && first->shape.size() == 2 && first->shape[1] == kMpnetWindowSize;
}

void MpnetMlp::load(const SafetensorsFile& file) {
  linear1.load(file, "linear1");
  linear2.load(file, "linear2");
  linear3.load(file, "linear3");
}

MpnetOutput MpnetMlp::run(MpnetWindow window) const {
  const Eigen::Map<const Eigen::Matrix<float, kMpnetWindowSize, 1>> x(window.data());
  Eigen::Matrix<float, 24, 1> h1 = linear1.run(x);
  elu_inplace(h1);
  Eigen::Matrix<float, 24, 1> h2 = linear2.run(h1);
  elu_inplace(h2);
  return clamp_progression(linear3.run(h2));
}

}  // namespace deixis::nn
