#pragma once
// A second, independent implementation of every network, in double precision and written for
// clarity rather than speed: plain loops over std::vector<double>, one small function per PyTorch
// operation, each network spelled out the way the authors' forward() reads (model.py,
// ISMAR2023/model.py; summarised in docs/conventions.md#mpnet, #ugnet, #amnet). It shares nothing
// with gesture/nn except the safetensors reader, so a mistake in the fast float32 path shows up as
// a disagreement here instead of being repeated.
//
// It exists for the tests: against the fixtures' float64 PyTorch outputs it agrees to rounding
// (reference_parity_test.cpp states the measured error), and it is then the yardstick for the fast
// path on inputs the fixtures never had.
//
// Conventions: a Vector is one row or one feature vector; Rows is a window (oldest row first) or a
// sequence of transformer tokens. Checkpoint tensors keep PyTorch's row-major layout and names.

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace deixis::reference {

using Vector = std::vector<double>;
using Rows = std::vector<Vector>;

// One checkpoint tensor, converted from float32 to double (exactly), row-major.
struct Tensor {
  std::vector<std::int64_t> shape;
  std::vector<double> values;
};

// All float32 tensors of a checkpoint by their state_dict name (Appendix A.2). The int64 BatchNorm
// counters are not needed and not kept.
class Weights {
 public:
  static Weights load(const std::filesystem::path& checkpoint);

  // nullptr when absent.
  const Tensor* find(const std::string& name) const;
  // The tensor, which must exist with exactly this shape; throws deixis::Error otherwise.
  const Tensor& get(const std::string& name, const std::vector<std::int64_t>& shape) const;

 private:
  std::string source_;
  std::map<std::string, Tensor> tensors_;
};

// ---- operations, named as in PyTorch --------------------------------------------------------

double sigmoid(double x);
Vector relu(Vector x);
Vector elu(Vector x);   // α = 1: x for x > 0, exp(x) − 1 otherwise
Vector silu(Vector x);  // x · σ(x)
Vector softmax(const Vector& x);
Vector concat(const std::vector<Vector>& parts);

// nn.Linear: weight [out, in], y = W·x + b.
Vector linear(const Vector& x, const Tensor& weight, const Tensor& bias);

// One layer of nn.GRU over a whole sequence from h0 = 0 (the authors' GRUs are not stateful,
// docs/conventions.md#grus); returns the hidden state after every row.
struct GruLayerWeights {
  const Tensor& weight_ih;  // [3H, in], gates stacked r | z | n
  const Tensor& weight_hh;  // [3H, H]
  const Tensor& bias_ih;    // [3H]
  const Tensor& bias_hh;    // [3H]
};
Rows gru_layer(const Rows& inputs, const GruLayerWeights& weights);

// LayerNorm over one vector (biased variance), eps 1e-5.
Vector layer_norm(const Vector& x, const Tensor& weight, const Tensor& bias);

// nn.MultiheadAttention self-attention (query = key = value = the tokens), no mask.
Rows multi_head_attention(const Rows& tokens, int heads, const Tensor& in_proj_weight,
                          const Tensor& in_proj_bias, const Tensor& out_proj_weight,
                          const Tensor& out_proj_bias);

// nn.TransformerEncoderLayer, post-norm, ReLU, eval mode (docs/conventions.md#mpnet); `prefix` is
// e.g. "transformer.layers.0".
Rows transformer_encoder_layer(const Rows& tokens, int heads, int feed_forward,
                               const Weights& weights, const std::string& prefix);

// nn.GroupNorm on one sample of C channels, eps 1e-5, per-channel affine
// (docs/conventions.md#ugnet-diffusion).
Vector group_norm(const Vector& x, int groups, const Tensor& weight, const Tensor& bias);

// nn.BatchNorm1d in eval mode: running statistics, eps 1e-5 (docs/conventions.md#amnet).
Vector batch_norm_eval(const Vector& x, const Tensor& weight, const Tensor& bias,
                       const Tensor& running_mean, const Tensor& running_var);

// One layer of the authors' ExpertMLP (docs/conventions.md#mixture-of-experts):
// W = Σ_e ω_e W_e, b = Σ_e ω_e b_e, then y = x·W + b, with W stored [experts, in, out] and
// multiplying from the right.
Vector expert_layer(const Vector& x, const Vector& omega, const Tensor& weight, const Tensor& bias);

// model.py PositionalEmbedding(dim, scale 1) of an integer time step: for k = 0 … dim/2 − 1,
// ω_k = exp(−k·ln(10⁴)/(dim/2)); [sin(t·ω_k) …, cos(t·ω_k) …]
// (docs/conventions.md#ugnet-diffusion).
Vector sinusoidal_time_embedding(int t, int dim);

// ---- networks -----------------------------------------------------------------------------------

enum class Architecture {
  kMpnetGruMoe,
  kMpnetMlp,
  kMpnetTransformer,
  kUgnetMoe,
  kUgnetMlp,
  kUgnetTransformer,
  kUgnetDiffusion,
  kAmnet,
};
// Recognised from the checkpoint's tensor names and shapes (Appendix A.2); throws deixis::Error
// for anything else.
Architecture architecture_of(const Weights& weights);
std::string_view architecture_name(Architecture architecture);

// MPNet: a 30 × 11 window (docs/conventions.md#mpnet-features).
struct MpnetResult {
  Vector progression;  // clamped to [0, 1]
  Vector preclamp;
  Vector omega;  // GRU-MoE only: gating softmax (9)
  Vector z;      // GRU-MoE only: the recurrent GRU's last output (24)
};
MpnetResult mpnet_gru_moe(const Weights& weights, const Rows& window);
MpnetResult mpnet_mlp(const Weights& weights, const Rows& window);
MpnetResult mpnet_transformer(const Weights& weights, const Rows& window);

// UGNet: a 30 × 32 window (docs/conventions.md#end-effectors).
struct UgnetResult {
  Vector pose;          // the next frame's 24-vector
  Vector omega;         // MoE only: gating softmax (9)
  Rows denoised_steps;  // Diffusion only: the denoiser's x0 at each of the 30 steps, t = 29 … 0
};
UgnetResult ugnet_moe(const Weights& weights, const Rows& window);
UgnetResult ugnet_mlp(const Weights& weights, const Rows& window);
UgnetResult ugnet_transformer(const Weights& weights, const Rows& window);
// `noise` holds the 30 standard-normal draws of sample_ddpm: noise[0] is the initial x, noise[i]
// (i = 1 … 29) is added, scaled by σ_t, after the step t = 30 − i
// (docs/conventions.md#ugnet-diffusion).
UgnetResult ugnet_diffusion(const Weights& weights, const Rows& window, const Rows& noise);

// AMNet (ISMAR 2023): local and remote windows of 20 × 16 (docs/conventions.md#amnet) → 21
// end-effector values.
Vector amnet(const Weights& weights, const Rows& local, const Rows& remote);

}  // namespace deixis::reference
