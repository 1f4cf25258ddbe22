#include "train/fused_denoiser.h"

#include "train/group_norm.h"
#include "train/tensor_maps.h"

#include <torch/autograd.h>

#include <Eigen/Core>

namespace deixis::train {

namespace {

constexpr float kGroupNormEps = 1e-5f;

using RowArray = Eigen::Array<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Where each tensor sits in the node's flat input list.
enum Input : std::size_t { kCondition, kNoisy, kTime, kFinWeight, kFinBias, kFirstBlock };
enum BlockInput : std::size_t { kNormWeight, kNormBias, kWeight, kBias, kPerBlock };

struct Dims {
  Eigen::Index batch, condition, pose, time, hidden, blocks, groups;
  // The columns every block and fco read after h: noisy ++ condition ++ time.
  Eigen::Index rest() const { return pose + condition + time; }
  Eigen::Index wide() const { return hidden + rest(); }
};

std::size_t block_input(Eigen::Index block, BlockInput which) {
  return kFirstBlock + static_cast<std::size_t>(block) * kPerBlock + which;
}
std::size_t fco_weight_index(const Dims& s) {
  return kFirstBlock + static_cast<std::size_t>(s.blocks) * kPerBlock;
}

Dims dims_of(at::TensorList in, std::int64_t groups) {
  Dims s{};
  s.batch = in[kCondition].size(0);
  s.condition = in[kCondition].size(1);
  s.pose = in[kNoisy].size(1);
  s.time = in[kTime].size(1);
  s.hidden = in[kFinWeight].size(0);
  s.blocks = static_cast<Eigen::Index>((in.size() - kFirstBlock - 2) / kPerBlock);
  s.groups = groups;
  return s;
}

struct DenoiserFunction : public torch::autograd::Function<DenoiserFunction> {
  // Saved after the inputs: the fin layer's input, each block's and fco's input (SiLU's output or
  // the last h, then the rest columns), the norms' x̂, 1/σ and affine outputs.
  enum Saved : std::size_t { kFinInput, kLayerInputs, kXHat, kRstd, kNormed, kSavedCount };

  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, at::TensorList inputs,
                               std::int64_t groups) {
    torch::autograd::variable_list in;
    for (const torch::Tensor& t : inputs) {
      in.push_back(t.contiguous());
    }
    const Dims s = dims_of(in, groups);
    const torch::TensorOptions f32 = in[kCondition].options();
    const Eigen::Index b = s.batch, hid = s.hidden, wide = s.wide();

    torch::Tensor fin_input = torch::cat({in[kCondition], in[kNoisy], in[kTime]}, 1);
    torch::Tensor layer_inputs = torch::empty({s.blocks + 1, b, wide}, f32);
    const torch::Tensor rest = torch::cat({in[kNoisy], in[kCondition], in[kTime]}, 1);
    for (Eigen::Index k = 0; k <= s.blocks; ++k) {
      map_mut(layer_inputs, b, wide, k * b * wide).rightCols(s.rest()) = map(rest, b, s.rest());
    }
    torch::Tensor x_hat = torch::empty({s.blocks, b, hid}, f32);
    torch::Tensor rstd = torch::empty({s.blocks, b, s.groups}, f32);
    torch::Tensor normed = torch::empty({s.blocks, b, hid}, f32);

    RowMatrix h = map(fin_input, b, fin_input.size(1)) *
                  map(in[kFinWeight], hid, fin_input.size(1)).transpose();
    h.rowwise() += vec(in[kFinBias]);
    for (Eigen::Index k = 0; k < s.blocks; ++k) {
      const Eigen::Index at = k * b * hid;
      group_norm(h, s.groups, kGroupNormEps, vec(in[block_input(k, kNormWeight)]),
                 vec(in[block_input(k, kNormBias)]), map_mut(x_hat, b, hid, at),
                 rstd.data_ptr<float>() + k * b * s.groups, map_mut(normed, b, hid, at));
      MatrixMap layer_input = map_mut(layer_inputs, b, wide, k * b * wide);
      const auto y = map(normed, b, hid, at).array();
      layer_input.leftCols(hid).array() = y / (1.0f + (-y).exp());  // SiLU
      h.noalias() = layer_input * map(in[block_input(k, kWeight)], hid, wide).transpose();
      h.rowwise() += vec(in[block_input(k, kBias)]);
    }
    MatrixMap last_input = map_mut(layer_inputs, b, wide, s.blocks * b * wide);
    last_input.leftCols(hid) = h;
    torch::Tensor out = torch::empty({b, s.pose}, f32);
    map_mut(out, b, s.pose).noalias() =
        last_input * map(in[fco_weight_index(s)], s.pose, wide).transpose();
    map_mut(out, b, s.pose).rowwise() += vec(in[fco_weight_index(s) + 1]);

    torch::autograd::variable_list saved = in;
    saved.insert(saved.end(), {fin_input, layer_inputs, x_hat, rstd, normed});
    ctx->save_for_backward(saved);
    ctx->saved_data["groups"] = groups;
    return out;
  }

