#pragma once
// One layer of a PyTorch nn.GRU with fixed sizes, run over a whole window.
//
// Gate order in the stacked weights is PyTorch's r | z | n, and b_hn sits *inside* the reset
// product (torch.nn.GRU, docs/conventions.md#grus):
//   r = σ(W_ir x + b_ir + W_hr h + b_hr)      z = σ(W_iz x + b_iz + W_hz h + b_hz)
//   n = tanh(W_in x + b_in + r ⊙ (W_hn h + b_hn))      h' = (1 − z) ⊙ n + z ⊙ h
// The authors' GRUs are not stateful: every call starts from h = 0 and runs over all rows of the
// window (docs/conventions.md#grus), so a layer has weights and no state.

#include <cstddef>
#include <string>

#include "gesture/nn/activations.h"
#include "gesture/nn/batch.h"
#include "gesture/nn/gates.h"
#include "gesture/nn/lanewise_math.h"
#include "gesture/nn/params.h"

namespace deixis::nn {

template <int In, int Hidden>
struct GruLayer {
  static constexpr int kGates = 3 * Hidden;
  MatrixParam<kGates, In> weight_ih;
  MatrixParam<kGates, Hidden> weight_hh;
  VectorParam<kGates> bias_ih;
  VectorParam<kGates> bias_hh;
  // The same weights transposed. A step's products are tiny (e.g. 27 × 9); as row-major dot
  // products they need a horizontal sum per row, whereas column by column they are a few
  // vectorised multiply-adds along the 3·Hidden gates.
  MatrixParam<In, kGates> weight_ih_by_column;
  MatrixParam<Hidden, kGates> weight_hh_by_column;

  // `prefix` is e.g. "gru" and `layer` 0 for "gru.weight_ih_l0".
  void load(const SafetensorsFile& file, const std::string& prefix, int layer) {
    const std::string l = "_l" + std::to_string(layer);
    load_matrix(file, prefix + ".weight_ih" + l, weight_ih);
    load_matrix(file, prefix + ".weight_hh" + l, weight_hh);
    load_vector(file, prefix + ".bias_ih" + l, bias_ih);
    load_vector(file, prefix + ".bias_hh" + l, bias_hh);
    transpose_into(weight_ih, weight_ih_by_column);
    transpose_into(weight_hh, weight_hh_by_column);
  }

  using State = Eigen::Matrix<float, Hidden, 1>;  // the hidden state h
  template <int Steps>
  using Projections = Eigen::Matrix<float, Steps, kGates, Eigen::RowMajor>;

  // W_ih·x + b_ih for every row of `inputs` (Steps × In) at once: one matrix product instead of
  // Steps small ones.
  template <int Steps, typename InputMatrix>
  Projections<Steps> project_inputs(const InputMatrix& inputs) const {
    Projections<Steps> gi;
    gi.noalias() = inputs * weight_ih.view().transpose();
    gi.rowwise() += bias_ih.view().transpose();
    return gi;
  }

  // One recurrence step: h ← GRU(h, x) given x's input projection `gi` (3·Hidden).
  template <typename ProjectionRow>
  void step(const ProjectionRow& gi, State& h) const {
    Eigen::Matrix<float, kGates, 1> gh = bias_hh.view();
    gh.noalias() += weight_hh_by_column.view().transpose().lazyProduct(h);
    gates(gi, gh, h);
  }

  // The rest of a step once both projections are known: gi = W_ih·x + b_ih, gh = W_hh·h + b_hh.
  template <typename ProjectionRow, typename HiddenProjection, typename StateVector>
  static void gates(const ProjectionRow& gi, const HiddenProjection& gh, StateVector&& h) {
    // The gates as whole vectors, through Eigen's vectorised logistic and tanh (accurate to a few
    // ulp; PyTorch's own CPU kernels are vectorised approximations too).
    const Eigen::Array<float, 2 * Hidden, 1> rz =
        (gi.template head<2 * Hidden>() + gh.template head<2 * Hidden>()).array().logistic();
    const State n = (gi.template tail<Hidden>().array() +
                     rz.template head<Hidden>() * gh.template tail<Hidden>().array())
                        .tanh()
                        .matrix();
    h = n + (rz.template tail<Hidden>() * (h - n).array()).matrix();
  }

