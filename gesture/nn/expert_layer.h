#pragma once
// One layer of the authors' mixture of experts (model.py: w_l1 [experts, in, out], b_l1
// [experts, out]): y = x·(Σ_e ω_e W_e) + Σ_e ω_e b_e. The weights are stored [e, in, out] and
// multiply from the right (x·W), unlike nn.Linear.
//
// We blend the experts' *outputs* instead of their weights: Σ_e ω_e (x·W_e + b_e) is the same
// value (both are linear in ω), costs one pass over the weights instead of two, and needs no
// per-call weight buffer. load() re-lays the weights out so that all experts' outputs are one
// long product, stored as contiguous panels of outputs (panel_order.h): a matrix–vector product
// for one person, a matrix product for a batch of people (batch.h), with the same bits per person.

#include <array>
#include <string>

#include "gesture/nn/activations.h"
#include "gesture/nn/batch.h"
#include "gesture/nn/lanewise_math.h"
#include "gesture/nn/panel_order.h"
#include "gesture/nn/params.h"

namespace deixis::nn {

template <int Experts, int In, int Out>
struct ExpertLayer {
  static constexpr int kAll = Experts * Out;  // outputs of all experts, expert-major
  static constexpr int kPanel = panel_width(kAll);
  static constexpr int kPanels = kAll / kPanel;

  // Panel p is an In × kPanel row-major block: the weights of outputs [p·kPanel, (p+1)·kPanel).
  AlignedFloats panels = AlignedFloats(static_cast<std::size_t>(In) * kAll);
  MatrixParam<Out, Experts> bias;  // column e: expert e's bias
  // The same biases expert by expert (expert e's at e·Out), for run_batch's blend.
  AlignedFloats bias_by_expert = AlignedFloats(static_cast<std::size_t>(kAll));

  void load(const SafetensorsFile& file, const std::string& weight_name,
            const std::string& bias_name) {
    AlignedFloats stacked(static_cast<std::size_t>(Experts) * In * Out);
    const std::int64_t weight_shape[] = {Experts, In, Out};
    file.copy_f32(weight_name, weight_shape, stacked);
    // Output column j = e·Out + o of the concatenated experts lives in panel j / kPanel.
    for (int e = 0; e < Experts; ++e) {
      for (int i = 0; i < In; ++i) {
        for (int o = 0; o < Out; ++o) {
          const int j = e * Out + o;
          panels[(static_cast<std::size_t>(j / kPanel) * In + i) * kPanel + j % kPanel] =
              stacked[(static_cast<std::size_t>(e) * In + i) * Out + o];
        }
      }
    }
    AlignedFloats b(static_cast<std::size_t>(Experts) * Out);
    const std::int64_t bias_shape[] = {Experts, Out};
    file.copy_f32(bias_name, bias_shape, b);
    auto bias_dst = bias.storage();
    for (int e = 0; e < Experts; ++e) {
      for (int o = 0; o < Out; ++o) {
        bias_dst[static_cast<std::size_t>(o) * Experts + e] =
            b[static_cast<std::size_t>(e) * Out + o];
      }
    }
    bias_by_expert.assign(b.begin(), b.end());
  }

  // y = Σ_e ω_e (x·W_e + b_e) for one input (AMNet's per-row experts). `reverse` visits the panels
  // last to first (same result; panel_order.h).
  template <typename InputVector, typename OmegaVector>
  Eigen::Matrix<float, Out, 1> run(const InputVector& x, const OmegaVector& omega,
                                   bool reverse = false) const {
    using Panel = Eigen::Matrix<float, In, kPanel, Eigen::RowMajor>;
    Eigen::Matrix<float, kAll, 1> all;  // x·W_e for every expert, expert-major
    for (int k = 0; k < kPanels; ++k) {
      const int p = reverse ? kPanels - 1 - k : k;
      const Eigen::Map<const Panel, Eigen::AlignedMax> panel(
          panels.data() + static_cast<std::size_t>(p) * In * kPanel);
      all.template segment<kPanel>(p * kPanel).noalias() = panel.transpose() * x;
    }
    const Eigen::Map<const Eigen::Matrix<float, Out, Experts>> per_expert(all.data());
    Eigen::Matrix<float, Out, 1> y;
    y.noalias() = per_expert * omega;
    y.noalias() += bias.view() * omega;
    return y;
  }

