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

  // Gating network: the target feature only.
  Eigen::Matrix<float, kWindowRows, kExperts, Eigen::RowMajor> gating_hidden;
  gating_l0.run<kWindowRows>(x.middleCols<5>(kMpnetTargetColumn), gating_hidden);
  Eigen::Matrix<float, kWindowRows, kExperts, Eigen::RowMajor> gating_out;
  gating_l1.run<kWindowRows>(gating_hidden, gating_out);
  Eigen::Matrix<float, kExperts, 1> omega = gating_out.row(kWindowRows - 1).transpose();
  softmax_inplace(omega);

  // Recurrent module: all 11 columns.
  Eigen::Matrix<float, kWindowRows, kRecurrentHidden, Eigen::RowMajor> recurrent_out;
  recurrent.run<kWindowRows>(x, recurrent_out);
  const Eigen::Matrix<float, kRecurrentHidden, 1> z = recurrent_out.row(kWindowRows - 1).transpose();

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
