#include <algorithm>

#include "gesture/nn/mpnet_architectures.h"

namespace deixis::nn {

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

namespace {

// Floats of gate working memory the GRUs of a batch of `count` need (GruLayer::step_batch).
constexpr std::size_t gate_work_floats(int count) {
  return std::max(decltype(MpnetGruMoe::gating_l0)::gate_work_floats(count),
                  decltype(MpnetGruMoe::recurrent)::gate_work_floats(count));
}

// The working memory of a batch of `count` windows, in BatchBuffers' slots (one layout for
// run_batch and reserve_batch). A batch's whole groups of sixteen run the GRUs with people in
// lanes (decision 92) in the `lanes` buffers, the rest as rows.
struct MpnetBatchMemory {
  static constexpr int kExperts = MpnetGruMoe::kExperts;
  static constexpr int kHidden = MpnetGruMoe::kRecurrentHidden;
  // The people as rows, `rows` of them (count in run(), the rest past the lanes in a batch).
  float* gi_gating;     // rows·30 × 27: gating layer 1's input projections, window by window
  float* gi_recurrent;  // rows·30 × 72
  float* gi_gating_l1;  // rows × 27: gating layer 2's input projection of this step
  float* gh;            // rows × 72: hidden projections of the step being taken
  float* gating_h0;     // rows × 9
  float* gate_work;     // their gates (GruLayer::step_batch), the wider layer's size
  // Everyone's.
  float* omega;  // count × 9: gating layer 2's state, then its softmax
  float* z;      // count × 24: the recurrent module's state
  float* all;    // count × 108: every expert's outputs of one layer
  float* h1;     // count × 12
  float* h2;     // count × 12
  float* y;      // count × 3

  // The people in lanes, people_in_lanes(count) of them: every array that wide
  // (GruLayer::step_lanes).
  struct Lanes {
    int width = 0;
    float* x = nullptr;             // 11 × width: the step's inputs
    float* gi_gating = nullptr;     // 27 × width: the step's input projections
    float* gi_recurrent = nullptr;  // 72 × width
    float* gi_gating_l1 = nullptr;  // 27 × width
    float* gh = nullptr;            // 72 × width
    float* gating_h0 = nullptr;     // 9 × width
    float* omega = nullptr;         // 9 × width
    float* z = nullptr;             // 24 × width
  } lanes;

  // One window's memory, on the stack (run()).
  struct Lone {
    std::array<float, kWindowRows * 3 * kExperts> gi_gating;
    std::array<float, kWindowRows * 3 * kHidden> gi_recurrent;
    std::array<float, 3 * kExperts> gi_gating_l1;
    std::array<float, 3 * kHidden> gh;
    std::array<float, kExperts> gating_h0, omega;
    std::array<float, kHidden> z;
    std::array<float, kExperts * MpnetGruMoe::kExpertHidden> all;
    std::array<float, MpnetGruMoe::kExpertHidden> h1, h2;
    std::array<float, kProgressionSize> y;
    alignas(EIGEN_MAX_ALIGN_BYTES) std::array<float, gate_work_floats(1)> gate_work;
  };

  explicit MpnetBatchMemory(Lone& lone)
      : gi_gating(lone.gi_gating.data()),
        gi_recurrent(lone.gi_recurrent.data()),
        gi_gating_l1(lone.gi_gating_l1.data()),
        gh(lone.gh.data()),
        gating_h0(lone.gating_h0.data()),
        gate_work(lone.gate_work.data()),
        omega(lone.omega.data()),
        z(lone.z.data()),
        all(lone.all.data()),
        h1(lone.h1.data()),
        h2(lone.h2.data()),
        y(lone.y.data()) {}