  // y = Σ_e ω_e (x·W_e + b_e) for `count` people (batch.h): row r of y (count × Out, rows
  // contiguous) = Σ_e ω_r,e (x_r·W_e + b_e), with x_r at x + r·ldx and ω_r at omega + r·Experts.
  // All experts' products for the whole batch are one matrix product per panel, each panel read
  // once for everyone; then each person's experts are blended with their own ω. `all` is working
  // memory of count × kAll floats.
  void run_batch(const float* x, std::size_t ldx, const float* omega, int count, float* all,
                 float* y, bool reverse = false) const noexcept {
    for (int k = 0; k < kPanels; ++k) {
      const int p = reverse ? kPanels - 1 - k : k;
      multiply_rows(x, ldx, panels.data() + static_cast<std::size_t>(p) * In * kPanel, kPanel,
                    all + p * kPanel, kAll, count, In, kPanel);
    }
    for (int r = 0; r < count; ++r) {
      blend(all + static_cast<std::size_t>(r) * kAll, omega + static_cast<std::size_t>(r) * Experts,
            y + static_cast<std::size_t>(r) * Out);
    }
  }

  // One person's y = Σ_e ω_e·(x·W_e) + Σ_e ω_e·b_e from every expert's x·W_e (`all`, expert
  // by expert): each sum a chain of multiply-adds over the experts in order, whole rows of
  // outputs at a time. Written out rather than two of Eigen's matrix-vector products, whose
  // general kernel took 0.5 µs a person of the 64-person tick for these 9-column products
  // (decision 92).
  void blend(const float* all_of_person, const float* omega, float* y) const noexcept {
    // Blocks of up to 48 outputs, whose two sums stay in registers over the experts.
    constexpr int kBlock = Out % 48 == 0 ? 48 : Out;
    for (int first = 0; first < Out; first += kBlock) {
      std::array<float, kBlock> experts{}, biases{};
      for (int e = 0; e < Experts; ++e) {
        const float w = omega[e];
        const std::size_t at = static_cast<std::size_t>(e) * Out + static_cast<std::size_t>(first);
        const float* column = all_of_person + at;
        const float* b = bias_by_expert.data() + at;
        for (int o = 0; o < kBlock; ++o) {
          experts[o] = lanewise::multiply_add(w, column[o], experts[o]);
          biases[o] = lanewise::multiply_add(w, b[o], biases[o]);
        }
      }
      for (int o = 0; o < kBlock; ++o) {
        y[first + o] = experts[o] + biases[o];
      }
    }
  }
};

// The MoE networks' three expert layers with ELU between, for `count` people
// (ExpertLayer::run_batch): x (count × In, row r at x + r·ldx) → y (count × Out). `all`, `h1` and
// `h2` are working memory of count × (the largest layer's kAll), count × Hidden and count × Hidden
// floats.
template <int Experts, int In, int Hidden, int Out>
void run_experts_batch(const ExpertLayer<Experts, In, Hidden>& l1,
                       const ExpertLayer<Experts, Hidden, Hidden>& l2,
                       const ExpertLayer<Experts, Hidden, Out>& l3, const float* x, std::size_t ldx,
                       const float* omega, int count, float* all, float* h1, float* h2, float* y,
                       bool reverse = false) noexcept {
  using Rows = Eigen::Matrix<float, Eigen::Dynamic, Hidden, Eigen::RowMajor>;
  l1.run_batch(x, ldx, omega, count, all, h1, reverse);
  Eigen::Map<Rows> a1(h1, count, Hidden);
  elu_inplace(a1);
  l2.run_batch(h1, Hidden, omega, count, all, h2, reverse);
  Eigen::Map<Rows> a2(h2, count, Hidden);
  elu_inplace(a2);
  l3.run_batch(h2, Hidden, omega, count, all, y, reverse);
}

}  // namespace deixis::nn
