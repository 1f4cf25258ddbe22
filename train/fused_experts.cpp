#include "train/fused_experts.h"

#include "train/tensor_maps.h"

#include <torch/autograd.h>

#include <Eigen/Core>

namespace deixis::train {

namespace {

constexpr int kLayers = 3;

// One layer's shapes.
struct Shape {
  Eigen::Index batch, experts, in, out;
};

Shape shape_of(const torch::Tensor& a, const torch::Tensor& w) {
  return {a.size(0), w.size(0), w.size(1), w.size(2)};
}

// products [experts, batch, out] ← a·W_e + b_e for every expert; returns u = Σ_e ω_e ⊙ products.
torch::Tensor blended_layer(const torch::Tensor& a, const torch::Tensor& omega,
                            const torch::Tensor& w, const torch::Tensor& b,
                            torch::Tensor& products) {
  const Shape s = shape_of(a, w);
  products = torch::empty({s.experts, s.batch, s.out}, a.options());
  torch::Tensor u = torch::zeros({s.batch, s.out}, a.options());
  const ConstMatrixMap in = map(a, s.batch, s.in);
  const ConstMatrixMap weights = map(omega, s.batch, s.experts);
  MatrixMap blended = map_mut(u, s.batch, s.out);
  for (Eigen::Index e = 0; e < s.experts; ++e) {
    MatrixMap p = map_mut(products, s.batch, s.out, e * s.batch * s.out);
    p.noalias() = in * map(w, s.in, s.out, e * s.in * s.out);
    p.rowwise() += Eigen::Map<const Eigen::RowVectorXf>(b.data_ptr<float>() + e * s.out, s.out);
    blended += (p.array().colwise() * weights.col(e).array()).matrix();
  }
  return u;
}

// ELU with α = 1: a = u (u > 0), eᵘ − 1 otherwise.
torch::Tensor elu_of(const torch::Tensor& u) {
  torch::Tensor a = torch::empty_like(u);
  const auto in = map(u, u.size(0), u.size(1)).array();
  map_mut(a, u.size(0), u.size(1)).array() = (in > 0.0f).select(in, in.exp() - 1.0f);
  return a;
}

struct ExpertLayersFunction : public torch::autograd::Function<ExpertLayersFunction> {
  // Saved: x, ω, W₁..W₃, the per-expert products of each layer and the ELU outputs a₁, a₂.
  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, torch::Tensor x,
                               torch::Tensor omega, torch::Tensor w1, torch::Tensor b1,
                               torch::Tensor w2, torch::Tensor b2, torch::Tensor w3,
                               torch::Tensor b3) {
    const std::array<torch::Tensor, kLayers> w = {w1.contiguous(), w2.contiguous(),
                                                  w3.contiguous()};
    const std::array<torch::Tensor, kLayers> b = {b1.contiguous(), b2.contiguous(),
                                                  b3.contiguous()};
    omega = omega.contiguous();
    torch::Tensor a = x.contiguous();
    std::vector<torch::Tensor> saved = {a, omega, w[0], w[1], w[2]};
    for (int l = 0; l < kLayers; ++l) {
      torch::Tensor products;
      torch::Tensor u = blended_layer(a, omega, w[l], b[l], products);
      saved.push_back(products);
      if (l + 1 < kLayers) {
        a = elu_of(u);
        saved.push_back(a);
      } else {
        a = u;
      }
    }
    ctx->save_for_backward(saved);
    return a;
  }

  static torch::autograd::tensor_list backward(torch::autograd::AutogradContext* ctx,
                                               torch::autograd::tensor_list grad_outputs) {
    const auto v = ctx->get_saved_variables();
    const torch::Tensor& x = v[0];
    const torch::Tensor& omega = v[1];
    const std::array<torch::Tensor, kLayers> w = {v[2], v[3], v[4]};
    // Layer l's input and per-expert products.
    const std::array<torch::Tensor, kLayers> input = {x, v[6], v[8]};
    const std::array<torch::Tensor, kLayers> products = {v[5], v[7], v[9]};

    const Eigen::Index batch = x.size(0), experts = omega.size(1);
    const ConstMatrixMap weights = map(omega, batch, experts);
    torch::Tensor d_omega = torch::zeros_like(omega);
    MatrixMap d_weights = map_mut(d_omega, batch, experts);
    torch::autograd::tensor_list grads(2 + 2 * kLayers);

    // g = ∂L/∂u of the layer being visited, from the last layer down.
    RowMatrix g = map(grad_outputs[0].contiguous(), batch, w[2].size(2));
    RowMatrix d_h;  // ω_e ⊙ g, one expert at a time
    for (int l = kLayers - 1; l >= 0; --l) {
      const Shape s = shape_of(input[l], w[l]);
      torch::Tensor d_w = torch::empty_like(w[l]);
      torch::Tensor d_b = torch::empty({s.experts, s.out}, x.options());
      const bool want_input = l > 0 || ctx->needs_input_grad(0);
      RowMatrix d_a = RowMatrix::Zero(s.batch, want_input ? s.in : 0);
      const ConstMatrixMap a = map(input[l], s.batch, s.in);
      for (Eigen::Index e = 0; e < s.experts; ++e) {
        // u = Σ_e ω_e ⊙ p_e: ∂L/∂ω_e = Σ_j g ⊙ p_e, ∂L/∂p_e = ω_e ⊙ g.
        const ConstMatrixMap p = map(products[l], s.batch, s.out, e * s.batch * s.out);
        d_weights.col(e) += (g.array() * p.array()).rowwise().sum().matrix();
        d_h = (g.array().colwise() * weights.col(e).array()).matrix();
        map_mut(d_w, s.in, s.out, e * s.in * s.out).noalias() = a.transpose() * d_h;
        map_mut(d_b, 1, s.out, e * s.out) = d_h.colwise().sum();
        if (want_input) {
          d_a.noalias() += d_h * map(w[l], s.in, s.out, e * s.in * s.out).transpose();
        }
      }
      grads[static_cast<std::size_t>(2 + 2 * l)] = d_w;
      grads[static_cast<std::size_t>(3 + 2 * l)] = d_b;
      if (l > 0) {
        // Through the ELU before this layer: a = ELU(u), a' = 1 (u > 0), a + 1 otherwise.
        const auto act = a.array();
        g = (d_a.array() * (act > 0.0f).select(1.0f, act + 1.0f)).matrix();
      } else if (want_input) {
        torch::Tensor d_x = torch::empty_like(x);
        map_mut(d_x, batch, s.in) = d_a;
        grads[0] = d_x;
      }
    }
    grads[1] = d_omega;
    return grads;
  }
};

}  // namespace

torch::Tensor expert_layers(const torch::Tensor& x, const torch::Tensor& omega,
                            const std::array<torch::Tensor, 3>& weights,
                            const std::array<torch::Tensor, 3>& biases) {
  TORCH_CHECK(x.dim() == 2 && omega.dim() == 2 && x.scalar_type() == torch::kFloat32 &&
                  omega.scalar_type() == torch::kFloat32,
              "expert_layers: x [batch, in] and omega [batch, experts] must be float32");
  return ExpertLayersFunction::apply(x, omega, weights[0], biases[0], weights[1], biases[1],
                                     weights[2], biases[2]);
}

}  // namespace deixis::train
