#include "train/moe_step.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/error.h"

namespace deixis::train {

namespace {

using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
using MatrixMap = Eigen::Map<RowMatrix>;
using ConstMatrixMap = Eigen::Map<const RowMatrix>;
using StridedMap = Eigen::Map<RowMatrix, 0, Eigen::OuterStride<>>;
using ConstStridedMap = Eigen::Map<const RowMatrix, 0, Eigen::OuterStride<>>;
using ArrayMap = Eigen::Map<Eigen::ArrayXf>;
using ConstArrayMap = Eigen::Map<const Eigen::ArrayXf>;

constexpr int kTime = MoeStep::kWindowRows;
constexpr int kExperts = MoeStep::kExperts;

// The product of extents as an index (every extent here is small and non-negative).
template <typename... Extent>
std::size_t size(Extent... extents) {
  return (static_cast<std::size_t>(extents) * ...);
}

// Eight floats: one AVX register with -march=x86-64-v3, two SSE registers without. The GRUs
// hold the batch in lanes, padded to a multiple of eight clips.
using Lane = float __attribute__((vector_size(32)));
constexpr int kLaneWidth = 8;

Lane load(const float* p) {
  Lane v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
void store(float* p, Lane v) {
  std::memcpy(p, &v, sizeof v);
}

// A small weight matrix read as w(g, k) = w[g·row + k·col]: W itself (row = columns, col = 1) or
// its transpose (row = 1, col = columns) without copying it.
struct Weights {
  const float* w;
  std::size_t row, col;
  float operator()(int g, int k) const {
    return w[static_cast<std::size_t>(g) * row + static_cast<std::size_t>(k) * col];
  }
};

// R rows × NB blocks of eight lanes of out = init + Σ_k w(g, k)·in[k], each accumulator in a
// register: a loop that added one row into memory at a time waited on its own stores.
template <int R, int NB>
void product_tile(float* out, std::size_t out_stride, const float* bias, Weights w, int g0,
                  int depth, const float* in, std::size_t in_stride, int block0) {
  Lane acc[R][NB];
  for (int r = 0; r < R; ++r) {
    for (int j = 0; j < NB; ++j) {
      float* o = out + static_cast<std::size_t>(g0 + r) * out_stride +
                 static_cast<std::size_t>((block0 + j) * kLaneWidth);
      acc[r][j] = bias != nullptr ? Lane{} + bias[g0 + r] : load(o);
    }
  }
  for (int k = 0; k < depth; ++k) {
    Lane x[NB];
    for (int j = 0; j < NB; ++j) {
      x[j] = load(in + static_cast<std::size_t>(k) * in_stride +
                  static_cast<std::size_t>((block0 + j) * kLaneWidth));
    }
    for (int r = 0; r < R; ++r) {
      const float weight = w(g0 + r, k);
      for (int j = 0; j < NB; ++j) {
        acc[r][j] += weight * x[j];
      }
    }
  }
  for (int r = 0; r < R; ++r) {
    for (int j = 0; j < NB; ++j) {
      store(out + static_cast<std::size_t>(g0 + r) * out_stride +
                static_cast<std::size_t>((block0 + j) * kLaneWidth),
            acc[r][j]);
    }
  }
}

// out[g][lanes] = (bias[g] or out's own values) + Σ_{k < depth} w(g, k)·in[k·in_stride + lanes]
// for g < rows: one time step's product with the batch in lanes.
void lane_product(float* out, std::size_t out_stride, const float* bias, Weights w, int rows,
                  int depth, const float* in, std::size_t in_stride, int lanes) {
  const int blocks = lanes / kLaneWidth;
  auto row_group = [&]<int R>(int g) {
    int j = 0;
    for (; j + 2 <= blocks; j += 2) {
      product_tile<R, 2>(out, out_stride, bias, w, g, depth, in, in_stride, j);
    }
    if (j < blocks) {
      product_tile<R, 1>(out, out_stride, bias, w, g, depth, in, in_stride, j);
    }
  };
  int g = 0;
  for (; g + 4 <= rows; g += 4) {
    row_group.template operator()<4>(g);
  }
  for (; g < rows; ++g) {
    row_group.template operator()<1>(g);
  }
}

// ELU (α = 1). Its derivative is taken from the output a in experts_backward: 1 where a > 0,
// a + 1 elsewhere.
void elu(const float* u, float* a, std::size_t n) {
  const ConstArrayMap in(u, static_cast<Eigen::Index>(n));
  ArrayMap(a, static_cast<Eigen::Index>(n)) = (in > 0.0f).select(in, in.exp() - 1.0f);
}

// The GRUs' lanes for a batch: the batch rounded up to whole vectors.
int lanes_for(int batch) {
  return (batch + kLaneWidth - 1) / kLaneWidth * kLaneWidth;
}

}  // namespace

MoeShape MoeShape::mpnet() {
  MoeShape s;
  s.window_columns = 11;
  s.gating_first = 6;
  s.gating_columns = 5;
  s.encoder_hidden = 24;
  s.expert_in = 24;
  s.expert_hidden = 12;
  s.expert_out = 3;
  s.clamp_output = true;
  return s;
}

MoeShape MoeShape::ugnet() {
  MoeShape s;
  s.window_columns = 32;
  s.gating_first = 24;
  s.gating_columns = 8;
  s.pose_columns = 24;
  s.expert_in = 24 + 8 * kTime;          // 264
  s.expert_hidden = 24 + 8 * kTime / 2;  // 144
  s.expert_out = 24;
  return s;
}

std::size_t MoeShape::parameter_count() const {
  auto gru = [](int in, int hidden) { return size(3 * hidden, in + hidden + 2); };
  std::size_t n = gru(gating_columns, kExperts) + gru(kExperts, kExperts);
  if (encoder_hidden > 0) {
    n += gru(window_columns, encoder_hidden);
  }
  const int dims[4] = {expert_in, expert_hidden, expert_hidden, expert_out};
  for (int l = 0; l < 3; ++l) {
    n += size(kExperts, dims[l] + 1, dims[l + 1]);
  }
  return n;
}

MoeStep::MoeStep(const MoeShape& shape, int max_batch, int members)
    : shape_(shape),
      max_batch_(max_batch),
      dims_{shape.expert_in, shape.expert_hidden, shape.expert_hidden, shape.expert_out} {
  if (max_batch < 1) {
    throw Error("MoeStep: the batch must hold at least one window");
  }
  if (members < 1 || members > kExperts) {
    throw Error("MoeStep: a team of 1 to " + std::to_string(kExperts) + " threads shares the " +
                std::to_string(kExperts) + " experts, not " + std::to_string(members));
  }
  const int lanes = lanes_for(max_batch);
  auto make_gru = [&](GruLayerState& layer, int input, int hidden) {
    layer.input = input;
    layer.hidden = hidden;
    layer.input_sequence.resize(size(input, kTime, lanes));
    layer.output.resize(size(hidden, kTime, lanes));
    layer.gates.resize(size(kTime, 4, hidden, lanes));
    layer.d_output.resize(size(hidden, kTime, lanes));
    layer.d_input_gates.resize(size(3 * hidden, kTime, lanes));
    layer.d_hidden_gates.resize(size(3 * hidden, kTime, lanes));
  };
  make_gru(gating_[0], shape.gating_columns, kExperts);
  make_gru(gating_[1], kExperts, kExperts);
  if (shape.encoder_hidden > 0) {
    make_gru(encoder_, shape.window_columns, shape.encoder_hidden);
  }
  const int widest = std::max(shape.expert_in, shape.expert_hidden);
  members_.resize(static_cast<std::size_t>(members));
  for (MemberState& m : members_) {
    for (int l = 0; l < 3; ++l) {
      m.input[l].resize(size(max_batch, dims_[l]));
      m.partial[l].resize(size(max_batch, dims_[l + 1]));
      m.blended[l].resize(size(max_batch, dims_[l + 1]));
      m.d_input_part[l].resize(size(max_batch, dims_[l]));
    }
    m.d_u.resize(size(max_batch, widest));
    m.d_a.resize(size(max_batch, widest));
    m.d_h.resize(size(max_batch, widest));
    m.d_output.resize(size(max_batch, shape.expert_out));
  }
  for (int l = 0; l < 3; ++l) {
    products_[l].resize(size(kExperts, max_batch, dims_[l + 1]));
  }
  omega_.resize(size(max_batch, kExperts));
  d_omega_.resize(size(max_batch, kExperts));
  output_.resize(size(max_batch, shape.expert_out));
  // A GRU's forward needs 7 and its backward 6 blocks of hidden × lanes.
  scratch_.resize(size(7, std::max(kExperts, shape.encoder_hidden), lanes));
}

std::span<const float> MoeStep::prediction() const {
  return {output_.data(), size(batch_, shape_.expert_out)};
}

// torch.nn.GRU over the 30 rows from a zero state, one time step at a time. Everything of a step
// is a [rows][lanes] block: the gate pre-activations are products with the batch in lanes, and
// the gates are element-wise passes over contiguous blocks.
void MoeStep::gru_forward(GruLayerState& layer, const GruLayerBuffers& p) {
  const int lanes = lanes_, hidden = layer.hidden, input = layer.input;
  const std::size_t tl = size(kTime, lanes), hl = size(hidden, lanes);
  float* gi = scratch_.data();  // W_ih·x + b_ih, [3·hidden][lanes]
  float* gh = gi + 3 * hl;      // W_hh·h + b_hh
  float* h = gh + 3 * hl;       // the state, [hidden][lanes]
  std::fill(h, h + hl, 0.0f);
  const auto n = static_cast<Eigen::Index>(hl);
  const Weights w_ih{p.w_ih, static_cast<std::size_t>(input), 1};
  const Weights w_hh{p.w_hh, static_cast<std::size_t>(hidden), 1};
  for (int t = 0; t < kTime; ++t) {
    const float* x = layer.input_sequence.data() + size(t, lanes);
    lane_product(gi, size(lanes), p.b_ih, w_ih, 3 * hidden, input, x, tl, lanes);
    lane_product(gh, size(lanes), p.b_hh, w_hh, 3 * hidden, t > 0 ? hidden : 0, h, size(lanes),
                 lanes);
    float* saved = layer.gates.data() + size(t, 4, hidden, lanes);
    ArrayMap r(saved, n), z(saved + hl, n), candidate(saved + 2 * hl, n), hn(saved + 3 * hl, n);
    r = Eigen::logistic(ConstArrayMap(gi, n) + ConstArrayMap(gh, n));
    z = Eigen::logistic(ConstArrayMap(gi + hl, n) + ConstArrayMap(gh + hl, n));
    hn = ConstArrayMap(gh + 2 * hl, n);
    candidate = (ConstArrayMap(gi + 2 * hl, n) + r * hn).tanh();
    ArrayMap state(h, n);
    state = (1.0f - z) * candidate + z * state;
    for (int j = 0; j < hidden; ++j) {
      std::copy(h + size(j, lanes), h + size(j + 1, lanes),
                layer.output.data() + size(j, tl) + size(t, lanes));
    }
  }
}

// Backpropagation through time from layer.d_output (∂L/∂output at every step). The gates'
// gradients of every step are kept, so the weight gradients are two matrix products over all
// steps at the end; `d_input` (∂L/∂input, [input][time][lanes]) is written when not null.
// Padding lanes have zero ∂L/∂output, hence zero gradients, and add nothing to the products.
void MoeStep::gru_backward(GruLayerState& layer, const GruLayerBuffers& p, const GruLayerBuffers& g,
                           float* d_input) {
  const int lanes = lanes_, hidden = layer.hidden, input = layer.input;
  const std::size_t tl = size(kTime, lanes), hl = size(hidden, lanes);
  const auto n = static_cast<Eigen::Index>(hl);
  float* dh = scratch_.data();  // ∂L/∂h_t, [hidden][lanes]
  float* h_prev = dh + hl;
  float* dgh = h_prev + hl;  // the hidden side's pre-activation gradients, [3·hidden][lanes]
  float* dh_prev = dgh + 3 * hl;
  std::fill(dh, dh + hl, 0.0f);
  // W_hhᵀ, read in place.
  const Weights w_hh_transposed{p.w_hh, 1, static_cast<std::size_t>(hidden)};
  for (int t = kTime - 1; t >= 0; --t) {
    for (int j = 0; j < hidden; ++j) {
      const float* from = layer.d_output.data() + size(j, tl) + size(t, lanes);
      float* to = dh + size(j, lanes);
      for (int b = 0; b < lanes; ++b) {
        to[b] += from[b];
      }
      float* prev = h_prev + size(j, lanes);
      if (t > 0) {
        const float* state = layer.output.data() + size(j, tl) + size(t - 1, lanes);
        std::copy(state, state + lanes, prev);
      } else {
        std::fill(prev, prev + lanes, 0.0f);
      }
    }
    const float* saved = layer.gates.data() + size(t, 4, hidden, lanes);
    const ConstArrayMap r(saved, n), z(saved + hl, n), candidate(saved + 2 * hl, n),
        hn(saved + 3 * hl, n);
    const ConstArrayMap d(dh, n), prev(h_prev, n);
    // h = (1 − z)·n + z·h_prev, n = tanh(a_n + r·hn), r and z logistic.
    ArrayMap da_r(dgh, n), da_z(dgh + hl, n), da_n(dgh + 2 * hl, n);
    da_n = d * (1.0f - z) * (1.0f - candidate * candidate);
    da_z = d * (prev - candidate) * z * (1.0f - z);
    da_r = da_n * hn * r * (1.0f - r);
    // The input side sees (da_r, da_z, da_n), the recurrent product (da_r, da_z, da_n·r).
    for (int q = 0; q < 3 * hidden; ++q) {
      const float* from = dgh + size(q, lanes);
      std::copy(from, from + lanes, layer.d_input_gates.data() + size(q, tl) + size(t, lanes));
    }
    da_n *= r;
    for (int q = 0; q < 3 * hidden; ++q) {
      const float* from = dgh + size(q, lanes);
      std::copy(from, from + lanes, layer.d_hidden_gates.data() + size(q, tl) + size(t, lanes));
    }
    // ∂L/∂h_{t−1} = z ⊙ ∂L/∂h_t + W_hhᵀ·dgh.
    ArrayMap(dh_prev, n) = d * z;
    lane_product(dh_prev, size(lanes), nullptr, w_hh_transposed, hidden, 3 * hidden, dgh,
                 size(lanes), lanes);
    std::copy(dh_prev, dh_prev + hl, dh);
  }

  const auto gates = static_cast<Eigen::Index>(3 * hidden);
  const auto steps = static_cast<Eigen::Index>(tl);
  const auto recurrent = static_cast<Eigen::Index>(size(kTime - 1, lanes));
  const ConstMatrixMap d_in(layer.d_input_gates.data(), gates, steps);
  const ConstMatrixMap x(layer.input_sequence.data(), input, steps);
  MatrixMap(g.w_ih, gates, input).noalias() = d_in * x.transpose();
  Eigen::Map<Eigen::VectorXf>(g.b_ih, gates) = d_in.rowwise().sum();
  // The first step's state is zero: only steps 1..29 contribute to W_hh's gradient.
  const ConstStridedMap d_rec(layer.d_hidden_gates.data() + lanes, gates, recurrent,
                              Eigen::OuterStride<>(steps));
  const ConstStridedMap states(layer.output.data(), hidden, recurrent, Eigen::OuterStride<>(steps));
  MatrixMap(g.w_hh, gates, hidden).noalias() = d_rec * states.transpose();
  Eigen::Map<Eigen::VectorXf>(g.b_hh, gates) =
      ConstMatrixMap(layer.d_hidden_gates.data(), gates, steps).rowwise().sum();
  if (d_input != nullptr) {
    MatrixMap(d_input, input, steps).noalias() =
        ConstMatrixMap(p.w_ih, gates, input).transpose() * d_in;
  }
}

// The experts [first, last) of a layer: products a·W_e + b_e, on `count` batch-major rows.
void MoeStep::products(const MoeBuffers& p, int layer, int first_expert, int last_expert,
                       const float* a, int count) {
  const auto batch = static_cast<Eigen::Index>(count);
  const Eigen::Index in = dims_[layer], out = dims_[layer + 1];
  const ConstMatrixMap input(a, batch, in);
  for (Eigen::Index e = first_expert; e < last_expert; ++e) {
    MatrixMap product(products_[layer].data() + e * batch * out, batch, out);
    product.noalias() = input * ConstMatrixMap(p.expert_weights[layer] + e * in * out, in, out);
    product.rowwise() +=
        Eigen::Map<const Eigen::RowVectorXf>(p.expert_biases[layer] + e * out, out);
  }
}

namespace {

// Member m's experts: [9·m/n, 9·(m+1)/n).
std::pair<int, int> experts_of(ExpertTeam team) {
  return {MoeStep::kExperts * team.member / team.members,
          MoeStep::kExperts * (team.member + 1) / team.members};
}

void meet(ExpertTeam team) {
  if (team.members > 1) {
    team.sync->arrive_and_wait();
  }
}

// out = Σ over members of their part (member order, so every member computes the same bits).
template <typename Part>
void add_parts(float* out, std::size_t n, int members, Part part) {
  std::copy_n(part(0), n, out);
  for (int k = 1; k < members; ++k) {
    const float* add = part(k);
    for (std::size_t i = 0; i < n; ++i) {
      out[i] += add[i];
    }
  }
}

}  // namespace

// u_l = Σ_e ω_e ⊙ (a·W_e + b_e). Each member blends its own experts' products, the members meet,
// and each adds up every member's part into its own u_l (and a_l = ELU(u_l)).
void MoeStep::experts_forward(const MoeBuffers& p, ExpertTeam team, bool layer0_products_done) {
  const auto batch = static_cast<Eigen::Index>(batch_);
  const ConstMatrixMap omega(omega_.data(), batch, kExperts);
  const auto [first, last] = experts_of(team);
  MemberState& own = members_[static_cast<std::size_t>(team.member)];
  for (int l = 0; l < 3; ++l) {
    const Eigen::Index out = dims_[l + 1];
    if (l > 0 || !layer0_products_done) {
      products(p, l, first, last, own.input[l].data(), batch_);
    }
    MatrixMap partial(own.partial[l].data(), batch, out);
    partial.setZero();
    for (Eigen::Index e = first; e < last; ++e) {
      const ConstMatrixMap product(products_[l].data() + e * batch * out, batch, out);
      partial += (product.array().colwise() * omega.col(e).array()).matrix();
    }
    meet(team);
    const std::size_t n = size(batch_, out);
    add_parts(own.blended[l].data(), n, team.members,
              [&](int k) { return members_[static_cast<std::size_t>(k)].partial[l].data(); });
    if (l + 1 < 3) {
      elu(own.blended[l].data(), own.input[l + 1].data(), n);
    }
  }
}

// Each member: its experts' weight, bias and ω gradients and its part of ∂L/∂a; the members meet
// and each adds up ∂L/∂a, then goes through the ELU to the layer below.
void MoeStep::experts_backward(const MoeBuffers& p, const MoeBuffers& g, ExpertTeam team) {
  const auto batch = static_cast<Eigen::Index>(batch_);
  const ConstMatrixMap omega(omega_.data(), batch, kExperts);
  MatrixMap d_omega(d_omega_.data(), batch, kExperts);
  const auto [first, last] = experts_of(team);
  MemberState& own = members_[static_cast<std::size_t>(team.member)];
  std::copy_n(own.d_output.begin(), size(batch_, shape_.expert_out), own.d_u.begin());
  for (int l = 2; l >= 0; --l) {
    const Eigen::Index in = dims_[l], out = dims_[l + 1];
    const ConstMatrixMap a(own.input[l].data(), batch, in);
    const ConstMatrixMap d_u(own.d_u.data(), batch, out);
    const bool want_input = l > 0 || shape_.encoder_hidden > 0;
    MatrixMap d_a_part(own.d_input_part[l].data(), batch, want_input ? in : 0);
    MatrixMap d_h(own.d_h.data(), batch, out);
    d_a_part.setZero();
    for (Eigen::Index e = first; e < last; ++e) {
      const ConstMatrixMap product(products_[l].data() + e * batch * out, batch, out);
      // ∂L/∂ω_e adds up over the three layers (u_l = Σ_e ω_e ⊙ products).
      if (l == 2) {
        d_omega.col(e) = (d_u.array() * product.array()).rowwise().sum().matrix();
      } else {
        d_omega.col(e) += (d_u.array() * product.array()).rowwise().sum().matrix();
      }
      d_h.noalias() = (d_u.array().colwise() * omega.col(e).array()).matrix();
      MatrixMap(g.expert_weights[l] + e * in * out, in, out).noalias() = a.transpose() * d_h;
      Eigen::Map<Eigen::RowVectorXf>(g.expert_biases[l] + e * out, out) = d_h.colwise().sum();
      if (want_input) {
        d_a_part.noalias() +=
            d_h * ConstMatrixMap(p.expert_weights[l] + e * in * out, in, out).transpose();
      }
    }
    if (!want_input) {
      continue;
    }
    meet(team);
    const std::size_t n = size(batch_, in);
    add_parts(own.d_a.data(), n, team.members,
              [&](int k) { return members_[static_cast<std::size_t>(k)].d_input_part[l].data(); });
    if (l > 0) {
      // Through the ELU that made this layer's input.
      const ConstMatrixMap d_a(own.d_a.data(), batch, in);
      MatrixMap(own.d_u.data(), batch, in) =
          (d_a.array() * (a.array() > 0.0f).select(1.0f, a.array() + 1.0f)).matrix();
    }
  }
}

// The gating network's and MPNet's encoder GRU's forward pass (member 0): ω, and MPNet's a₀.
void MoeStep::gating_forward(const MoeBuffers& p, WindowBatch windows, int count) {
  const std::size_t tl = size(kTime, lanes_);
  auto at = [&](int b, int r, int c) {
    return windows.first[size(b) * windows.item_stride + size(r) * windows.row_stride +
                         static_cast<std::size_t>(c)];
  };
  // The GRUs' inputs, batch innermost; padding lanes hold zeros.
  auto gather = [&](GruLayerState& layer, int first_column) {
    std::fill(layer.input_sequence.begin(), layer.input_sequence.end(), 0.0f);
    for (int k = 0; k < layer.input; ++k) {
      for (int t = 0; t < kTime; ++t) {
        float* to = layer.input_sequence.data() + size(k, tl) + size(t, lanes_);
        for (int b = 0; b < count; ++b) {
          to[b] = at(b, t, first_column + k);
        }
      }
    }
  };
  gather(gating_[0], shape_.gating_first);
  // Softmax over the 9 hidden units of the second GRU layer's last output.
  gru_forward(gating_[0], p.gating[0]);
  std::copy_n(gating_[0].output.begin(), size(kExperts, tl), gating_[1].input_sequence.begin());
  gru_forward(gating_[1], p.gating[1]);
  for (int b = 0; b < count; ++b) {
    float* w = omega_.data() + size(b, kExperts);
    float largest = -std::numeric_limits<float>::infinity();
    for (int e = 0; e < kExperts; ++e) {
      w[e] = gating_[1].output[size(e, tl) + size(kTime - 1, lanes_) + b];
      largest = std::max(largest, w[e]);
    }
    float sum = 0.0f;
    for (int e = 0; e < kExperts; ++e) {
      w[e] = std::exp(w[e] - largest);
      sum += w[e];
    }
    for (int e = 0; e < kExperts; ++e) {
      w[e] /= sum;
    }
  }
  if (shape_.encoder_hidden > 0) {
    gather(encoder_, 0);
    gru_forward(encoder_, p.encoder);
    float* a = members_[0].input[0].data();
    for (int b = 0; b < count; ++b) {
      for (int j = 0; j < shape_.encoder_hidden; ++j) {
        a[size(b, shape_.expert_in) + static_cast<std::size_t>(j)] =
            encoder_.output[size(j, tl) + size(kTime - 1, lanes_) + b];
      }
    }
  }
}

// UGNet's condition vector: the newest row's pose, then the gating columns of all 30 rows,
// oldest first.
void MoeStep::gather_condition(WindowBatch windows, int count, float* a) const {
  for (int b = 0; b < count; ++b) {
    const float* clip = windows.first + size(b) * windows.item_stride;
    float* row = a + size(b, shape_.expert_in);
    const float* newest = clip + size(kTime - 1) * windows.row_stride;
    row = std::copy_n(newest, shape_.pose_columns, row);
    for (int t = 0; t < kTime; ++t) {
      row = std::copy_n(clip + size(t) * windows.row_stride + size(shape_.gating_first),
                        shape_.gating_columns, row);
    }
  }
}

double MoeStep::forward(const MoeBuffers& p, WindowBatch windows, TargetBatch targets, int count,
                        ExpertTeam team) {
  if (count < 1 || count > max_batch_) {
    throw Error("MoeStep: " + std::to_string(count) + " windows, the buffers hold 1 to " +
                std::to_string(max_batch_));
  }
  if (team.members != static_cast<int>(members_.size()) ||
      (team.members > 1 && team.sync == nullptr)) {
    throw Error("MoeStep: built for a team of " + std::to_string(members_.size()) +
                " threads, called by one of " + std::to_string(team.members));
  }
  // Every member writes the same batch size; nobody reads another's before the first meeting.
  MemberState& own = members_[static_cast<std::size_t>(team.member)];
  const auto [first, last] = experts_of(team);
  if (team.member == 0) {
    batch_ = count;
    lanes_ = lanes_for(count);
    gating_forward(p, windows, count);
  }
  // UGNet's first layer reads data only: its products need no gating and start at once.
  const bool ugnet = shape_.encoder_hidden == 0;
  if (ugnet) {
    // batch_ is member 0's to write: until the meeting the others go by `count`.
    gather_condition(windows, count, own.input[0].data());
    products(p, 0, first, last, own.input[0].data(), count);
  }
  meet(team);  // ω (and MPNet's a₀) are ready
  if (!ugnet && team.member > 0) {
    std::copy_n(members_[0].input[0].begin(), size(count, dims_[0]), own.input[0].begin());
  }
  experts_forward(p, team, ugnet);

  // Output, L1 loss and its gradient (torch: mean |y − target|, sgn(0) = 0; the clamp passes
  // the gradient where 0 ≤ u ≤ 1). Every member takes its own copy of the gradient.
  const int out = shape_.expert_out;
  const float scale = 1.0f / static_cast<float>(size(count, out));
  double loss = 0;
  for (int b = 0; b < count; ++b) {
    const float* target = targets.first + size(b) * targets.item_stride;
    for (int c = 0; c < out; ++c) {
      const std::size_t i = size(b, out) + static_cast<std::size_t>(c);
      const float u = own.blended[2][i];
      float y = u;
      float pass = 1.0f;
      if (shape_.clamp_output) {
        y = std::clamp(u, 0.0f, 1.0f);
        pass = (u >= 0.0f && u <= 1.0f) ? 1.0f : 0.0f;
      }
      if (team.member == 0) {
        output_[i] = y;
      }
      const float difference = y - target[c];
      loss += std::abs(static_cast<double>(difference));
      const float sign = difference > 0.0f ? 1.0f : (difference < 0.0f ? -1.0f : 0.0f);
      own.d_output[i] = sign * scale * pass;
    }
  }
  return loss / static_cast<double>(size(count, out));
}

// The GRUs' backward pass (member 0), once every member's ∂L/∂ω and ∂L/∂a₀ are in.
void MoeStep::gating_backward(const MoeBuffers& p, const MoeBuffers& g) {
  const std::size_t tl = size(kTime, lanes_);
  if (shape_.encoder_hidden > 0) {
    // ∂L/∂a₀ is the gradient of the encoder GRU's last output.
    std::fill(encoder_.d_output.begin(), encoder_.d_output.end(), 0.0f);
    const float* d_a = members_[0].d_a.data();
    for (int j = 0; j < shape_.encoder_hidden; ++j) {
      float* to = encoder_.d_output.data() + size(j, tl) + size(kTime - 1, lanes_);
      for (int b = 0; b < batch_; ++b) {
        to[b] = d_a[size(b, shape_.expert_in) + static_cast<std::size_t>(j)];
      }
    }
  }
  // Softmax: ∂L/∂z_e = ω_e (∂L/∂ω_e − Σ_f ω_f ∂L/∂ω_f), at the last step of the second layer.
  std::fill(gating_[1].d_output.begin(), gating_[1].d_output.end(), 0.0f);
  for (int b = 0; b < batch_; ++b) {
    const float* w = omega_.data() + size(b, kExperts);
    const float* dw = d_omega_.data() + size(b, kExperts);
    float dot = 0.0f;
    for (int e = 0; e < kExperts; ++e) {
      dot += w[e] * dw[e];
    }
    for (int e = 0; e < kExperts; ++e) {
      gating_[1].d_output[size(e, tl) + size(kTime - 1, lanes_) + b] = w[e] * (dw[e] - dot);
    }
  }
  gru_backward(gating_[1], p.gating[1], g.gating[1], gating_[0].d_output.data());
  gru_backward(gating_[0], p.gating[0], g.gating[0], nullptr);
  if (shape_.encoder_hidden > 0) {
    gru_backward(encoder_, p.encoder, g.encoder, nullptr);
  }
}

void MoeStep::backward(const MoeBuffers& p, const MoeBuffers& g, ExpertTeam team) {
  experts_backward(p, g, team);
  meet(team);  // every expert's ∂L/∂ω is in
  if (team.member == 0) {
    gating_backward(p, g);
  }
}

}  // namespace deixis::train
