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

}  // namespace deixis::nn

namespace deixis::nn {
namespace {

// Floats of gate working memory the GRUs of a batch of `count` need (GruLayer::step_batch).
constexpr std::size_t gate_work_floats(int count) {
  return decltype(UgnetMoe::gating_l0)::gate_work_floats(count);
}

// The working memory of a batch of `count` windows, in BatchBuffers' slots (one layout for
// run_batch and reserve_batch). A batch's whole groups of sixteen run the gating GRUs with
// people in lanes (decision 92) in the `lanes` buffers, the rest as rows.
struct UgnetBatchMemory {
  static constexpr int kExperts = UgnetMoe::kExperts;
  static constexpr int kHidden = UgnetMoe::kHidden;
  // The people as rows, `rows` of them (count in run(), the rest past the lanes in a batch).
  float* gi_gating;     // rows·30 × 27: gating layer 1's input projections, window by window
  float* gi_gating_l1;  // rows × 27: gating layer 2's input projection of this step
  float* gh;            // rows × 27: hidden projections of the step being taken
  float* gating_h0;     // rows × 9
  float* gate_work;     // their gates (GruLayer::step_batch)
  // Everyone's.
  float* omega;      // count × 9: gating layer 2's state, then its softmax
  float* condition;  // count × 264
  float* all;        // count × 9·144: every expert's outputs of one layer
  float* h1;         // count × 144
  float* h2;         // count × 144

  // The people in lanes, people_in_lanes(count) of them: every array that wide
  // (GruLayer::step_lanes).
  struct Lanes {
    int width = 0;
    float* x = nullptr;             // 8 × width: the step's conditioning columns
    float* gi_gating = nullptr;     // 27 × width: their projections
    float* gi_gating_l1 = nullptr;  // 27 × width
    float* gh = nullptr;            // 27 × width
    float* gating_h0 = nullptr;     // 9 × width
    float* omega = nullptr;         // 9 × width
  } lanes;

  // One window's memory, on the stack (run()).
  struct Lone {
    std::array<float, kWindowRows * 3 * kExperts> gi_gating;
    std::array<float, 3 * kExperts> gi_gating_l1, gh;
    std::array<float, kExperts> gating_h0, omega;
    std::array<float, kConditionSize> condition;
    std::array<float, kExperts * kHidden> all;
    std::array<float, kHidden> h1, h2;
    alignas(EIGEN_MAX_ALIGN_BYTES) std::array<float, gate_work_floats(1)> gate_work;
  };

  explicit UgnetBatchMemory(Lone& lone)
      : gi_gating(lone.gi_gating.data()),
        gi_gating_l1(lone.gi_gating_l1.data()),
        gh(lone.gh.data()),
        gating_h0(lone.gating_h0.data()),
        gate_work(lone.gate_work.data()),
        omega(lone.omega.data()),
        condition(lone.condition.data()),
        all(lone.all.data()),
        h1(lone.h1.data()),
        h2(lone.h2.data()) {}

