#include "gesture/train/moe_step.h"

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include "gesture/error.h"

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
constexpr int kGatingLayers = 2;

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

MoeStep::MoeStep(const MoeShape& shape, int max_batch) : shape_(shape), max_batch_(max_batch) {
  if (max_batch < 1) {
    throw Error("MoeStep: the batch must hold at least one window");
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
  const int dims[4] = {shape.expert_in, shape.expert_hidden, shape.expert_hidden, shape.expert_out};
  for (int l = 0; l < 3; ++l) {
    experts_[l].in = dims[l];
    experts_[l].out = dims[l + 1];
    experts_[l].input.resize(size(max_batch, dims[l]));
    experts_[l].products.resize(size(kExperts, max_batch, dims[l + 1]));
    experts_[l].blended.resize(size(max_batch, dims[l + 1]));
  }
  omega_.resize(size(max_batch, kExperts));
  d_omega_.resize(size(max_batch, kExperts));
  output_.resize(size(max_batch, shape.expert_out));
  d_output_.resize(size(max_batch, shape.expert_out));
  // Per-step temporaries: a GRU's forward needs 7 and its backward 6 blocks of hidden × lanes,
  // experts_backward three blocks of batch × the widest layer.
  const int widest_gru = std::max(kExperts, shape.encoder_hidden);
  const int widest_layer = std::max(shape.expert_in, shape.expert_hidden);
  scratch_.resize(std::max(size(7, widest_gru, lanes), size(3, max_batch, widest_layer)));
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

// u_l = Σ_e ω_e ⊙ (a·W_e + b_e): nine products per layer on the batch-major activations.
void MoeStep::experts_forward(const MoeBuffers& p) {
  const auto batch = static_cast<Eigen::Index>(batch_);
  const ConstMatrixMap omega(omega_.data(), batch, kExperts);
  for (int l = 0; l < 3; ++l) {
    ExpertLayerState& layer = experts_[l];
    const Eigen::Index in = layer.in, out = layer.out;
    const ConstMatrixMap a(layer.input.data(), batch, in);
    MatrixMap u(layer.blended.data(), batch, out);
    u.setZero();
    for (Eigen::Index e = 0; e < kExperts; ++e) {
      MatrixMap product(layer.products.data() + e * batch * out, batch, out);
      product.noalias() = a * ConstMatrixMap(p.expert_weights[l] + e * in * out, in, out);
      product.rowwise() += Eigen::Map<const Eigen::RowVectorXf>(p.expert_biases[l] + e * out, out);
      u += (product.array().colwise() * omega.col(e).array()).matrix();
    }
    if (l + 1 < 3) {
      elu(layer.blended.data(), experts_[l + 1].input.data(), size(batch_, out));
    }
  }
}

void MoeStep::experts_backward(const MoeBuffers& p, const MoeBuffers& g) {
  const auto batch = static_cast<Eigen::Index>(batch_);
  const ConstMatrixMap omega(omega_.data(), batch, kExperts);
  MatrixMap d_omega(d_omega_.data(), batch, kExperts);
  d_omega.setZero();
  const int widest = std::max(shape_.expert_in, shape_.expert_hidden);
  float* d_u_buffer = scratch_.data();                    // ∂L/∂u_l, [batch][out]
  float* d_a_buffer = d_u_buffer + size(batch_, widest);  // ∂L/∂a_{l−1}, [batch][in]
  float* d_h_buffer = d_a_buffer + size(batch_, widest);  // ω_e ⊙ ∂L/∂u_l, [batch][out]
  std::copy(d_output_.begin(),
            d_output_.begin() + static_cast<std::ptrdiff_t>(size(batch_, shape_.expert_out)),
            d_u_buffer);
  for (int l = 2; l >= 0; --l) {
    const ExpertLayerState& layer = experts_[l];
    const Eigen::Index in = layer.in, out = layer.out;
    const ConstMatrixMap a(layer.input.data(), batch, in);
    const MatrixMap d_u(d_u_buffer, batch, out);
    const bool want_input = l > 0 || shape_.encoder_hidden > 0;
    MatrixMap d_a(d_a_buffer, batch, want_input ? in : 0);
    MatrixMap d_h(d_h_buffer, batch, out);
    d_a.setZero();
    for (Eigen::Index e = 0; e < kExperts; ++e) {
      const ConstMatrixMap product(layer.products.data() + e * batch * out, batch, out);
      d_omega.col(e) += (d_u.array() * product.array()).rowwise().sum().matrix();
      d_h.noalias() = (d_u.array().colwise() * omega.col(e).array()).matrix();
      MatrixMap(g.expert_weights[l] + e * in * out, in, out).noalias() = a.transpose() * d_h;
      Eigen::Map<Eigen::RowVectorXf>(g.expert_biases[l] + e * out, out) = d_h.colwise().sum();
      if (want_input) {
        d_a.noalias() +=
            d_h * ConstMatrixMap(p.expert_weights[l] + e * in * out, in, out).transpose();
      }
    }
    if (l > 0) {
      // Through the ELU that made this layer's input.
      MatrixMap next(d_u_buffer, batch, in);
      next = (d_a.array() * (a.array() > 0.0f).select(1.0f, a.array() + 1.0f)).matrix();
    }
  }
  if (shape_.encoder_hidden > 0) {
    // ∂L/∂a₀ is the gradient of the encoder GRU's last output.
    std::fill(encoder_.d_output.begin(), encoder_.d_output.end(), 0.0f);
    const std::size_t tl = size(kTime, lanes_);
    for (int j = 0; j < shape_.encoder_hidden; ++j) {
      float* to = encoder_.d_output.data() + size(j, tl) + size(kTime - 1, lanes_);
      for (int b = 0; b < batch_; ++b) {
        to[b] = d_a_buffer[size(b, shape_.expert_in) + static_cast<std::size_t>(j)];
      }
    }
  }
}

double MoeStep::forward(const MoeBuffers& p, WindowBatch windows, TargetBatch targets, int count,
                        int whole_batch) {
  if (count < 1 || count > max_batch_) {
    throw Error("MoeStep: " + std::to_string(count) + " windows, the buffers hold 1 to " +
                std::to_string(max_batch_));
  }
  if (whole_batch == 0) {
    whole_batch = count;
  }
  if (whole_batch < count) {
    throw Error("MoeStep: a slice of " + std::to_string(count) + " windows of a batch of " +
                std::to_string(whole_batch));
  }
  batch_ = count;
  lanes_ = lanes_for(count);
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
  if (shape_.encoder_hidden > 0) {
    gather(encoder_, 0);
  }

  // Gating: softmax over the 9 hidden units of the second GRU layer's last output.
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

  // The experts' input: MPNet's GRU encoding, or UGNet's condition vector (the newest row's pose,
  // then the gating columns of all 30 rows, oldest first).
  float* a = experts_[0].input.data();
  if (shape_.encoder_hidden > 0) {
    gru_forward(encoder_, p.encoder);
    for (int b = 0; b < count; ++b) {
      for (int j = 0; j < shape_.encoder_hidden; ++j) {
        a[size(b, shape_.expert_in) + static_cast<std::size_t>(j)] =
            encoder_.output[size(j, tl) + size(kTime - 1, lanes_) + b];
      }
    }
  } else {
    for (int b = 0; b < count; ++b) {
      float* row = a + size(b, shape_.expert_in);
      for (int c = 0; c < shape_.pose_columns; ++c) {
        *row++ = at(b, kTime - 1, c);
      }
      for (int t = 0; t < kTime; ++t) {
        for (int k = 0; k < shape_.gating_columns; ++k) {
          *row++ = at(b, t, shape_.gating_first + k);
        }
      }
    }
  }
  experts_forward(p);

  // Output, L1 loss and its gradient (torch: mean |y − target|, sgn(0) = 0; the clamp passes
  // the gradient where 0 ≤ u ≤ 1).
  const int out = shape_.expert_out;
  const float scale = 1.0f / static_cast<float>(size(whole_batch, out));
  double loss = 0;
  for (int b = 0; b < count; ++b) {
    const float* target = targets.first + size(b) * targets.item_stride;
    for (int c = 0; c < out; ++c) {
      const std::size_t i = size(b, out) + static_cast<std::size_t>(c);
      const float u = experts_[2].blended[i];
      float y = u;
      float pass = 1.0f;
      if (shape_.clamp_output) {
        y = std::clamp(u, 0.0f, 1.0f);
        pass = (u >= 0.0f && u <= 1.0f) ? 1.0f : 0.0f;
      }
      output_[i] = y;
      const float difference = y - target[c];
      loss += std::abs(static_cast<double>(difference));
      const float sign = difference > 0.0f ? 1.0f : (difference < 0.0f ? -1.0f : 0.0f);
      d_output_[i] = sign * scale * pass;
    }
  }
  return loss / static_cast<double>(size(whole_batch, out));
}

void MoeStep::backward(const MoeBuffers& p, const MoeBuffers& g) {
  experts_backward(p, g);
  const std::size_t tl = size(kTime, lanes_);
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

}  // namespace deixis::train
