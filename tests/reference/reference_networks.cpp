#include "reference/reference_networks.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/io/safetensors.h"

namespace deixis::reference {

namespace {

// Sizes the paper fixes (docs/conventions.md#mpnet-features, #end-effectors, #amnet).
constexpr std::size_t kWindowRows = 30;
constexpr std::size_t kMpnetColumns = 11;
constexpr std::size_t kMpnetTargetColumn = 6;  // cols 6-10: (θH, φH, θR, φR, rR)
constexpr std::size_t kTargetFeatureSize = 5;
constexpr std::size_t kUgnetColumns = 32;
constexpr std::size_t kPoseSize = 24;         // cols 0-23: the end-effectors x
constexpr std::size_t kConditionColumns = 8;  // cols 24-31: target feature ++ progression
constexpr std::size_t kAmnetRows = 20;
constexpr std::size_t kAmnetColumns = 16;
constexpr std::size_t kAmnetAngles = 12;       // cols 0-11
constexpr std::size_t kAmnetTarget = 3;        // cols 12-14
constexpr std::size_t kAmnetScaleColumn = 15;  // only the newest remote row's value is read
constexpr int kDiffusionSteps = 30;

std::size_t dim(const Tensor& t, std::size_t k) {
  return static_cast<std::size_t>(t.shape[k]);
}

// Element (row, col) of a 2-D tensor and (i, j, k) of a 3-D one, row-major as PyTorch stores them.
double at(const Tensor& t, std::size_t row, std::size_t col) {
  return t.values[row * dim(t, 1) + col];
}
double at(const Tensor& t, std::size_t i, std::size_t j, std::size_t k) {
  return t.values[(i * dim(t, 1) + j) * dim(t, 2) + k];
}

void expect_size(const Vector& x, std::size_t size, const char* what) {
  if (x.size() != size) {
    throw Error(std::string("reference: ") + what + ": expected " + std::to_string(size) +
                " values, got " + std::to_string(x.size()));
  }
}

void expect_window(const Rows& window, std::size_t rows, std::size_t columns, const char* what) {
  if (window.size() != rows) {
    throw Error(std::string("reference: ") + what + ": expected a window of " +
                std::to_string(rows) + " rows, got " + std::to_string(window.size()));
  }
  for (const Vector& row : window) {
    expect_size(row, columns, what);
  }
}

std::int64_t as_dim(std::size_t n) {
  return static_cast<std::int64_t>(n);
}

// Columns [first, first + count) of every row.
Rows columns(const Rows& window, std::size_t first, std::size_t count) {
  Rows out;
  for (const Vector& row : window) {
    out.emplace_back(row.begin() + as_dim(first), row.begin() + as_dim(first + count));
  }
  return out;
}

Vector clamp_01(Vector x) {
  for (double& v : x) {
    v = std::clamp(v, 0.0, 1.0);
  }
  return x;
}

Vector add(const Vector& a, const Vector& b) {
  Vector sum(a.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    sum[i] = a[i] + b[i];
  }
  return sum;
}

// nn.Linear `prefix`.weight [out, in] and `prefix`.bias [out].
Vector linear(const Vector& x, const Weights& weights, const std::string& prefix, std::size_t in,
              std::size_t out) {
  return linear(x, weights.get(prefix + ".weight", {as_dim(out), as_dim(in)}),
                weights.get(prefix + ".bias", {as_dim(out)}));
}

// A stacked nn.GRU (`prefix`.weight_ih_l0, …): each layer reads the previous layer's outputs
// (dropout 0). Returns the last layer's output at every row.
Rows gru(const Rows& inputs, const Weights& weights, const std::string& prefix, int layers,
         std::size_t input_size, std::size_t hidden) {
  Rows x = inputs;
  for (int l = 0; l < layers; ++l) {
    const std::string suffix = "_l" + std::to_string(l);
    const std::int64_t gates = as_dim(3 * hidden);
    const std::int64_t in = as_dim(l == 0 ? input_size : hidden);
    x = gru_layer(x, {weights.get(prefix + ".weight_ih" + suffix, {gates, in}),
                      weights.get(prefix + ".weight_hh" + suffix, {gates, as_dim(hidden)}),
                      weights.get(prefix + ".bias_ih" + suffix, {gates}),
                      weights.get(prefix + ".bias_hh" + suffix, {gates})});
  }
  return x;
}

// One layer of an ExpertMLP stored as `w_name` [experts, in, out] and `b_name` [experts, out].
Vector expert_layer(const Vector& x, const Vector& omega, const Weights& weights,
                    const std::string& w_name, const std::string& b_name, std::size_t in,
                    std::size_t out) {
  const std::int64_t experts = as_dim(omega.size());
  return expert_layer(x, omega, weights.get(w_name, {experts, as_dim(in), as_dim(out)}),
                      weights.get(b_name, {experts, as_dim(out)}));
}

}  // namespace

// ---- Weights ------------------------------------------------------------------------------------

Weights Weights::load(const std::filesystem::path& checkpoint) {
  const SafetensorsFile file = SafetensorsFile::read(checkpoint);
  Weights weights;
  weights.source_ = file.source();
  for (const TensorInfo& info : file.tensors()) {
    if (info.dtype != DType::kF32) {
      continue;  // BatchNorm's int64 num_batches_tracked: unused in eval mode
    }
    const std::vector<float> values = file.read_f32(info.name, info.shape);
    Tensor tensor{info.shape, Vector(values.size())};
    std::transform(values.begin(), values.end(), tensor.values.begin(),
                   [](float v) { return static_cast<double>(v); });
    weights.tensors_.emplace(info.name, std::move(tensor));
  }
  return weights;
}

const Tensor* Weights::find(const std::string& name) const {
  const auto it = tensors_.find(name);
  return it == tensors_.end() ? nullptr : &it->second;
}

const Tensor& Weights::get(const std::string& name, const std::vector<std::int64_t>& shape) const {
  const Tensor* tensor = find(name);
  if (tensor == nullptr) {
    throw Error(source_ + ": tensor '" + name + "' missing (reference implementation)");
  }
  if (tensor->shape != shape) {
    throw Error(source_ + ": tensor '" + name + "': expected shape " + shape_string(shape) +
                ", found " + shape_string(tensor->shape));
  }
  return *tensor;
}

// ---- operations ---------------------------------------------------------------------------------

double sigmoid(double x) {
  return 1.0 / (1.0 + std::exp(-x));
}

Vector relu(Vector x) {
  for (double& v : x) {
    v = std::max(v, 0.0);
  }
  return x;
}

Vector elu(Vector x) {
  for (double& v : x) {
    v = v > 0.0 ? v : std::expm1(v);
  }
  return x;
}

Vector silu(Vector x) {
  for (double& v : x) {
    v = v * sigmoid(v);
  }
  return x;
}

Vector softmax(const Vector& x) {
  // Subtracting the maximum changes nothing mathematically and keeps exp() finite.
  const double max = *std::max_element(x.begin(), x.end());
  Vector y(x.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    y[i] = std::exp(x[i] - max);
    sum += y[i];
  }
  for (double& v : y) {
    v /= sum;
  }
  return y;
}

Vector concat(const std::vector<Vector>& parts) {
  Vector out;
  for (const Vector& part : parts) {
    out.insert(out.end(), part.begin(), part.end());
  }
  return out;
}

Vector linear(const Vector& x, const Tensor& weight, const Tensor& bias) {
  const std::size_t out = dim(weight, 0);
  const std::size_t in = dim(weight, 1);
  expect_size(x, in, "linear input");
  Vector y(out);
  for (std::size_t o = 0; o < out; ++o) {
    const double* row = &weight.values[o * in];  // W[o, :]
    double sum = bias.values[o];
    for (std::size_t i = 0; i < in; ++i) {
      sum += row[i] * x[i];
    }
    y[o] = sum;
  }
  return y;
}

Rows gru_layer(const Rows& inputs, const GruLayerWeights& weights) {
  // torch.nn.GRU (docs/conventions.md#grus), gates stacked r | z | n; b_hn stays inside the reset
  // product:
  //   r = σ(W_ir x + b_ir + W_hr h + b_hr)     z = σ(W_iz x + b_iz + W_hz h + b_hz)
  //   n = tanh(W_in x + b_in + r ⊙ (W_hn h + b_hn))     h' = (1 − z) ⊙ n + z ⊙ h
  const std::size_t hidden = dim(weights.weight_hh, 1);
  Vector h(hidden, 0.0);  // h0 = 0 on every call: the authors' GRUs are not stateful
  Rows outputs;
  for (const Vector& x : inputs) {
    const Vector gi = linear(x, weights.weight_ih, weights.bias_ih);
    const Vector gh = linear(h, weights.weight_hh, weights.bias_hh);
    Vector next(hidden);
    for (std::size_t k = 0; k < hidden; ++k) {
      const double r = sigmoid(gi[k] + gh[k]);
      const double z = sigmoid(gi[hidden + k] + gh[hidden + k]);
      const double n = std::tanh(gi[2 * hidden + k] + r * gh[2 * hidden + k]);
      next[k] = (1.0 - z) * n + z * h[k];
    }
    h = next;
    outputs.push_back(h);
  }
  return outputs;
}

Vector layer_norm(const Vector& x, const Tensor& weight, const Tensor& bias) {
  const double n = static_cast<double>(x.size());
  double mean = 0.0;
  for (double v : x) {
    mean += v;
  }
  mean /= n;
  double variance = 0.0;  // biased, as PyTorch
  for (double v : x) {
    variance += (v - mean) * (v - mean);
  }
  variance /= n;
  const double inv_std = 1.0 / std::sqrt(variance + 1e-5);
  Vector y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    y[i] = (x[i] - mean) * inv_std * weight.values[i] + bias.values[i];
  }
  return y;
}