  MpnetBatchMemory(BatchBuffers& buffers, int count) {
    const auto n = static_cast<std::size_t>(count);
    const int in_lanes = people_in_lanes(count);
    const auto as_rows = static_cast<std::size_t>(count - in_lanes);
    const auto rows = as_rows * kWindowRows;
    gi_gating = buffers.get(0, rows * 3 * kExperts).data();
    gi_recurrent = buffers.get(1, rows * 3 * kHidden).data();
    gi_gating_l1 = buffers.get(2, as_rows * 3 * kExperts).data();
    gh = buffers.get(3, as_rows * 3 * kHidden).data();
    gating_h0 = buffers.get(4, as_rows * kExperts).data();
    omega = buffers.get(5, n * kExperts).data();
    z = buffers.get(6, n * kHidden).data();
    all = buffers.get(7, n * kExperts * MpnetGruMoe::kExpertHidden).data();
    h1 = buffers.get(8, n * MpnetGruMoe::kExpertHidden).data();
    h2 = buffers.get(9, n * MpnetGruMoe::kExpertHidden).data();
    y = buffers.get(10, n * kProgressionSize).data();
    gate_work = buffers.get(11, gate_work_floats(static_cast<int>(as_rows))).data();
    if (in_lanes > 0) {
      lanes.width = in_lanes;
      const auto width = static_cast<std::size_t>(lanes.width);
      lanes.x = buffers.get(12, kMpnetFeatures * width).data();
      lanes.gi_gating = buffers.get(13, 3 * kExperts * width).data();
      lanes.gi_recurrent = buffers.get(14, 3 * kHidden * width).data();
      lanes.gi_gating_l1 = buffers.get(15, 3 * kExperts * width).data();
      lanes.gh = buffers.get(16, 3 * kHidden * width).data();
      lanes.gating_h0 = buffers.get(17, kExperts * width).data();
      lanes.omega = buffers.get(18, kExperts * width).data();
      lanes.z = buffers.get(19, kHidden * width).data();
    }
  }
};

// The three GRUs over `count` windows with people as rows: omega (count × 9) ← the gating
// network's last state, z (count × 24) ← the recurrent module's; the rest of m is working memory.
void run_grus_by_rows(const MpnetGruMoe& net, const float* windows, int count,
                      const MpnetBatchMemory& m, float* omega, float* z) {
  constexpr int kExperts = MpnetGruMoe::kExperts;
  constexpr int kHidden = MpnetGruMoe::kRecurrentHidden;
  const auto n = static_cast<std::size_t>(count);
  // The gating network (2-layer GRU over the target feature) and the recurrent module (GRU over
  // all 11 columns) are independent recurrences; stepping them in one loop lets the CPU overlap
  // their dependency chains. Every row of every window is projected at once: rows of
  // consecutive windows are consecutive.
  net.gating_l0.project_inputs_batch(windows + kMpnetTargetColumn, kMpnetFeatures,
                                     count * kWindowRows, m.gi_gating);
  net.recurrent.project_inputs_batch(windows, kMpnetFeatures, count * kWindowRows, m.gi_recurrent);
  std::fill_n(m.gating_h0, n * kExperts, 0.0f);
  std::fill_n(omega, n * kExperts, 0.0f);
  std::fill_n(z, n * kHidden, 0.0f);
  constexpr std::size_t kGatingStride = kWindowRows * 3 * kExperts;
  constexpr std::size_t kRecurrentStride = kWindowRows * 3 * kHidden;
  for (int t = 0; t < kWindowRows; ++t) {
    step_two_layers_batch(net.gating_l0, net.gating_l1, m.gi_gating + t * 3 * kExperts,
                          kGatingStride, m.gating_h0, omega, m.gi_gating_l1, m.gh, m.gate_work,
                          count);
    net.recurrent.step_batch(m.gi_recurrent + t * 3 * kHidden, kRecurrentStride, z, m.gh,
                             m.gate_work, count);
  }
}

// The same for the first m.lanes.width windows with people in lanes (decision 92): each step's
// inputs gathered into lanes and projected, the step taken on whole rows of people (everything a
// step touches stays in the L1 cache), the last states turned back into rows of m.omega and m.z.
void run_grus_in_lanes(const MpnetGruMoe& net, const float* windows, const MpnetBatchMemory& m) {
  constexpr int kExperts = MpnetGruMoe::kExperts;
  constexpr int kHidden = MpnetGruMoe::kRecurrentHidden;
  const MpnetBatchMemory::Lanes& l = m.lanes;
  const auto width = static_cast<std::size_t>(l.width);
  std::fill_n(l.gating_h0, kExperts * width, 0.0f);
  std::fill_n(l.omega, kExperts * width, 0.0f);
  std::fill_n(l.z, kHidden * width, 0.0f);
  for (int t = 0; t < kWindowRows; ++t) {
    window_row_to_lanes(windows, kMpnetWindowSize, static_cast<std::size_t>(t) * kMpnetFeatures,
                        kMpnetFeatures, l.width, l.x);
    net.gating_l0.project_inputs_lanes(l.x + kMpnetTargetColumn * width, width, l.width,
                                       l.gi_gating, width);
    net.recurrent.project_inputs_lanes(l.x, width, l.width, l.gi_recurrent, width);
    step_two_layers_lanes(net.gating_l0, net.gating_l1, l.gi_gating, l.gating_h0, l.omega,
                          l.gi_gating_l1, l.gh, l.width);
    net.recurrent.step_lanes(l.gi_recurrent, l.z, l.gh, l.width);
  }
  lanes_to_rows(l.omega, kExperts, l.width, l.width, m.omega);
  lanes_to_rows(l.z, kHidden, l.width, l.width, m.z);
}

// The whole network on `count` windows in `m`. The same code runs one window (run()) and a batch
// (run_batch()), and nn/batch.h's products give a row the same bits in either layout, so a
// person's progression does not depend on who else is in the batch.
void run_moe(const MpnetGruMoe& net, const float* windows, int count, MpnetOutput* out,
             const MpnetBatchMemory& m) {
  constexpr int kExperts = MpnetGruMoe::kExperts;
  constexpr int kHidden = MpnetGruMoe::kRecurrentHidden;
  const auto n = static_cast<std::size_t>(count);
  // Whole groups of sixteen people in lanes, the rest as rows: the same bits either way.
  const int in_lanes = m.lanes.width;
  if (in_lanes > 0) {
    run_grus_in_lanes(net, windows, m);
  }
  if (in_lanes < count) {
    const auto first = static_cast<std::size_t>(in_lanes);
    run_grus_by_rows(net, windows + first * kMpnetWindowSize, count - in_lanes, m,
                     m.omega + first * kExperts, m.z + first * kHidden);
  }
  for (std::size_t r = 0; r < n; ++r) {
    Eigen::Map<Eigen::Matrix<float, kExperts, 1>> omega(m.omega + r * kExperts);
    softmax_inplace(omega);
  }
  run_experts_batch(net.expert_l1, net.expert_l2, net.expert_l3, m.z, kHidden, m.omega, count,
                    m.all, m.h1, m.h2, m.y);
  for (std::size_t r = 0; r < n; ++r) {
    out[r] = clamp_progression(
        Eigen::Map<const Eigen::Matrix<float, kProgressionSize, 1>>(m.y + r * kProgressionSize));
  }
}

}  // namespace

MpnetOutput MpnetGruMoe::run(MpnetWindow window, MpnetTrace* trace) const {
  MpnetBatchMemory::Lone lone;
  const MpnetBatchMemory m(lone);
  MpnetOutput out;
  run_moe(*this, window.data(), 1, &out, m);
  if (trace != nullptr) {
    std::copy(lone.omega.begin(), lone.omega.end(), trace->omega.begin());
    std::copy(lone.z.begin(), lone.z.end(), trace->z.begin());
  }
  return out;
}

void MpnetGruMoe::reserve_batch(int count, BatchBuffers& buffers) {
  // Both layouts: smaller batches later run as rows.
  const MpnetBatchMemory by_rows(buffers, std::min(count, kLaneGroup - 1));
  const MpnetBatchMemory sized(buffers, count);
}

void MpnetGruMoe::run_batch(const float* windows, int count, MpnetOutput* out,
                            BatchBuffers& buffers) const {
  if (count <= 0) {
    return;
  }
  run_moe(*this, windows, count, out, MpnetBatchMemory(buffers, count));
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