  // Batches (batch.h): `count` people at once, one row each.
  //
  // W_ih·x + b_ih of `count` inputs into gi (count × 3·Hidden, rows contiguous); input r starts
  // at x + r·ldx.
  void project_inputs_batch(const float* x, std::size_t ldx, int count, float* gi) const noexcept {
    multiply_rows(x, ldx, weight_ih_by_column.storage().data(), kGates, gi, kGates, count, In,
                  kGates);
    for (int r = 0; r < count; ++r) {
      Eigen::Map<Eigen::Matrix<float, kGates, 1>>(gi + static_cast<std::size_t>(r) * kGates) +=
          bias_ih.view();
    }
  }

  // Floats of gate working memory step_batch() needs for `count` people (gate_work below).
  static constexpr std::size_t gate_work_floats(int count) noexcept {
    return padded_to_packets(static_cast<std::size_t>(count) * 2 * Hidden) +
           padded_to_packets(static_cast<std::size_t>(count) * Hidden);
  }

  // One recurrence step of `count` people: row r of h (count × Hidden, rows contiguous) ←
  // GRU(h_r, x_r) given x_r's input projection at gi + r·ldgi. `gh` is working memory of
  // count × 3·Hidden floats; `gate_work` of gate_work_floats(count) floats, aligned to
  // EIGEN_MAX_ALIGN_BYTES.
  //
  // The gates are evaluated across the whole batch, one value per lane: everyone's r|z
  // pre-activations side by side through one logistic, everyone's n through one tanh, over
  // buffers padded to whole packets. Each lane's result depends on that lane's value alone (Eigen's
  // packet logistic and tanh select every lane by its own value), and every value goes through
  // the packet operation (gates.h), never Eigen's scalar path, which rounds differently
  // (it has no fused multiply-adds). The multiply-adds around them are
  // explicit (lanewise::multiply_add): left to the compiler, a loop's vectorised body and its
  // scalar remainder were not contracted alike, and a person's bits changed with the batch. So a
  // person's state is bit for bit the same alone and in any batch (docs/decisions.md, decision
  // 90), and the 9-wide gating layers' odd remainders cost no scalar calls.
  void step_batch(const float* gi, std::size_t ldgi, float* h, float* gh, float* gate_work,
                  int count) const noexcept {
    multiply_rows(h, Hidden, weight_hh_by_column.storage().data(), kGates, gh, kGates, count,
                  Hidden, kGates);
    const auto n = static_cast<std::size_t>(count);
    const float* b = bias_hh.view().data();
    float* rz = gate_work;
    float* candidate = gate_work + padded_to_packets(n * 2 * Hidden);
    for (std::size_t r = 0; r < n; ++r) {
      const float* gir = gi + r * ldgi;
      const float* ghr = gh + r * kGates;
      float* rzr = rz + r * 2 * Hidden;
      for (int j = 0; j < 2 * Hidden; ++j) {
        rzr[j] = gir[j] + (ghr[j] + b[j]);
      }
    }
    logistic_in_place(rz, n * 2 * Hidden);
    for (std::size_t r = 0; r < n; ++r) {
      const float* gir = gi + r * ldgi + 2 * Hidden;
      const float* ghr = gh + r * kGates + 2 * Hidden;
      const float* reset = rz + r * 2 * Hidden;
      float* cr = candidate + r * Hidden;
      for (int j = 0; j < Hidden; ++j) {
        cr[j] = lanewise::multiply_add(reset[j], ghr[j] + b[2 * Hidden + j], gir[j]);
      }
    }
    tanh_in_place(candidate, n * Hidden);
    for (std::size_t r = 0; r < n; ++r) {
      const float* update = rz + r * 2 * Hidden + Hidden;
      const float* cr = candidate + r * Hidden;
      float* hr = h + r * Hidden;
      for (int j = 0; j < Hidden; ++j) {
        hr[j] = lanewise::multiply_add(update[j], hr[j] - cr[j], cr[j]);
      }
    }
  }