  static torch::autograd::variable_list backward(torch::autograd::AutogradContext* ctx,
                                                 torch::autograd::variable_list grad_outputs) {
    const torch::autograd::variable_list saved = ctx->get_saved_variables();
    const std::size_t n = saved.size() - kSavedCount;
    const at::TensorList in(saved.data(), n);
    const torch::Tensor* buffers = saved.data() + n;
    const Dims s = dims_of(in, ctx->saved_data["groups"].toInt());
    const Eigen::Index b = s.batch, hid = s.hidden, wide = s.wide();
    const torch::Tensor& layer_inputs = buffers[kLayerInputs];
    const bool data_gradients = ctx->needs_input_grad(kCondition) || ctx->needs_input_grad(kNoisy);
    const bool time_gradient = ctx->needs_input_grad(kTime);

    torch::autograd::variable_list grads(n + 1);  // + the groups argument's (none)
    // Every gradient is written whole, so it needs no zeroing.
    auto gradient_like = [&](std::size_t i) {
      grads[i] = torch::empty_like(in[i]);
      return i;
    };
    // The gradient at noisy ++ condition ++ time, summed over fco and the blocks; only time's
    // columns when the data need none (in training they are data: only the step embedding has
    // parameters before it).
    RowMatrix d_rest = RowMatrix::Zero(b, s.rest());
    // One linear layer reading [h ++ rest]: its weight and bias gradients, d_rest, and the
    // gradient at its h columns into d_h.
    auto linear_backward = [&](const RowMatrix& d_output, std::size_t weight, Eigen::Index input_at,
                               Eigen::Index outputs, RowMatrix& d_input_h) {
      const ConstMatrixMap w = map(in[weight], outputs, wide);
      map_mut(grads[gradient_like(weight)], outputs, wide).noalias() =
          d_output.transpose() * map(layer_inputs, b, wide, input_at);
      vec_mut(grads[gradient_like(weight + 1)]) = d_output.colwise().sum();
      d_input_h.noalias() = d_output * w.leftCols(hid);
      if (data_gradients) {
        d_rest.noalias() += d_output * w.rightCols(s.rest());
      } else if (time_gradient) {
        d_rest.rightCols(s.time).noalias() += d_output * w.rightCols(s.time);
      }
    };

    const RowMatrix d_out = map(grad_outputs[0].contiguous(), b, s.pose);
    RowMatrix d_h(b, hid), d_y(b, hid);
    linear_backward(d_out, fco_weight_index(s), s.blocks * b * wide, s.pose, d_h);
    for (Eigen::Index k = s.blocks - 1; k >= 0; --k) {
      linear_backward(d_h, block_input(k, kWeight), k * b * wide, hid, d_y);
      // SiLU'(y) = σ(y)·(1 + y·(1 − σ(y))).
      const Eigen::Index at = k * b * hid;
      const auto y = map(buffers[kNormed], b, hid, at).array();
      const RowArray sigma = 1.0f / (1.0f + (-y).exp());
      d_y.array() *= sigma * (1.0f + y * (1.0f - sigma));
      group_norm_backward(d_y, map(buffers[kXHat], b, hid, at),
                          buffers[kRstd].data_ptr<float>() + k * b * s.groups, s.groups,
                          vec(in[block_input(k, kNormWeight)]),
                          vec_mut(grads[gradient_like(block_input(k, kNormWeight))]),
                          vec_mut(grads[gradient_like(block_input(k, kNormBias))]), d_h);
    }

    // fin reads condition ++ noisy ++ time.
    const Eigen::Index fin_width = s.condition + s.pose + s.time;
    const ConstMatrixMap fin_w = map(in[kFinWeight], hid, fin_width);
    map_mut(grads[gradient_like(kFinWeight)], hid, fin_width).noalias() =
        d_h.transpose() * map(buffers[kFinInput], b, fin_width);
    vec_mut(grads[gradient_like(kFinBias)]) = d_h.colwise().sum();
    if (time_gradient) {
      map_mut(grads[gradient_like(kTime)], b, s.time).noalias() =
          d_rest.rightCols(s.time) + d_h * fin_w.rightCols(s.time);
    }
    if (ctx->needs_input_grad(kCondition)) {
      map_mut(grads[gradient_like(kCondition)], b, s.condition).noalias() =
          d_rest.middleCols(s.pose, s.condition) + d_h * fin_w.leftCols(s.condition);
    }
    if (ctx->needs_input_grad(kNoisy)) {
      map_mut(grads[gradient_like(kNoisy)], b, s.pose).noalias() =
          d_rest.leftCols(s.pose) + d_h * fin_w.middleCols(s.condition, s.pose);
    }
    return grads;
  }
};

}  // namespace

