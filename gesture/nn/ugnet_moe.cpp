#include "gesture/nn/ugnet_architectures.h"

namespace deixis::nn {

ConditionVector condition_vector(UgnetWindow window) {
  const Eigen::Map<const UgnetWindowMatrix> x(window.data());
  ConditionVector c;
  c.head<kPoseSize>() = x.row(kWindowRows - 1).head<kPoseSize>().transpose();
  for (int row = 0; row < kWindowRows; ++row) {
    c.segment<kConditionColumns>(kPoseSize + row * kConditionColumns) =
        x.row(row).tail<kConditionColumns>().transpose();
  }
  return c;
}

bool UgnetMoe::recognises(const SafetensorsFile& file) {
  return file.contains("gating_network.gru.weight_ih_l0") && file.contains("moe_network.w_l1") &&
         !file.contains("gru.weight_ih_l0");
}

void UgnetMoe::load(const SafetensorsFile& file) {
  gating_l0.load(file, "gating_network.gru", 0);
  gating_l1.load(file, "gating_network.gru", 1);
  expert_l1.load(file, "moe_network.w_l1", "moe_network.b_l1");
  expert_l2.load(file, "moe_network.w_l2", "moe_network.b_l2");
  expert_l3.load(file, "moe_network.w_l3", "moe_network.b_l3");
}

PoseVector UgnetMoe::run(UgnetWindow window, UgnetTrace* trace) const {
  const Eigen::Map<const UgnetWindowMatrix> x(window.data());

  // Gating network: the 2-layer GRU over the conditioning columns, layer 2 stepped with layer 1.
  const auto gi_gating = gating_l0.project_inputs<kWindowRows>(x.rightCols<kConditionColumns>());
  using Gating = Eigen::Matrix<float, kExperts, 1>;
  Gating gating_h0 = Gating::Zero();
  Gating omega = Gating::Zero();
  for (int t = 0; t < kWindowRows; ++t) {
    gating_l0.step(gi_gating.row(t).transpose(), gating_h0);
    gating_l1.step(gating_l1.project_input(gating_h0), omega);
  }
  softmax_inplace(omega);

  const ConditionVector c = condition_vector(window);
  const bool reverse = panel_order.next_is_reversed();
  Eigen::Matrix<float, kHidden, 1> h1 = expert_l1.run(c, omega, reverse);
  elu_inplace(h1);
  Eigen::Matrix<float, kHidden, 1> h2 = expert_l2.run(h1, omega, reverse);
  elu_inplace(h2);
  PoseVector out;
  Eigen::Map<Eigen::Matrix<float, kPoseSize, 1>>(out.data()) = expert_l3.run(h2, omega, reverse);

  if (trace != nullptr) {
    Eigen::Map<Eigen::Matrix<float, kExperts, 1>>(trace->omega.data()) = omega;
  }
  return out;
}

}  // namespace deixis::nn