Rows multi_head_attention(const Rows& tokens, int heads, const Tensor& in_proj_weight,
                          const Tensor& in_proj_bias, const Tensor& out_proj_weight,
                          const Tensor& out_proj_bias) {
  const std::size_t width = dim(out_proj_weight, 0);
  const std::size_t head_dim = width / static_cast<std::size_t>(heads);
  const std::size_t n = tokens.size();

  // in_proj stacks the query, key and value projections: rows [0, D), [D, 2D), [2D, 3D).
  Rows q, k, v;
  for (const Vector& token : tokens) {
    const Vector qkv = linear(token, in_proj_weight, in_proj_bias);
    q.emplace_back(qkv.begin(), qkv.begin() + as_dim(width));
    k.emplace_back(qkv.begin() + as_dim(width), qkv.begin() + as_dim(2 * width));
    v.emplace_back(qkv.begin() + as_dim(2 * width), qkv.end());
  }

  // Each head attends with its own slice of the width: softmax(q·kᵀ / √head_dim)·v.
  const double scale = 1.0 / std::sqrt(static_cast<double>(head_dim));
  Rows attended(n, Vector(width, 0.0));
  for (std::size_t h = 0; h < static_cast<std::size_t>(heads); ++h) {
    const std::size_t first = h * head_dim;
    for (std::size_t i = 0; i < n; ++i) {
      Vector scores(n);
      for (std::size_t j = 0; j < n; ++j) {
        double dot = 0.0;
        for (std::size_t d = 0; d < head_dim; ++d) {
          dot += q[i][first + d] * k[j][first + d];
        }
        scores[j] = dot * scale;
      }
      const Vector p = softmax(scores);
      for (std::size_t d = 0; d < head_dim; ++d) {
        double sum = 0.0;
        for (std::size_t j = 0; j < n; ++j) {
          sum += p[j] * v[j][first + d];
        }
        attended[i][first + d] = sum;
      }
    }
  }

  Rows out;
  for (const Vector& a : attended) {
    out.push_back(linear(a, out_proj_weight, out_proj_bias));
  }
  return out;
}

