#include "train/fused_transformer.h"

#include "train/group_norm.h"
#include "train/tensor_maps.h"

#include <ATen/CPUGeneratorImpl.h>
#include <torch/autograd.h>
#include <torch/nn/modules/transformerlayer.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <mutex>
#include <vector>

namespace deixis::train {

namespace {

constexpr float kLayerNormEps = 1e-5f;

// ---- dropout masks ----

// Chris Wellons' lowbias32: a 32-bit bijection with good avalanche, cheap enough to vectorise
// (AVX2 has 32-bit multiplies), so a mask costs a few cycles per 8 elements where torch's
// bernoulli path cost 8 % of a step.
inline std::uint32_t hash32(std::uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// mask[i] = 0 with probability p, else 1/(1 − p) (inverted dropout, as torch), element i drawn
// from the top 31 bits of hash32(hash32(i + key_lo) ^ key_hi): a signed 32-bit comparison, which
// AVX2 has (an unsigned one it has not), so the loop vectorises. Masks hold fewer than 2³¹
// elements.
void fill_dropout_mask(float* mask, std::int64_t n, std::uint64_t key, double p) {
  const auto lo = static_cast<std::uint32_t>(key);
  const auto hi = static_cast<std::uint32_t>(key >> 32);
  const auto threshold = static_cast<std::int32_t>(std::min(p * 2147483648.0, 2147483647.0));
  const auto keep = static_cast<float>(1.0 / (1.0 - p));
  const auto count = static_cast<std::uint32_t>(n);
  for (std::uint32_t i = 0; i < count; ++i) {
    const auto u = static_cast<std::int32_t>(hash32(hash32(i + lo) ^ hi) >> 1);
    mask[i] = u >= threshold ? keep : 0.0f;
  }
}

// ---- shapes and saved buffers ----

struct Dims {
  Eigen::Index time, batch, d, heads, head_dim, ff;
  Eigen::Index first_query;  // the first token whose output is computed
  Eigen::Index queries() const { return time - first_query; }
  Eigen::Index rows() const { return time * batch; }             // every token
  Eigen::Index query_rows() const { return queries() * batch; }  // tokens with an output
  Eigen::Index query_offset() const { return first_query * batch; }
  // The four dropout masks, packed: attention weights [queries][time][heads·batch], attention
  // output, feed-forward hidden, feed-forward output ([query rows][width] each).
  Eigen::Index attention_size() const { return batch * heads * queries() * time; }
  Eigen::Index mask_size() const {
    return attention_size() + query_rows() * d + query_rows() * ff + query_rows() * d;
  }
};

// Offsets of the packed masks, nullptr when there is no dropout.
struct Masks {
  const float* attention = nullptr;
  const float* attention_out = nullptr;
  const float* hidden = nullptr;
  const float* ff_out = nullptr;
  Masks(const torch::Tensor& packed, const Dims& s) {
    if (packed.numel() == 0) {
      return;
    }
    attention = packed.data_ptr<float>();
    attention_out = attention + s.attention_size();
    hidden = attention_out + s.query_rows() * s.d;
    ff_out = hidden + s.query_rows() * s.ff;
  }
};

// m ⊙= mask, when there is a mask (m is rows × cols, contiguous).
void apply_mask(Eigen::Ref<RowMatrix> m, const float* mask) {
  if (mask != nullptr) {
    m.array() *= ConstMatrixMap(mask, m.rows(), m.cols()).array();
  }
}

// ---- attention ----
//
// Per (batch item, head) the blocks are tiny (30 × 30 scores, head_dim 4): too small for GEMM
// calls, and rows of 30 are not a multiple of the vector width. So the attention runs on all
// (head, batch item) pairs at once, with that pair index innermost ([token][channel][head·batch],
// 64 floats for MPNet): every loop below is then an element-wise pass over contiguous pairs,
// which the compiler vectorises fully, with no reductions along the vector.

// Queries [queries][head_dim][pairs], keys and values [time][head_dim][pairs], pair = h·batch + b.
struct HeadMajor {
  std::vector<float> q, k, v;
  explicit HeadMajor(const Dims& s)
      : q(static_cast<std::size_t>(s.queries() * s.d * s.batch)),
        k(static_cast<std::size_t>(s.time * s.d * s.batch)),
        v(static_cast<std::size_t>(s.time * s.d * s.batch)) {}
};

// Token t's channel c of part (0 query, 1 key, 2 value) in qkv [time·batch, 3d] → in the
// head-major buffer, for every head and batch item. Also used for ∂L/∂a [query rows, d] with
// parts = 1.
void to_head_major(const Dims& s, const float* rows, Eigen::Index width, Eigen::Index part,
                   Eigen::Index first, Eigen::Index count, float* out) {
  const Eigen::Index pairs = s.heads * s.batch;
  for (Eigen::Index t = 0; t < count; ++t) {
    for (Eigen::Index b = 0; b < s.batch; ++b) {
      const float* row = rows + ((first + t) * s.batch + b) * width + part * s.d;
      for (Eigen::Index h = 0; h < s.heads; ++h) {
        for (Eigen::Index c = 0; c < s.head_dim; ++c) {
          out[(t * s.head_dim + c) * pairs + h * s.batch + b] = row[h * s.head_dim + c];
        }
      }
    }
  }
}

// The inverse of to_head_major (writes; every element of the block is written once).
void from_head_major(const Dims& s, const float* in, Eigen::Index width, Eigen::Index part,
                     Eigen::Index first, Eigen::Index count, float* rows) {
  const Eigen::Index pairs = s.heads * s.batch;
  for (Eigen::Index t = 0; t < count; ++t) {
    for (Eigen::Index b = 0; b < s.batch; ++b) {
      float* row = rows + ((first + t) * s.batch + b) * width + part * s.d;
      for (Eigen::Index h = 0; h < s.heads; ++h) {
        for (Eigen::Index c = 0; c < s.head_dim; ++c) {
          row[h * s.head_dim + c] = in[(t * s.head_dim + c) * pairs + h * s.batch + b];
        }
      }
    }
  }
}

HeadMajor gather_heads(const Dims& s, const float* qkv) {
  HeadMajor m(s);
  to_head_major(s, qkv, 3 * s.d, 0, s.first_query, s.queries(), m.q.data());
  to_head_major(s, qkv, 3 * s.d, 1, 0, s.time, m.k.data());
  to_head_major(s, qkv, 3 * s.d, 2, 0, s.time, m.v.data());
  return m;
}

// y ← y + a ⊙ b, element-wise over n.
inline void add_product(const float* a, const float* b, float* y, Eigen::Index n) {
  for (Eigen::Index x = 0; x < n; ++x) {
    y[x] += a[x] * b[x];
  }
}

// Query i's P ⊙ mask [time][pairs] into scratch, or P itself without a mask.
const float* dropped(const float* p, const float* mask, Eigen::Index n,
                     std::vector<float>& scratch) {
  if (mask == nullptr) {
    return p;
  }
  for (Eigen::Index x = 0; x < n; ++x) {
    scratch[static_cast<std::size_t>(x)] = p[x] * mask[x];
  }
  return scratch.data();
}

// P = softmax(Q·Kᵀ / √head_dim) over the keys, kept before dropout in probabilities
// [queries][time][pairs], and the heads' outputs (P ⊙ mask)·V into a [query rows, d].
void attention_forward(const Dims& s, const float* qkv, const float* mask, float* probabilities,
                       float* a) {
  const float scale = 1.0f / std::sqrt(static_cast<float>(s.head_dim));
  const Eigen::Index n = s.time, hd = s.head_dim, pairs = s.heads * s.batch, block = n * pairs;
  const HeadMajor in = gather_heads(s, qkv);
  std::vector<float> out(static_cast<std::size_t>(s.queries() * hd * pairs));
  std::vector<float> scratch(static_cast<std::size_t>(block));
  Eigen::ArrayXf extreme(pairs), sum(pairs);
  for (Eigen::Index i = 0; i < s.queries(); ++i) {
    float* p = probabilities + i * block;
    std::fill(p, p + block, 0.0f);
    for (Eigen::Index j = 0; j < n; ++j) {
      for (Eigen::Index c = 0; c < hd; ++c) {
        add_product(&in.q[static_cast<std::size_t>((i * hd + c) * pairs)],
                    &in.k[static_cast<std::size_t>((j * hd + c) * pairs)], p + j * pairs, pairs);
      }
    }
    // Softmax over the keys j, for every pair at once.
    Eigen::Map<Eigen::ArrayXXf> scores(p, pairs, n);  // column j: key j
    scores *= scale;
    extreme = scores.rowwise().maxCoeff();
    scores.colwise() -= extreme;
    scores = scores.exp();
    sum = scores.rowwise().sum().inverse();
    scores.colwise() *= sum;
    const float* kept = dropped(p, mask == nullptr ? nullptr : mask + i * block, block, scratch);
    for (Eigen::Index c = 0; c < hd; ++c) {
      float* o = &out[static_cast<std::size_t>((i * hd + c) * pairs)];
      for (Eigen::Index j = 0; j < n; ++j) {
        add_product(kept + j * pairs, &in.v[static_cast<std::size_t>((j * hd + c) * pairs)], o,
                    pairs);
      }
    }
  }
  from_head_major(s, out.data(), s.d, 0, 0, s.queries(), a);
}

// Backward of attention_forward: ∂L/∂(q, k, v) into d_qkv [time·batch, 3d] from ∂L/∂a (rows of
// tokens before the first query keep a zero query gradient: d_qkv is zeroed by the caller).
void attention_backward(const Dims& s, const float* qkv, const float* mask,
                        const float* probabilities, const float* da, float* d_qkv) {
  const float scale = 1.0f / std::sqrt(static_cast<float>(s.head_dim));
  const Eigen::Index n = s.time, hd = s.head_dim, pairs = s.heads * s.batch, block = n * pairs;
  const HeadMajor in = gather_heads(s, qkv);
  HeadMajor grad(s);  // zero-initialised
  std::vector<float> d_out(static_cast<std::size_t>(s.queries() * hd * pairs));
  to_head_major(s, da, s.d, 0, 0, s.queries(), d_out.data());
  std::vector<float> scratch(static_cast<std::size_t>(block)), dp(static_cast<std::size_t>(block));
  Eigen::ArrayXf p_dp(pairs);
  for (Eigen::Index i = 0; i < s.queries(); ++i) {
    const float* p = probabilities + i * block;
    const float* m = mask == nullptr ? nullptr : mask + i * block;
    const float* kept = dropped(p, m, block, scratch);
    // out = P̃·V with P̃ = P ⊙ mask: ∂V += P̃ᵀ·∂out, ∂P = (∂out·Vᵀ) ⊙ mask.
    std::fill(dp.begin(), dp.end(), 0.0f);
    for (Eigen::Index j = 0; j < n; ++j) {
      for (Eigen::Index c = 0; c < hd; ++c) {
        const float* g = &d_out[static_cast<std::size_t>((i * hd + c) * pairs)];
        const auto jc = static_cast<std::size_t>((j * hd + c) * pairs);
        add_product(kept + j * pairs, g, &grad.v[jc], pairs);
        add_product(g, &in.v[jc], &dp[static_cast<std::size_t>(j * pairs)], pairs);
      }
    }
    Eigen::Map<Eigen::ArrayXXf> d_p(dp.data(), pairs, n);
    const Eigen::Map<const Eigen::ArrayXXf> probability(p, pairs, n);
    if (m != nullptr) {
      d_p *= Eigen::Map<const Eigen::ArrayXXf>(m, pairs, n);
    }
    // Softmax: ∂scores = P ⊙ (∂P − Σ_j P ⊙ ∂P); scores = scale · Q·Kᵀ.
    p_dp = (probability * d_p).rowwise().sum();
    d_p = scale * probability * (d_p.colwise() - p_dp);
    for (Eigen::Index j = 0; j < n; ++j) {
      for (Eigen::Index c = 0; c < hd; ++c) {
        const auto ic = static_cast<std::size_t>((i * hd + c) * pairs);
        const auto jc = static_cast<std::size_t>((j * hd + c) * pairs);
        const float* ds = &dp[static_cast<std::size_t>(j * pairs)];
        add_product(ds, &in.k[jc], &grad.q[ic], pairs);
        add_product(ds, &in.q[ic], &grad.k[jc], pairs);
      }
    }
  }
  from_head_major(s, grad.q.data(), 3 * s.d, 0, s.first_query, s.queries(), d_qkv);
  from_head_major(s, grad.k.data(), 3 * s.d, 1, 0, s.time, d_qkv);
  from_head_major(s, grad.v.data(), 3 * s.d, 2, 0, s.time, d_qkv);
}

// ---- the layer ----

struct EncoderLayerFunction : public torch::autograd::Function<EncoderLayerFunction> {
  enum Saved {
    kX,
    kInW,
    kOutW,
    kW1,
    kW2,
    kGamma1,
    kGamma2,
    kQkv,
    kProbabilities,
    kAttention,
    kNorm1,
    kXHat1,
    kRstd1,
    kHidden,
    kXHat2,
    kRstd2,
    kMasks,
  };

  static Dims dims_of(const torch::Tensor& x, const torch::Tensor& w1, std::int64_t heads,
                      bool last_only) {
    Dims s{};
    s.time = x.size(0);
    s.batch = x.size(1);
    s.d = x.size(2);
    s.heads = heads;
    s.head_dim = s.d / heads;
    s.ff = w1.size(0);
    s.first_query = last_only ? s.time - 1 : 0;
    return s;
  }

  static torch::Tensor forward(torch::autograd::AutogradContext* ctx, torch::Tensor x,
                               torch::Tensor in_w, torch::Tensor in_b, torch::Tensor out_w,
                               torch::Tensor out_b, torch::Tensor w1, torch::Tensor b1,
                               torch::Tensor w2, torch::Tensor b2, torch::Tensor gamma1,
                               torch::Tensor beta1, torch::Tensor gamma2, torch::Tensor beta2,
                               std::int64_t heads, EncoderLayerOptions options) {
    x = x.contiguous();
    in_w = in_w.contiguous();
    out_w = out_w.contiguous();
    w1 = w1.contiguous();
    w2 = w2.contiguous();
    const Dims s = dims_of(x, w1, heads, options.last_only);
    const Eigen::Index rows = s.rows(), nq = s.query_rows(), d = s.d;
    const torch::TensorOptions f32 = x.options();

    torch::Tensor masks = torch::empty({options.dropout > 0.0 ? s.mask_size() : 0}, f32);
    if (masks.numel() > 0) {
      TORCH_CHECK(masks.numel() < (std::int64_t{1} << 31), "encoder_layer: too many tokens");
      fill_dropout_mask(masks.data_ptr<float>(), masks.numel(), options.seed, options.dropout);
    }
    const Masks m(masks, s);

    // Self-attention.
    torch::Tensor qkv = torch::empty({rows, 3 * d}, f32);
    map_mut(qkv, rows, 3 * d).noalias() = map(x, rows, d) * map(in_w, 3 * d, d).transpose();
    map_mut(qkv, rows, 3 * d).rowwise() += vec(in_b.contiguous());
    torch::Tensor probabilities = torch::empty({s.attention_size()}, f32);
    torch::Tensor attention = torch::empty({nq, d}, f32);
    attention_forward(s, qkv.data_ptr<float>(), m.attention, probabilities.data_ptr<float>(),
                      attention.data_ptr<float>());

    // x = norm1(x + dropout(out_proj(attention))), on the query rows only.
    RowMatrix residual = map(attention, nq, d) * map(out_w, d, d).transpose();
    residual.rowwise() += vec(out_b.contiguous());
    apply_mask(residual, m.attention_out);
    residual += map(x, nq, d, s.query_offset() * d);
    torch::Tensor x_hat1 = torch::empty({nq, d}, f32);
    torch::Tensor rstd1 = torch::empty({nq}, f32);
    torch::Tensor norm1 = torch::empty({nq, d}, f32);
    MatrixMap x_hat1_map = map_mut(x_hat1, nq, d), norm1_map = map_mut(norm1, nq, d);
    group_norm(residual, 1, kLayerNormEps, vec(gamma1.contiguous()), vec(beta1.contiguous()),
               x_hat1_map, rstd1.data_ptr<float>(), norm1_map);

    // x = norm2(x + dropout(linear2(dropout(relu(linear1(x)))))).
    torch::Tensor hidden = torch::empty({nq, s.ff}, f32);
    MatrixMap h = map_mut(hidden, nq, s.ff);
    h.noalias() = map(norm1, nq, d) * map(w1, s.ff, d).transpose();
    h.rowwise() += vec(b1.contiguous());
    h = h.cwiseMax(0.0f);
    apply_mask(h, m.hidden);
    residual.noalias() = h * map(w2, d, s.ff).transpose();
    residual.rowwise() += vec(b2.contiguous());
    apply_mask(residual, m.ff_out);
    residual += map(norm1, nq, d);
    torch::Tensor x_hat2 = torch::empty({nq, d}, f32);
    torch::Tensor rstd2 = torch::empty({nq}, f32);
    torch::Tensor out = options.last_only ? torch::empty({s.batch, d}, f32)
                                          : torch::empty({s.queries(), s.batch, d}, f32);
    MatrixMap x_hat2_map = map_mut(x_hat2, nq, d), out_map = map_mut(out, nq, d);
    group_norm(residual, 1, kLayerNormEps, vec(gamma2.contiguous()), vec(beta2.contiguous()),
               x_hat2_map, rstd2.data_ptr<float>(), out_map);

    ctx->save_for_backward({x, in_w, out_w, w1, w2, gamma1.contiguous(), gamma2.contiguous(), qkv,
                            probabilities, attention, norm1, x_hat1, rstd1, hidden, x_hat2, rstd2,
                            masks});
    ctx->saved_data["heads"] = heads;
    ctx->saved_data["last_only"] = options.last_only;
    return out;
  }

  static torch::autograd::tensor_list backward(torch::autograd::AutogradContext* ctx,
                                               torch::autograd::tensor_list grad_outputs) {
    const auto v = ctx->get_saved_variables();
    const torch::Tensor& x = v[kX];
    const Dims s =
        dims_of(x, v[kW1], ctx->saved_data["heads"].toInt(), ctx->saved_data["last_only"].toBool());
    const Eigen::Index rows = s.rows(), nq = s.query_rows(), d = s.d, ff = s.ff;
    const Masks m(v[kMasks], s);
    const torch::Tensor g = grad_outputs[0].defined() ? grad_outputs[0].contiguous()
                                                      : torch::zeros({nq, d}, x.options());

    torch::Tensor d_gamma2 = torch::empty({d}, x.options()), d_beta2 = torch::empty_like(d_gamma2);
    RowMatrix d_residual(nq, d);
    group_norm_backward(map(g, nq, d), map(v[kXHat2], nq, d), v[kRstd2].data_ptr<float>(), 1,
                        vec(v[kGamma2]), vec_mut(d_gamma2), vec_mut(d_beta2), d_residual);

    // Feed-forward block: residual₂ = norm1 + mask₄ ⊙ (hidden·W₂ᵀ + b₂), hidden = mask₃ ⊙ relu(·).
    RowMatrix d_norm1 = d_residual;
    apply_mask(d_residual, m.ff_out);
    torch::Tensor d_w2 = torch::empty({d, ff}, x.options()), d_b2 = torch::empty({d}, x.options());
    const ConstMatrixMap hidden = map(v[kHidden], nq, ff);
    map_mut(d_w2, d, ff).noalias() = d_residual.transpose() * hidden;
    vec_mut(d_b2) = d_residual.colwise().sum();
    RowMatrix d_hidden = d_residual * map(v[kW2], d, ff);
    apply_mask(d_hidden, m.hidden);
    // A kept hidden unit is positive exactly when its ReLU was active; a dropped one has no
    // gradient either way.
    d_hidden.array() = (hidden.array() > 0.0f).select(d_hidden.array(), 0.0f);
    torch::Tensor d_w1 = torch::empty({ff, d}, x.options()), d_b1 = torch::empty({ff}, x.options());
    map_mut(d_w1, ff, d).noalias() = d_hidden.transpose() * map(v[kNorm1], nq, d);
    vec_mut(d_b1) = d_hidden.colwise().sum();
    d_norm1.noalias() += d_hidden * map(v[kW1], ff, d);

    torch::Tensor d_gamma1 = torch::empty({d}, x.options()), d_beta1 = torch::empty_like(d_gamma1);
    group_norm_backward(d_norm1, map(v[kXHat1], nq, d), v[kRstd1].data_ptr<float>(), 1,
                        vec(v[kGamma1]), vec_mut(d_gamma1), vec_mut(d_beta1), d_residual);

    // Attention block: residual₁ = x + mask₂ ⊙ (attention·W_outᵀ + b_out).
    torch::Tensor d_x = torch::zeros_like(x);
    map_mut(d_x, nq, d, s.query_offset() * d) = d_residual;
    apply_mask(d_residual, m.attention_out);
    torch::Tensor d_out_w = torch::empty({d, d}, x.options()),
                  d_out_b = torch::empty({d}, x.options());
    map_mut(d_out_w, d, d).noalias() = d_residual.transpose() * map(v[kAttention], nq, d);
    vec_mut(d_out_b) = d_residual.colwise().sum();
    const RowMatrix d_attention = d_residual * map(v[kOutW], d, d);

    torch::Tensor d_qkv = torch::zeros({rows, 3 * d}, x.options());
    attention_backward(s, v[kQkv].data_ptr<float>(), m.attention,
                       v[kProbabilities].data_ptr<float>(), d_attention.data(),
                       d_qkv.data_ptr<float>());
    torch::Tensor d_in_w = torch::empty({3 * d, d}, x.options()),
                  d_in_b = torch::empty({3 * d}, x.options());
    const ConstMatrixMap dqkv = map(d_qkv, rows, 3 * d);
    map_mut(d_in_w, 3 * d, d).noalias() = dqkv.transpose() * map(x, rows, d);
    vec_mut(d_in_b) = dqkv.colwise().sum();
    map_mut(d_x, rows, d).noalias() += dqkv * map(v[kInW], 3 * d, d);

    return {d_x,      d_in_w,  d_in_b,   d_out_w, d_out_b,         d_w1,           d_b1, d_w2, d_b2,
            d_gamma1, d_beta1, d_gamma2, d_beta2, torch::Tensor(), torch::Tensor()};
  }
};

std::uint64_t draw_key(at::Generator& generator) {
  std::lock_guard<std::mutex> lock(generator.mutex());
  return splitmix64(generator.get<at::CPUGeneratorImpl>()->random64());
}

}  // namespace

torch::Tensor dropout_masks(std::int64_t count, std::uint64_t key, double p) {
  TORCH_CHECK(count < (std::int64_t{1} << 31), "dropout_masks: fewer than 2^31 elements");
  torch::Tensor masks = torch::empty({count});
  fill_dropout_mask(masks.data_ptr<float>(), count, key, p);
  return masks;
}

torch::Tensor encoder_layer(const torch::Tensor& tokens, const EncoderLayerWeights& w,
                            const EncoderLayerOptions& options) {
  TORCH_CHECK(tokens.dim() == 3 && tokens.scalar_type() == torch::kFloat32,
              "encoder_layer: tokens must be float32 [time, batch, d]");
  TORCH_CHECK(tokens.size(2) % w.heads == 0, "encoder_layer: d not divisible by the heads");
  TORCH_CHECK(options.dropout >= 0.0 && options.dropout < 1.0, "encoder_layer: dropout in [0, 1)");
  return EncoderLayerFunction::apply(tokens, w.in_proj_weight, w.in_proj_bias, w.out_proj_weight,
                                     w.out_proj_bias, w.linear1_weight, w.linear1_bias,
                                     w.linear2_weight, w.linear2_bias, w.norm1_weight, w.norm1_bias,
                                     w.norm2_weight, w.norm2_bias, w.heads, options);
}

torch::Tensor encoder_last_token(torch::nn::TransformerEncoder& encoder,
                                 const torch::Tensor& tokens, at::Generator generator) {
  TORCH_CHECK(encoder->norm.is_empty(), "encoder_last_token: a final norm is not supported");
  torch::Tensor x = tokens;
  const std::size_t layers = encoder->layers->size();
  for (std::size_t l = 0; l < layers; ++l) {
    auto* layer = encoder->layers[l]->as<torch::nn::TransformerEncoderLayerImpl>();
    TORCH_CHECK(layer != nullptr &&
                    c10::get_if<torch::enumtype::kReLU>(&layer->options.activation()) != nullptr,
                "encoder_last_token: ReLU TransformerEncoderLayers only");
    const EncoderLayerWeights w{layer->self_attn->in_proj_weight,
                                layer->self_attn->in_proj_bias,
                                layer->self_attn->out_proj->weight,
                                layer->self_attn->out_proj->bias,
                                layer->linear1->weight,
                                layer->linear1->bias,
                                layer->linear2->weight,
                                layer->linear2->bias,
                                layer->norm1->weight,
                                layer->norm1->bias,
                                layer->norm2->weight,
                                layer->norm2->bias,
                                layer->options.nhead()};
    EncoderLayerOptions options;
    options.last_only = l + 1 == layers;
    if (layer->is_training() && layer->options.dropout() > 0.0) {
      options.dropout = layer->options.dropout();
      options.seed = draw_key(generator);
    }
    x = encoder_layer(x, w, options);
  }
  return layers == 0 ? x.select(0, -1) : x;
}

}  // namespace deixis::train
