#include "train/fused_gru.h"

#include "train/tensor_maps.h"

#include <torch/autograd.h>
#include <torch/nn/init.h>

#include <Eigen/Core>
#include <cmath>
#include <string>

namespace deixis::train {

namespace {

using Strided = Eigen::Map<RowMatrix, 0, Eigen::OuterStride<>>;
using ConstStrided = Eigen::Map<const RowMatrix, 0, Eigen::OuterStride<>>;

// Saved per time step for backpropagation through time: r, z, n and W_hn·h + b_hn, each
// [batch, hidden], stored as [time, batch, 4·hidden].
enum Saved { kR = 0, kZ = 1, kN = 2, kHn = 3 };

struct GruLayerFunction : public torch::autograd::Function<GruLayerFunction> {
  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, torch::Tensor x,
                               torch::Tensor w_ih, torch::Tensor w_hh, torch::Tensor b_ih,
                               torch::Tensor b_hh) {
    x = x.contiguous();
    w_ih = w_ih.contiguous();
    w_hh = w_hh.contiguous();
    b_ih = b_ih.contiguous();
    b_hh = b_hh.contiguous();
    const Eigen::Index batch = x.size(0), time = x.size(1), input = x.size(2);
    const Eigen::Index hidden = w_hh.size(1), gates = 3 * hidden;

    // Input projections of every step at once: [batch·time, 3H], row b·T + t.
    torch::Tensor xi = torch::empty({batch * time, gates}, x.options());
    map_mut(xi, batch * time, gates).noalias() =
        map(x, batch * time, input) * map(w_ih, gates, input).transpose();
    map_mut(xi, batch * time, gates).rowwise() +=
        Eigen::Map<const Eigen::RowVectorXf>(b_ih.data_ptr<float>(), gates);

    torch::Tensor out = torch::empty({batch, time, hidden}, x.options());
    torch::Tensor saved = torch::empty({time, batch, 4 * hidden}, x.options());
    const ConstMatrixMap whh = map(w_hh, gates, hidden);
    const Eigen::Map<const Eigen::RowVectorXf> bhh(b_hh.data_ptr<float>(), gates);
    // The gates go straight into their saved slots: nothing is allocated per time step.
    RowMatrix h = RowMatrix::Zero(batch, hidden);
    RowMatrix gh(batch, gates);
    for (Eigen::Index t = 0; t < time; ++t) {
      gh.noalias() = h * whh.transpose();
      gh.rowwise() += bhh;
      const ConstStrided xi_t(xi.data_ptr<float>() + t * gates, batch, gates,
                              Eigen::OuterStride<>(time * gates));
      MatrixMap s(saved.data_ptr<float>() + t * batch * 4 * hidden, batch, 4 * hidden);
      auto r = s.middleCols(kR * hidden, hidden).array();
      auto z = s.middleCols(kZ * hidden, hidden).array();
      auto n = s.middleCols(kN * hidden, hidden).array();
      r = Eigen::logistic(xi_t.leftCols(hidden).array() + gh.leftCols(hidden).array());
      z = Eigen::logistic(xi_t.middleCols(hidden, hidden).array() +
                          gh.middleCols(hidden, hidden).array());
      n = (xi_t.rightCols(hidden).array() + r * gh.rightCols(hidden).array()).tanh();
      s.middleCols(kHn * hidden, hidden) = gh.rightCols(hidden);
      h.array() = (1.0f - z) * n + z * h.array();
      Strided(out.data_ptr<float>() + t * hidden, batch, hidden,
              Eigen::OuterStride<>(time * hidden)) = h;
    }
    ctx->save_for_backward({x, w_ih, w_hh, out, saved});
    return out;
  }