Rows transformer_encoder_layer(const Rows& tokens, int heads, int feed_forward,
                               const Weights& weights, const std::string& prefix) {
  const std::int64_t d = as_dim(tokens.front().size());
  const std::int64_t ff = feed_forward;
  const Tensor& norm1_weight = weights.get(prefix + ".norm1.weight", {d});
  const Tensor& norm1_bias = weights.get(prefix + ".norm1.bias", {d});
  const Tensor& norm2_weight = weights.get(prefix + ".norm2.weight", {d});
  const Tensor& norm2_bias = weights.get(prefix + ".norm2.bias", {d});
  const Tensor& linear1_weight = weights.get(prefix + ".linear1.weight", {ff, d});
  const Tensor& linear1_bias = weights.get(prefix + ".linear1.bias", {ff});
  const Tensor& linear2_weight = weights.get(prefix + ".linear2.weight", {d, ff});
  const Tensor& linear2_bias = weights.get(prefix + ".linear2.bias", {d});

  const Rows attention = multi_head_attention(
      tokens, heads, weights.get(prefix + ".self_attn.in_proj_weight", {3 * d, d}),
      weights.get(prefix + ".self_attn.in_proj_bias", {3 * d}),
      weights.get(prefix + ".self_attn.out_proj.weight", {d, d}),
      weights.get(prefix + ".self_attn.out_proj.bias", {d}));

  // Post-norm (norm_first = False): x = norm1(x + SA(x)); x = norm2(x + FF(x)). Dropout is off.
  Rows out;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const Vector x = layer_norm(add(tokens[i], attention[i]), norm1_weight, norm1_bias);
    const Vector ff_out =
        linear(relu(linear(x, linear1_weight, linear1_bias)), linear2_weight, linear2_bias);
    out.push_back(layer_norm(add(x, ff_out), norm2_weight, norm2_bias));
  }
  return out;
}

