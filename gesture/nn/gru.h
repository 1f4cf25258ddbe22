#pragma once
// One layer of a PyTorch nn.GRU with fixed sizes, run over a whole window.
//
// Gate order in the stacked weights is PyTorch's r | z | n, and b_hn sits *inside* the reset
// product (torch.nn.GRU, docs/conventions.md#grus):
//   r = σ(W_ir x + b_ir + W_hr h + b_hr)      z = σ(W_iz x + b_iz + W_hz h + b_hz)
//   n = tanh(W_in x + b_in + r ⊙ (W_hn h + b_hn))      h' = (1 − z) ⊙ n + z ⊙ h
// The authors' GRUs are not stateful: every call starts from h = 0 and runs over all rows of the
// window (docs/conventions.md#grus), so a layer has weights and no state.

#include <string>

#include "gesture/nn/activations.h"
#include "gesture/nn/batch.h"
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

  // One recurrence step of `count` people: row r of h (count × Hidden, rows contiguous) ←
  // GRU(h_r, x_r) given x_r's input projection at gi + r·ldgi. `gh` is working memory of
  // count × 3·Hidden floats.
  void step_batch(const float* gi, std::size_t ldgi, float* h, float* gh,
                  int count) const noexcept {
    multiply_rows(h, Hidden, weight_hh_by_column.storage().data(), kGates, gh, kGates, count,
                  Hidden, kGates);
    for (int r = 0; r < count; ++r) {
      Eigen::Map<Eigen::Matrix<float, kGates, 1>> ghr(gh + static_cast<std::size_t>(r) * kGates);
      ghr += bias_hh.view();
      gates(Eigen::Map<const Eigen::Matrix<float, kGates, 1>>(gi + r * ldgi), ghr,
            Eigen::Map<State>(h + static_cast<std::size_t>(r) * Hidden));
    }
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
// `gh` are working memory of count × 3·Hidden floats each.
template <int In, int Hidden>
void step_two_layers_batch(const GruLayer<In, Hidden>& layer0,
                           const GruLayer<Hidden, Hidden>& layer1, const float* gi0,
                           std::size_t ldgi0, float* h0, float* h1, float* gi1, float* gh,
                           int count) noexcept {
  layer0.step_batch(gi0, ldgi0, h0, gh, count);
  layer1.project_inputs_batch(h0, Hidden, count, gi1);
  layer1.step_batch(gi1, 3 * Hidden, h1, gh, count);
}

}  // namespace deixis::nn
