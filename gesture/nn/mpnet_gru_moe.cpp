#include "gesture/nn/mpnet_architectures.h"

namespace deixis::nn {

using WindowMatrix = Eigen::Matrix<float, kWindowRows, kMpnetFeatures, Eigen::RowMajor>;

bool MpnetGruMoe::recognises(const SafetensorsFile& file) {
  return file.contains("gating_network.gru.weight_ih_l0") && file.contains("gru.weight_ih_l0") &&
         file.contains("moe_network.w_l1");
}

void MpnetGruMoe::load(const SafetensorsFile& file) {
  gating_l0.load(file, "gating_network.gru", 0);
  gating_l1.load(file, "gating_network.gru", 1);
  recurrent.load(file, "gru", 0);
  expert_l1.load(file, "moe_network.w_l1", "moe_network.b_l1");
  expert_l2.load(file, "moe_network.w_l2", "moe_network.b_l2");
  expert_l3.load(file, "moe_network.w_l3", "moe_network.b_l3");
}

MpnetOutput MpnetGruMoe::run(MpnetWindow window, MpnetTrace* trace) const {
  const Eigen::Map<const WindowMatrix> x(window.data());

  // The gating network (2-layer GRU over the target feature) and the recurrent module (GRU over
  // all 11 columns) are independent recurrences; stepping them in one loop lets the CPU overlap
  // their dependency chains. Layer 2 of the gating GRU consumes layer 1's state of the same step.
  const auto gi_gating = gating_l0.project_inputs<kWindowRows>(x.middleCols<5>(kMpnetTargetColumn));
  const auto gi_recurrent = recurrent.project_inputs<kWindowRows>(x);
  Eigen::Matrix<float, kExperts, 1> gating_h0 = Eigen::Matrix<float, kExperts, 1>::Zero();
  Eigen::Matrix<float, kExperts, 1> gating_h1 = Eigen::Matrix<float, kExperts, 1>::Zero();
  Eigen::Matrix<float, kRecurrentHidden, 1> z = Eigen::Matrix<float, kRecurrentHidden, 1>::Zero();
  for (int t = 0; t < kWindowRows; ++t) {
    gating_l0.step(gi_gating.row(t).transpose(), gating_h0);
    gating_l1.step(gating_l1.project_input(gating_h0), gating_h1);
    recurrent.step(gi_recurrent.row(t).transpose(), z);
  }
  Eigen::Matrix<float, kExperts, 1> omega = gating_h1;
  softmax_inplace(omega);

  Eigen::Matrix<float, kExpertHidden, 1> h1 = expert_l1.run(z, omega);
  elu_inplace(h1);
  Eigen::Matrix<float, kExpertHidden, 1> h2 = expert_l2.run(h1, omega);
  elu_inplace(h2);
  const Eigen::Matrix<float, kProgressionSize, 1> y = expert_l3.run(h2, omega);

  if (trace != nullptr) {
    Eigen::Map<Eigen::Matrix<float, kExperts, 1>>(trace->omega.data()) = omega;
    Eigen::Map<Eigen::Matrix<float, kRecurrentHidden, 1>>(trace->z.data()) = z;
  }
  return clamp_progression(y);
}

MpnetOutput clamp_progression(const Eigen::Matrix<float, kProgressionSize, 1>& raw) {
  MpnetOutput out;
  for (int i = 0; i < kProgressionSize; ++i) {
    out.preclamp[i] = raw(i);
    out.progression[i] = std::clamp(raw(i), 0.0f, 1.0f);
  }
  return out;
}

}  // namespace deixis::nn