Vector group_norm(const Vector& x, int groups, const Tensor& weight, const Tensor& bias) {
  const std::size_t per_group = x.size() / static_cast<std::size_t>(groups);
  Vector y(x.size());
  for (std::size_t g = 0; g < static_cast<std::size_t>(groups); ++g) {
    const std::size_t first = g * per_group;
    double mean = 0.0;
    for (std::size_t c = first; c < first + per_group; ++c) {
      mean += x[c];
    }
    mean /= static_cast<double>(per_group);
    double variance = 0.0;  // biased, as PyTorch
    for (std::size_t c = first; c < first + per_group; ++c) {
      variance += (x[c] - mean) * (x[c] - mean);
    }
    variance /= static_cast<double>(per_group);
    const double inv_std = 1.0 / std::sqrt(variance + 1e-5);
    // The affine transform is per channel, not per group.
    for (std::size_t c = first; c < first + per_group; ++c) {
      y[c] = (x[c] - mean) * inv_std * weight.values[c] + bias.values[c];
    }
  }
  return y;
}

Vector batch_norm_eval(const Vector& x, const Tensor& weight, const Tensor& bias,
                       const Tensor& running_mean, const Tensor& running_var) {
  Vector y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    y[i] = (x[i] - running_mean.values[i]) / std::sqrt(running_var.values[i] + 1e-5) *
               weight.values[i] +
           bias.values[i];
  }
  return y;
}