  static torch::autograd::tensor_list backward(torch::autograd::AutogradContext* ctx,
                                               torch::autograd::tensor_list grad_outputs) {
    const auto vars = ctx->get_saved_variables();
    const torch::Tensor& x = vars[0];
    const torch::Tensor& w_ih = vars[1];
    const torch::Tensor& w_hh = vars[2];
    const torch::Tensor& out = vars[3];
    const torch::Tensor& saved = vars[4];
    const Eigen::Index batch = x.size(0), time = x.size(1), input = x.size(2);
    const Eigen::Index hidden = w_hh.size(1), gates = 3 * hidden;

    torch::Tensor grad_out =
        grad_outputs[0].defined() ? grad_outputs[0].contiguous() : torch::zeros_like(out);
    torch::Tensor d_xi = torch::empty({batch * time, gates}, x.options());
    torch::Tensor d_w_hh = torch::zeros({gates, hidden}, x.options());
    torch::Tensor d_b_hh = torch::zeros({gates}, x.options());
    const ConstMatrixMap whh = map(w_hh, gates, hidden);
    MatrixMap dwhh = map_mut(d_w_hh, gates, hidden);
    Eigen::Map<Eigen::RowVectorXf> dbhh(d_b_hh.data_ptr<float>(), gates);

    RowMatrix dh = RowMatrix::Zero(batch, hidden);
    RowMatrix h_prev(batch, hidden);
    RowMatrix dgh(batch, gates);
    for (Eigen::Index t = time - 1; t >= 0; --t) {
      dh += ConstStrided(grad_out.data_ptr<float>() + t * hidden, batch, hidden,
                         Eigen::OuterStride<>(time * hidden));
      if (t > 0) {
        h_prev = ConstStrided(out.data_ptr<float>() + (t - 1) * hidden, batch, hidden,
                              Eigen::OuterStride<>(time * hidden));
      } else {
        h_prev.setZero();
      }
      const ConstMatrixMap s(saved.data_ptr<float>() + t * batch * 4 * hidden, batch, 4 * hidden);
      const auto r = s.middleCols(kR * hidden, hidden).array();
      const auto z = s.middleCols(kZ * hidden, hidden).array();
      const auto n = s.middleCols(kN * hidden, hidden).array();
      const auto hn = s.middleCols(kHn * hidden, hidden).array();

      // h = (1 − z)·n + z·h_prev. The three gate gradients are written into dgh's columns
      // (r, z, and n·r for the recurrent product) and d_xi's (r, z, n), no temporaries.
      auto da_r = dgh.leftCols(hidden).array();
      auto da_z = dgh.middleCols(hidden, hidden).array();
      auto da_n = dgh.rightCols(hidden).array();
      da_n = dh.array() * (1.0f - z) * (1.0f - n * n);  // through tanh
      da_z = dh.array() * (h_prev.array() - n) * z * (1.0f - z);
      da_r = da_n * hn * r * (1.0f - r);
      Strided dxi_t(d_xi.data_ptr<float>() + t * gates, batch, gates,
                    Eigen::OuterStride<>(time * gates));
      dxi_t = dgh;
      dgh.rightCols(hidden).array() *= r;

      dwhh.noalias() += dgh.transpose() * h_prev;
      dbhh += dgh.colwise().sum();
      dh = (dh.array() * z).matrix();
      dh.noalias() += dgh * whh;
    }

    const ConstMatrixMap dxi = map(d_xi, batch * time, gates);
    torch::Tensor d_x = torch::empty_like(x);
    map_mut(d_x, batch * time, input).noalias() = dxi * map(w_ih, gates, input);
    torch::Tensor d_w_ih = torch::empty_like(w_ih);
    map_mut(d_w_ih, gates, input).noalias() = dxi.transpose() * map(x, batch * time, input);
    torch::Tensor d_b_ih = torch::empty({gates}, x.options());
    Eigen::Map<Eigen::RowVectorXf>(d_b_ih.data_ptr<float>(), gates) = dxi.colwise().sum();
    return {d_x, d_w_ih, d_w_hh, d_b_ih, d_b_hh};
  }
};

}  // namespace

torch::Tensor gru_layer(const torch::Tensor& x, const torch::Tensor& w_ih,
                        const torch::Tensor& w_hh, const torch::Tensor& b_ih,
                        const torch::Tensor& b_hh) {
  TORCH_CHECK(x.dim() == 3 && x.scalar_type() == torch::kFloat32,
              "gru_layer: x must be float32 "
              "[batch, time, input]");
  return GruLayerFunction::apply(x, w_ih, w_hh, b_ih, b_hh);
}

FusedGruImpl::FusedGruImpl(int input_size, int hidden_size, int layers) : hidden_(hidden_size) {
  // torch.nn.GRU's initialisation: every parameter U(−1/√H, 1/√H).
  const double bound = 1.0 / std::sqrt(static_cast<double>(hidden_size));
  for (int l = 0; l < layers; ++l) {
    const std::int64_t in = l == 0 ? input_size : hidden_size;
    const std::string k = std::to_string(l);
    auto init = [&](const std::string& name, std::vector<std::int64_t> shape) {
      return register_parameter(name + "_l" + k, torch::empty(shape).uniform_(-bound, bound));
    };
    w_ih_.push_back(init("weight_ih", {3 * hidden_size, in}));
    w_hh_.push_back(init("weight_hh", {3 * hidden_size, hidden_size}));
    b_ih_.push_back(init("bias_ih", {3 * hidden_size}));
    b_hh_.push_back(init("bias_hh", {3 * hidden_size}));
  }
}

torch::Tensor FusedGruImpl::forward(const torch::Tensor& x) {
  torch::Tensor h = x;
  for (std::size_t l = 0; l < w_ih_.size(); ++l) {
    h = gru_layer(h, w_ih_[l], w_hh_[l], b_ih_[l], b_hh_[l]);
  }
  return h;
}

}  // namespace deixis::train