  UgnetBatchMemory(BatchBuffers& buffers, int count) {
    const auto n = static_cast<std::size_t>(count);
    const int in_lanes = people_in_lanes(count);
    const auto as_rows = static_cast<std::size_t>(count - in_lanes);
    gi_gating = buffers.get(0, as_rows * kWindowRows * 3 * kExperts).data();
    gi_gating_l1 = buffers.get(1, as_rows * 3 * kExperts).data();
    gh = buffers.get(2, as_rows * 3 * kExperts).data();
    gating_h0 = buffers.get(3, as_rows * kExperts).data();
    omega = buffers.get(4, n * kExperts).data();
    condition = buffers.get(5, n * kConditionSize).data();
    all = buffers.get(6, n * kExperts * kHidden).data();
    h1 = buffers.get(7, n * kHidden).data();
    h2 = buffers.get(8, n * kHidden).data();
    gate_work = buffers.get(9, gate_work_floats(static_cast<int>(as_rows))).data();
    if (in_lanes > 0) {
      lanes.width = in_lanes;
      const auto width = static_cast<std::size_t>(lanes.width);
      lanes.x = buffers.get(12, kConditionColumns * width).data();
      lanes.gi_gating = buffers.get(13, 3 * kExperts * width).data();
      lanes.gi_gating_l1 = buffers.get(15, 3 * kExperts * width).data();
      lanes.gh = buffers.get(16, 3 * kExperts * width).data();
      lanes.gating_h0 = buffers.get(17, kExperts * width).data();
      lanes.omega = buffers.get(18, kExperts * width).data();
    }
  }
};

// The gating network over `count` windows' conditioning columns with people as rows: omega
// (count × 9) ← its last state; the rest of m is working memory. Rows of consecutive windows are
// consecutive, so all are projected at once, then everyone's GRUs step together.
void run_gating_by_rows(const UgnetMoe& net, const float* windows, int count,
                        const UgnetBatchMemory& m, float* omega) {
  constexpr int kExperts = UgnetMoe::kExperts;
  const auto n = static_cast<std::size_t>(count);
  net.gating_l0.project_inputs_batch(windows + kPoseSize, kUgnetColumns, count * kWindowRows,
                                     m.gi_gating);
  std::fill_n(m.gating_h0, n * kExperts, 0.0f);
  std::fill_n(omega, n * kExperts, 0.0f);
  constexpr std::size_t kGatingStride = kWindowRows * 3 * kExperts;
  for (int t = 0; t < kWindowRows; ++t) {
    step_two_layers_batch(net.gating_l0, net.gating_l1, m.gi_gating + t * 3 * kExperts,
                          kGatingStride, m.gating_h0, omega, m.gi_gating_l1, m.gh, m.gate_work,
                          count);
  }
}

// The same for the first m.lanes.width windows with people in lanes (decision 92), into their
// rows of m.omega.
void run_gating_in_lanes(const UgnetMoe& net, const float* windows, const UgnetBatchMemory& m) {
  constexpr int kExperts = UgnetMoe::kExperts;
  const UgnetBatchMemory::Lanes& l = m.lanes;
  const auto width = static_cast<std::size_t>(l.width);
  std::fill_n(l.gating_h0, kExperts * width, 0.0f);
  std::fill_n(l.omega, kExperts * width, 0.0f);
  for (int t = 0; t < kWindowRows; ++t) {
    window_row_to_lanes(windows, kUgnetWindowSize,
                        static_cast<std::size_t>(t) * kUgnetColumns + kPoseSize, kConditionColumns,
                        l.width, l.x);
    net.gating_l0.project_inputs_lanes(l.x, width, l.width, l.gi_gating, width);
    step_two_layers_lanes(net.gating_l0, net.gating_l1, l.gi_gating, l.gating_h0, l.omega,
                          l.gi_gating_l1, l.gh, l.width);
  }
  lanes_to_rows(l.omega, kExperts, l.width, l.width, m.omega);
}

// The whole network on `count` windows in `m`. The same code runs one window (run()) and a batch
// (run_batch()), and nn/batch.h's products give a row the same bits in either, so a person's
// prediction does not depend on who else is in the batch. `reverse`: panel_order.h.
void run_moe(const UgnetMoe& net, const float* windows, int count, float* out,
             const UgnetBatchMemory& m, bool reverse) {
  constexpr int kExperts = UgnetMoe::kExperts;
  const auto n = static_cast<std::size_t>(count);
  // Whole groups of sixteen people in lanes, the rest as rows: the same bits either way.
  const int in_lanes = m.lanes.width;
  if (in_lanes > 0) {
    run_gating_in_lanes(net, windows, m);
  }
  if (in_lanes < count) {
    const auto first = static_cast<std::size_t>(in_lanes);
    run_gating_by_rows(net, windows + first * kUgnetWindowSize, count - in_lanes, m,
                       m.omega + first * kExperts);
  }
  for (std::size_t r = 0; r < n; ++r) {
    Eigen::Map<Eigen::Matrix<float, kExperts, 1>> omega(m.omega + r * kExperts);
    softmax_inplace(omega);
    Eigen::Map<ConditionVector>(m.condition + r * kConditionSize) =
        condition_vector(UgnetWindow(windows + r * kUgnetWindowSize, kUgnetWindowSize));
  }

  run_experts_batch(net.expert_l1, net.expert_l2, net.expert_l3, m.condition, kConditionSize,
                    m.omega, count, m.all, m.h1, m.h2, out, reverse);
}

}  // namespace

PoseVector UgnetMoe::run(UgnetWindow window, UgnetTrace* trace) const {
  UgnetBatchMemory::Lone lone;
  PoseVector out;
  run_moe(*this, window.data(), 1, out.data(), UgnetBatchMemory(lone),
          panel_order.next_is_reversed());
  if (trace != nullptr) {
    std::copy(lone.omega.begin(), lone.omega.end(), trace->omega.begin());
  }
  return out;
}

void UgnetMoe::reserve_batch(int count, BatchBuffers& buffers) {
  // Both layouts: smaller batches later run as rows.
  const UgnetBatchMemory by_rows(buffers, std::min(count, kLaneGroup - 1));
  const UgnetBatchMemory sized(buffers, count);
}

void UgnetMoe::run_batch(const float* windows, int count, float* out, BatchBuffers& buffers) const {
  if (count <= 0) {
    return;
  }
  run_moe(*this, windows, count, out, UgnetBatchMemory(buffers, count),
          panel_order.next_is_reversed());
}

}  // namespace deixis::nn