Vector expert_layer(const Vector& x, const Vector& omega, const Tensor& weight,
                    const Tensor& bias) {
  const std::size_t experts = dim(weight, 0);
  const std::size_t in = dim(weight, 1);
  const std::size_t out = dim(weight, 2);
  expect_size(x, in, "expert layer input");
  expect_size(omega, experts, "expert weights ω");

  // ExpertMLP.forward blends the experts' weights first: w = Σ_e ω_e·W_e, b = ω·B.
  Vector w(in * out, 0.0);
  Vector b(out, 0.0);
  for (std::size_t e = 0; e < experts; ++e) {
    for (std::size_t i = 0; i < in; ++i) {
      for (std::size_t o = 0; o < out; ++o) {
        w[i * out + o] += omega[e] * at(weight, e, i, o);
      }
    }
    for (std::size_t o = 0; o < out; ++o) {
      b[o] += omega[e] * at(bias, e, o);
    }
  }
  // Then linearlayer: y_o = Σ_i x_i·w_io + b_o (x·W from the right, unlike nn.Linear).
  Vector y(out);
  for (std::size_t o = 0; o < out; ++o) {
    double sum = 0.0;
    for (std::size_t i = 0; i < in; ++i) {
      sum += x[i] * w[i * out + o];
    }
    y[o] = sum + b[o];
  }
  return y;
}

Vector sinusoidal_time_embedding(int t, int dim) {
  const std::size_t half = static_cast<std::size_t>(dim) / 2;
  const double step = std::log(10000.0) / static_cast<double>(half);
  Vector e(2 * half);
  for (std::size_t k = 0; k < half; ++k) {
    const double angle = static_cast<double>(t) * std::exp(-static_cast<double>(k) * step);
    e[k] = std::sin(angle);         // sines first
    e[half + k] = std::cos(angle);  // then cosines
  }
  return e;
}

// ---- networks -----------------------------------------------------------------------------------

Architecture architecture_of(const Weights& weights) {
  const auto has_shape = [&](const std::string& name, std::vector<std::int64_t> shape) {
    const Tensor* t = weights.find(name);
    return t != nullptr && t->shape == shape;
  };
  if (weights.find("angle_encoder.w_l1") != nullptr) {
    return Architecture::kAmnet;
  }
  if (weights.find("model.fin.weight") != nullptr && weights.find("time_mlp.1.weight") != nullptr) {
    return Architecture::kUgnetDiffusion;
  }
  // The gating GRU reads the 5 target columns in MPNet and the 8 conditioning columns in UGNet.
  if (has_shape("gating_network.gru.weight_ih_l0", {27, 5})) {
    return Architecture::kMpnetGruMoe;
  }
  if (has_shape("gating_network.gru.weight_ih_l0", {27, 8})) {
    return Architecture::kUgnetMoe;
  }
  if (has_shape("linear1.weight", {24, 330})) {
    return Architecture::kMpnetMlp;
  }
  if (has_shape("linear1.weight", {1056, 264})) {
    return Architecture::kUgnetMlp;
  }
  if (weights.find("linear_input.weight") != nullptr) {
    return Architecture::kMpnetTransformer;
  }
  if (weights.find("linear_input_pose.weight") != nullptr) {
    return Architecture::kUgnetTransformer;
  }
  throw Error("reference: checkpoint of an unknown architecture");
}

std::string_view architecture_name(Architecture architecture) {
  switch (architecture) {
    case Architecture::kMpnetGruMoe:
      return "MPNet GRU-MoE";
    case Architecture::kMpnetMlp:
      return "MPNet MLP";
    case Architecture::kMpnetTransformer:
      return "MPNet Transformer";
    case Architecture::kUgnetMoe:
      return "UGNet MoE";
    case Architecture::kUgnetMlp:
      return "UGNet MLP";
    case Architecture::kUgnetTransformer:
      return "UGNet Transformer";
    case Architecture::kUgnetDiffusion:
      return "UGNet Diffusion";
    case Architecture::kAmnet:
      return "AMNet";
  }
  return "?";
}

