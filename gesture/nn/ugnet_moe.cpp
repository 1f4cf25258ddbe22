#include <algorithm>

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

namespace deixis::nn {
namespace {

// The working memory of a batch of `count` windows, in BatchBuffers' slots (one layout for
// run_batch and reserve_batch).
struct UgnetBatchMemory {
  static constexpr int kExperts = UgnetMoe::kExperts;
  static constexpr int kHidden = UgnetMoe::kHidden;
  float* gi_gating;     // count·30 × 27: gating layer 1's input projections, window by window
  float* gi_gating_l1;  // count × 27: gating layer 2's input projection of this step
  float* gh;            // count × 27: hidden projections of the step being taken
  float* gating_h0;     // count × 9
  float* omega;         // count × 9: gating layer 2's state, then its softmax
  float* condition;     // count × 264
  float* all;           // count × 9·144: every expert's outputs of one layer
  float* h1;            // count × 144
  float* h2;            // count × 144

  UgnetBatchMemory(BatchBuffers& buffers, int count) {
    const auto n = static_cast<std::size_t>(count);
    gi_gating = buffers.get(0, n * kWindowRows * 3 * kExperts).data();
    gi_gating_l1 = buffers.get(1, n * 3 * kExperts).data();
    gh = buffers.get(2, n * 3 * kExperts).data();
    gating_h0 = buffers.get(3, n * kExperts).data();
    omega = buffers.get(4, n * kExperts).data();
    condition = buffers.get(5, n * kConditionSize).data();
    all = buffers.get(6, n * kExperts * kHidden).data();
    h1 = buffers.get(7, n * kHidden).data();
    h2 = buffers.get(8, n * kHidden).data();
  }
};

}  // namespace

void UgnetMoe::reserve_batch(int count, BatchBuffers& buffers) {
  const UgnetBatchMemory sized(buffers, count);
}

void UgnetMoe::run_batch(const float* windows, int count, float* out, BatchBuffers& buffers) const {
  if (count <= 0) {
    return;
  }
  const UgnetBatchMemory m(buffers, count);
  const auto n = static_cast<std::size_t>(count);
  // The gating network over every window's conditioning columns: rows of consecutive windows are
  // consecutive, so all are projected at once, then everyone's GRUs step together.
  gating_l0.project_inputs_batch(windows + kPoseSize, kUgnetColumns, count * kWindowRows,
                                 m.gi_gating);
  std::fill_n(m.gating_h0, n * kExperts, 0.0f);
  std::fill_n(m.omega, n * kExperts, 0.0f);
  constexpr std::size_t kGatingStride = kWindowRows * 3 * kExperts;
  for (int t = 0; t < kWindowRows; ++t) {
    step_two_layers_batch(gating_l0, gating_l1, m.gi_gating + t * 3 * kExperts, kGatingStride,
                          m.gating_h0, m.omega, m.gi_gating_l1, m.gh, count);
  }
  for (std::size_t r = 0; r < n; ++r) {
    Eigen::Map<Eigen::Matrix<float, kExperts, 1>> omega(m.omega + r * kExperts);
    softmax_inplace(omega);
    Eigen::Map<ConditionVector>(m.condition + r * kConditionSize) =
        condition_vector(UgnetWindow(windows + r * kUgnetWindowSize, kUgnetWindowSize));
  }

  run_experts_batch(expert_l1, expert_l2, expert_l3, m.condition, kConditionSize, m.omega, count,
                    m.all, m.h1, m.h2, out);
}

}  // namespace deixis::nn
