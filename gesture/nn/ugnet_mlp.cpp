#include "gesture/nn/ugnet_architectures.h"

namespace deixis::nn {

bool UgnetMlp::recognises(const SafetensorsFile& file) {
  const TensorInfo* first = file.find("linear1.weight");
  return first != nullptr && first->shape.size() == 2 && first->shape[1] == kConditionSize;
}

void UgnetMlp::load(const SafetensorsFile& file) {
  linear1.load(file, "linear1");
  linear2.load(file, "linear2");
  linear3.load(file, "linear3");
}

PoseVector UgnetMlp::run(UgnetWindow window) const {
  const ConditionVector c = condition_vector(window);
  const bool reverse = panel_order.next_is_reversed();
  Eigen::Matrix<float, 4 * kConditionSize, 1> h1 = linear1.run_in_panels(c, reverse);
  elu_inplace(h1);
  Eigen::Matrix<float, kConditionSize, 1> h2 = linear2.run_in_panels(h1, reverse);
  elu_inplace(h2);
  PoseVector out;
  Eigen::Map<Eigen::Matrix<float, kPoseSize, 1>>(out.data()) = linear3.run(h2);
  return out;
}

}  // namespace deixis::nn