MpnetResult mpnet_gru_moe(const Weights& weights, const Rows& window) {
  // model.py MPNet_MoE (docs/conventions.md#mpnet, #mixture-of-experts).
  expect_window(window, kWindowRows, kMpnetColumns, "MPNet window");
  MpnetResult result;
  // Gating network: 2-layer GRU(9) over the target feature only; softmax of the last row's output
  // (no linear layer before it).
  const Rows target = columns(window, kMpnetTargetColumn, kTargetFeatureSize);
  result.omega =
      softmax(gru(target, weights, "gating_network.gru", 2, kTargetFeatureSize, 9).back());
  // Recurrent module: 1-layer GRU(24) over all 11 columns; z is its last output.
  result.z = gru(window, weights, "gru", 1, kMpnetColumns, 24).back();
  // Experts 24 → 12 → 12 → 3 (hidden = 24 // 2), ELU after the first two layers, then the clamp.
  Vector h = elu(expert_layer(result.z, result.omega, weights, "moe_network.w_l1",
                              "moe_network.b_l1", 24, 12));
  h = elu(expert_layer(h, result.omega, weights, "moe_network.w_l2", "moe_network.b_l2", 12, 12));
  result.preclamp =
      expert_layer(h, result.omega, weights, "moe_network.w_l3", "moe_network.b_l3", 12, 3);
  result.progression = clamp_01(result.preclamp);
  return result;
}

MpnetResult mpnet_mlp(const Weights& weights, const Rows& window) {
  // model.py MPNet_MLP (docs/conventions.md#mpnet): the window flattened row-major, index
  // row·11 + col.
  expect_window(window, kWindowRows, kMpnetColumns, "MPNet window");
  const Vector x = concat(window);
  Vector h = elu(linear(x, weights, "linear1", kWindowRows * kMpnetColumns, 24));
  h = elu(linear(h, weights, "linear2", 24, 24));
  MpnetResult result;
  result.preclamp = linear(h, weights, "linear3", 24, 3);
  result.progression = clamp_01(result.preclamp);
  return result;
}

MpnetResult mpnet_transformer(const Weights& weights, const Rows& window) {
  // model.py MPNet_Transformer (docs/conventions.md#mpnet): one token per row, no positional
  // encoding.
  expect_window(window, kWindowRows, kMpnetColumns, "MPNet window");
  Rows tokens;
  for (const Vector& row : window) {
    tokens.push_back(linear(row, weights, "linear_input", kMpnetColumns, 16));
  }
  for (int l = 0; l < 4; ++l) {
    tokens = transformer_encoder_layer(tokens, 4, 16, weights,
                                       "transformer.layers." + std::to_string(l));
  }
  MpnetResult result;
  result.preclamp = linear(tokens.back(), weights, "linear_output", 16, 3);  // newest row's token
  result.progression = clamp_01(result.preclamp);
  return result;
}

namespace {

// The 264-vector the UGNet MoE experts, MLP and diffusion condition read
// (docs/conventions.md#ugnet): the newest row's pose (cols 0-23) ++ cols 24-31 of every row, oldest
// first (index 24 + row·8 + k).
Vector condition_vector(const Rows& window) {
  Vector c(window.back().begin(), window.back().begin() + as_dim(kPoseSize));
  for (const Vector& row : window) {
    c.insert(c.end(), row.begin() + as_dim(kPoseSize), row.end());
  }
  return c;
}

constexpr std::size_t kConditionSize = kPoseSize + kConditionColumns * kWindowRows;  // 264

}  // namespace

UgnetResult ugnet_moe(const Weights& weights, const Rows& window) {
  // model.py UGNet_MoE (docs/conventions.md#ugnet).
  expect_window(window, kWindowRows, kUgnetColumns, "UGNet window");
  UgnetResult result;
  const Rows conditioning = columns(window, kPoseSize, kConditionColumns);
  result.omega =
      softmax(gru(conditioning, weights, "gating_network.gru", 2, kConditionColumns, 9).back());
  // Experts 264 → 144 → 144 → 24 (144 = 24 + 240 // 2), ELU after the first two layers.
  constexpr std::size_t kHidden = kPoseSize + (kConditionColumns * kWindowRows) / 2;
  const Vector c = condition_vector(window);
  Vector h = elu(expert_layer(c, result.omega, weights, "moe_network.w_l1", "moe_network.b_l1",
                              kConditionSize, kHidden));
  h = elu(expert_layer(h, result.omega, weights, "moe_network.w_l2", "moe_network.b_l2", kHidden,
                       kHidden));
  result.pose = expert_layer(h, result.omega, weights, "moe_network.w_l3", "moe_network.b_l3",
                             kHidden, kPoseSize);
  return result;
}