  // Batches with people in lanes (batch.h, multiply_lanes): value j of person p at v + j·ld + p,
  // `lanes` a multiple of kLaneGroup. The same operations on every value as step_batch's, so a
  // person's bits are the same in either layout (decision 92).
  //
  // gi (3·Hidden × lanes, row j at gi + j·ldgi) = W_ih·x + b_ih for x (In × lanes, row i at
  // x + i·ldx).
  void project_inputs_lanes(const float* x, std::size_t ldx, int lanes, float* gi,
                            std::size_t ldgi) const noexcept {
    multiply_lanes(weight_ih.storage().data(), In, x, ldx, gi, ldgi, kGates, In, lanes,
                   bias_ih.storage().data());
  }

  // One recurrence step of everyone in lanes: h (Hidden × lanes, rows contiguous) ← GRU(h, x)
  // given x's input projection gi (3·Hidden × lanes, rows contiguous). `gh` is working memory of
  // 3·Hidden × lanes floats aligned to EIGEN_MAX_ALIGN_BYTES: W_hh·h + b_hh, then the gates in
  // place, whole rows of people at a time.
  void step_lanes(const float* gi, float* h, float* gh, int lanes) const noexcept {
    const auto ld = static_cast<std::size_t>(lanes);
    multiply_lanes(weight_hh.storage().data(), Hidden, h, ld, gh, ld, kGates, Hidden, lanes,
                   bias_hh.storage().data());
    gru_gates_in_lanes(gi, gh, h, Hidden * ld);
  }

  // Runs over the rows of `inputs` (Steps × In) from h = 0 and writes every step's hidden state
  // to `outputs` (Steps × Hidden); the last row is the layer's final output.
  template <int Steps, typename InputMatrix, typename OutputMatrix>
  void run(const InputMatrix& inputs, OutputMatrix& outputs) const {
    const Projections<Steps> gi = project_inputs<Steps>(inputs);
    State h = State::Zero();
    for (int t = 0; t < Steps; ++t) {
      step(gi.row(t).transpose(), h);
      outputs.row(t) = h.transpose();
    }
  }
};

// One step of a 2-layer GRU for `count` people, layer 2 fed with layer 1's new state (the MoE
// networks' gating): h0 ← layer0(h0, gi0 row r at gi0 + r·ldgi0), h1 ← layer1(h1, h0). `gi1` and
// `gh` are working memory of count × 3·Hidden floats each, `gate_work` GruLayer::step_batch's.
template <int In, int Hidden>
void step_two_layers_batch(const GruLayer<In, Hidden>& layer0,
                           const GruLayer<Hidden, Hidden>& layer1, const float* gi0,
                           std::size_t ldgi0, float* h0, float* h1, float* gi1, float* gh,
                           float* gate_work, int count) noexcept {
  layer0.step_batch(gi0, ldgi0, h0, gh, gate_work, count);
  layer1.project_inputs_batch(h0, Hidden, count, gi1);
  layer1.step_batch(gi1, 3 * Hidden, h1, gh, gate_work, count);
}

// step_two_layers_batch with people in lanes (GruLayer::step_lanes): h0 ← layer0(h0, gi0),
// h1 ← layer1(h1, h0), every array `lanes` wide. `gi1` and `gh` are working memory of
// 3·Hidden × lanes floats each.
template <int In, int Hidden>
void step_two_layers_lanes(const GruLayer<In, Hidden>& layer0,
                           const GruLayer<Hidden, Hidden>& layer1, const float* gi0, float* h0,
                           float* h1, float* gi1, float* gh, int lanes) noexcept {
  const auto ld = static_cast<std::size_t>(lanes);
  layer0.step_lanes(gi0, h0, gh, lanes);
  layer1.project_inputs_lanes(h0, ld, lanes, gi1, ld);
  layer1.step_lanes(gi1, h1, gh, lanes);
}

}  // namespace deixis::nn