torch::Tensor denoise(const torch::Tensor& condition, const torch::Tensor& noisy,
                      const torch::Tensor& time, const DenoiserWeights& w) {
  TORCH_CHECK(condition.dim() == 2 && noisy.dim() == 2 && time.dim() == 2,
              "denoise: condition, noisy and time must be [batch, features]");
  TORCH_CHECK(noisy.size(0) == condition.size(0) && time.size(0) == condition.size(0),
              "denoise: condition, noisy and time must have the same batch");
  const std::int64_t hidden = w.fin_weight.size(0);
  const std::int64_t pose = noisy.size(1);
  const std::int64_t rest = condition.size(1) + pose + time.size(1);
  TORCH_CHECK(w.groups > 0 && hidden % w.groups == 0,
              "denoise: groups must divide the hidden width");
  // The node reads every tensor as raw float32 memory of the shape checked here.
  auto expect = [](const torch::Tensor& t, std::initializer_list<std::int64_t> shape,
                   const char* what) {
    TORCH_CHECK(t.device().is_cpu() && t.scalar_type() == torch::kFloat32, "denoise: ", what,
                " must be a float32 CPU tensor");
    TORCH_CHECK(t.sizes() == c10::IntArrayRef(shape), "denoise: ", what, " is ", t.sizes(),
                ", not ", c10::IntArrayRef(shape));
  };
  expect(condition, {condition.size(0), condition.size(1)}, "condition");
  expect(noisy, {condition.size(0), pose}, "noisy");
  expect(time, {condition.size(0), time.size(1)}, "time");
  expect(w.fin_weight, {hidden, rest}, "fin's weight (condition + pose + time wide)");
  expect(w.fin_bias, {hidden}, "fin's bias");
  std::vector<torch::Tensor> inputs{condition, noisy, time, w.fin_weight, w.fin_bias};
  for (const DenoiserBlockWeights& block : w.blocks) {
    expect(block.norm_weight, {hidden}, "a block's norm weight");
    expect(block.norm_bias, {hidden}, "a block's norm bias");
    expect(block.weight, {hidden, hidden + rest}, "a block's weight");
    expect(block.bias, {hidden}, "a block's bias");
    inputs.insert(inputs.end(), {block.norm_weight, block.norm_bias, block.weight, block.bias});
  }
  expect(w.fco_weight, {pose, hidden + rest}, "fco's weight");
  expect(w.fco_bias, {pose}, "fco's bias");
  inputs.insert(inputs.end(), {w.fco_weight, w.fco_bias});
  return DenoiserFunction::apply(at::TensorList(inputs), w.groups);
}

}  // namespace deixis::train