UgnetResult ugnet_mlp(const Weights& weights, const Rows& window) {
  // model.py UGNet_MLP (docs/conventions.md#ugnet): 264 → 1056 → 264 → 24, ELU between.
  expect_window(window, kWindowRows, kUgnetColumns, "UGNet window");
  const Vector c = condition_vector(window);
  Vector h = elu(linear(c, weights, "linear1", kConditionSize, 4 * kConditionSize));
  h = elu(linear(h, weights, "linear2", 4 * kConditionSize, kConditionSize));
  UgnetResult result;
  result.pose = linear(h, weights, "linear3", kConditionSize, kPoseSize);
  return result;
}

UgnetResult ugnet_transformer(const Weights& weights, const Rows& window) {
  // model.py UGNet_Transformer (docs/conventions.md#ugnet): 30 feature tokens, then the newest pose
  // as the 31st token; no positional encoding; the output is read from the pose token.
  expect_window(window, kWindowRows, kUgnetColumns, "UGNet window");
  constexpr std::size_t kWidth = 160;
  Rows tokens;
  for (const Vector& row : window) {
    const Vector features(row.begin() + as_dim(kPoseSize), row.end());
    tokens.push_back(linear(features, weights, "linear_input_feature", kConditionColumns, kWidth));
  }
  const Vector newest_pose(window.back().begin(), window.back().begin() + as_dim(kPoseSize));
  tokens.push_back(linear(newest_pose, weights, "linear_input_pose", kPoseSize, kWidth));
  for (int l = 0; l < 4; ++l) {
    tokens = transformer_encoder_layer(tokens, 4, kWidth, weights,
                                       "transformer.layers." + std::to_string(l));
  }
  UgnetResult result;
  result.pose = linear(tokens.back(), weights, "linear_output", kWidth, kPoseSize);
  return result;
}

UgnetResult ugnet_diffusion(const Weights& weights, const Rows& window, const Rows& noise) {
  // model.py UGNet_Diffusion.sample_ddpm and NoiseDecoder.forward
  // (docs/conventions.md#ugnet-diffusion).
  expect_window(window, kWindowRows, kUgnetColumns, "UGNet window");
  expect_window(noise, kDiffusionSteps, kPoseSize, "diffusion noise");
  constexpr std::size_t kHidden = 128;
  constexpr std::size_t kTime = 64;
  constexpr std::size_t kBlockInput = kHidden + kPoseSize + kConditionSize + kTime;  // 480
  const Tensor& sigma = weights.get("sigma", {kDiffusionSteps});  // √β_t, the checkpoint's buffer

  const Vector c = condition_vector(window);
  Vector x = noise[0];  // x ← N(0, I)
  UgnetResult result;
  for (int t = kDiffusionSteps - 1; t >= 0; --t) {
    // time_mlp = PositionalEmbedding(64) → Linear → SiLU → Linear, evaluated for this t.
    const Vector e = linear(silu(linear(sinusoidal_time_embedding(t, static_cast<int>(kTime)),
                                        weights, "time_mlp.1", kTime, kTime)),
                            weights, "time_mlp.3", kTime, kTime);
    // The denoiser: fin reads c ++ x ++ e; every block and fco read h ++ x ++ c ++ e.
    Vector h = linear(concat({c, x, e}), weights, "model.fin", kConditionSize + kPoseSize + kTime,
                      kHidden);
    for (int block = 0; block < 10; ++block) {
      // model.net is [GroupNorm, SiLU, Linear] × 10: indices 3k, 3k + 1, 3k + 2.
      const std::string norm = "model.net." + std::to_string(3 * block);
      h = group_norm(h, 16, weights.get(norm + ".weight", {kHidden}),
                     weights.get(norm + ".bias", {kHidden}));
      h = silu(h);
      h = linear(concat({h, x, c, e}), weights, "model.net." + std::to_string(3 * block + 2),
                 kBlockInput, kHidden);
    }
    const Vector x0 = linear(concat({h, x, c, e}), weights, "model.fco", kBlockInput, kPoseSize);
    result.denoised_steps.push_back(x0);
    // The denoiser predicts the clean pose; sample_ddpm re-noises it with σ_t (not the DDPM
    // posterior) except after the last step.
    x = x0;
    if (t > 0) {
      const Vector& draw = noise[static_cast<std::size_t>(kDiffusionSteps - t)];
      for (std::size_t j = 0; j < kPoseSize; ++j) {
        x[j] += sigma.values[static_cast<std::size_t>(t)] * draw[j];
      }
    }
  }
  result.pose = x;
  return result;
}

namespace {

// ISMAR2023/model.py ExpertMLP.forward: layer 1 → BatchNorm (eval) → ELU → layer 2, both layers
// with the same ω.
Vector amnet_expert_mlp(const Vector& x, const Vector& omega, const Weights& weights,
                        const std::string& prefix, std::size_t in, std::size_t out) {
  constexpr std::int64_t kHidden = 16;
  Vector h = expert_layer(x, omega, weights, prefix + ".w_l1", prefix + ".b_l1", in, kHidden);
  h = batch_norm_eval(h, weights.get(prefix + ".bn.weight", {kHidden}),
                      weights.get(prefix + ".bn.bias", {kHidden}),
                      weights.get(prefix + ".bn.running_mean", {kHidden}),
                      weights.get(prefix + ".bn.running_var", {kHidden}));
  h = elu(h);
  return expert_layer(h, omega, weights, prefix + ".w_l2", prefix + ".b_l2", kHidden, out);
}

// GatingNetwork: 2-layer GRU(6) over the target columns, softmax at every row.
Rows amnet_gate(const Weights& weights, const Rows& window) {
  const Rows target = columns(window, kAmnetAngles, kAmnetTarget);
  Rows omega = gru(target, weights, "gating_network.gru", 2, kAmnetTarget, 6);
  for (Vector& row : omega) {
    row = softmax(row);
  }
  return omega;
}

}  // namespace

Vector amnet(const Weights& weights, const Rows& local, const Rows& remote) {
  // ISMAR2023/model.py ISMAR2023.forward (docs/conventions.md#amnet).
  expect_window(local, kAmnetRows, kAmnetColumns, "AMNet local window");
  expect_window(remote, kAmnetRows, kAmnetColumns, "AMNet remote window");
  // The same gating network, run separately on each window.
  const Rows omega_local = amnet_gate(weights, local);
  const Rows omega_remote = amnet_gate(weights, remote);
  // The angle encoder, per row with that row's ω; local and remote encodings are summed.
  Rows encoded;
  for (std::size_t row = 0; row < kAmnetRows; ++row) {
    const Vector local_angles(local[row].begin(), local[row].begin() + as_dim(kAmnetAngles));
    const Vector remote_angles(remote[row].begin(), remote[row].begin() + as_dim(kAmnetAngles));
    encoded.push_back(add(amnet_expert_mlp(local_angles, omega_local[row], weights, "angle_encoder",
                                           kAmnetAngles, 16),
                          amnet_expert_mlp(remote_angles, omega_remote[row], weights,
                                           "angle_encoder", kAmnetAngles, 16)));
  }
  // 2-layer GRU(16); its last output ++ the newest remote row's scale, decoded with the newest
  // remote ω.
  const Vector z = gru(encoded, weights, "gru", 2, 16, 16).back();
  const Vector decoder_input = concat({z, {remote.back()[kAmnetScaleColumn]}});
  return amnet_expert_mlp(decoder_input, omega_remote.back(), weights, "motion_decoder", 17, 21);
}

}  // namespace deixis::reference
