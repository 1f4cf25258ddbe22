#include <algorithm>
#include <array>
#include <cmath>

#include "gesture/nn/ugnet_architectures.h"

namespace deixis::nn {

namespace {

using Diffusion = UgnetDiffusion;
constexpr int kSteps = kDiffusionSteps;

// The sinusoidal time embedding of model.py's PositionalEmbedding (dim 64, scale 1): for
// k = 0…31, ω_k = exp(−k·ln(10⁴)/32); [sin(t·ω_k)…, cos(t·ω_k)…], in float32 as PyTorch.
Eigen::Matrix<float, Diffusion::kTimeEmbedding, 1> sinusoid(int t) {
  constexpr int kHalf = Diffusion::kTimeEmbedding / 2;
  const float scale = static_cast<float>(std::log(10000.0) / kHalf);
  Eigen::Matrix<float, Diffusion::kTimeEmbedding, 1> e;
  for (int k = 0; k < kHalf; ++k) {
    const float angle = static_cast<float>(t) * std::exp(static_cast<float>(k) * -scale);
    e(k) = std::sin(angle);
    e(kHalf + k) = std::cos(angle);
  }
  return e;
}

// Copies columns [first, first + count) of a row-major Rows × Cols tensor into `dst`.
template <int Rows, int Count>
void copy_columns(const std::vector<float>& src, int cols, int first,
                  MatrixParam<Rows, Count>& dst) {
  auto out = dst.storage();
  for (int r = 0; r < Rows; ++r) {
    for (int c = 0; c < Count; ++c) {
      out[static_cast<std::size_t>(r) * Count + c] =
          src[static_cast<std::size_t>(r) * cols + first + c];
    }
  }
}

// Splits one linear layer of the denoiser. Its input columns are laid out as
// [hidden_at, noisy_at, condition_at, time_at] (fin has no hidden part).
template <int Out, int HiddenIn>
void load_conditioned(
    const SafetensorsFile& file, const std::string& prefix, int hidden_at, int noisy_at,
    int condition_at, int time_at,
    const std::array<Eigen::Matrix<float, Diffusion::kTimeEmbedding, 1>, kSteps>& time_embeddings,
    Diffusion::ConditionedLinear<Out, HiddenIn>& layer) {
  constexpr int kIn = HiddenIn + kPoseSize + kConditionSize + Diffusion::kTimeEmbedding;
  const std::int64_t weight_shape[] = {Out, kIn};
  const std::vector<float> w = file.read_f32(prefix + ".weight", weight_shape);
  const std::int64_t bias_shape[] = {Out};
  const std::vector<float> b = file.read_f32(prefix + ".bias", bias_shape);
  if constexpr (HiddenIn > 0) {
    copy_columns(w, kIn, hidden_at, layer.w_hidden);
  }
  copy_columns(w, kIn, noisy_at, layer.w_noisy);
  copy_columns(w, kIn, condition_at, layer.w_condition);
  MatrixParam<Out, Diffusion::kTimeEmbedding> w_time;
  copy_columns(w, kIn, time_at, w_time);
  const Eigen::Map<const Eigen::Matrix<float, Out, 1>> bias(b.data());
  auto rows = layer.time_and_bias.storage();
  for (int t = 0; t < kSteps; ++t) {
    Eigen::Map<Eigen::Matrix<float, Out, 1>> row(rows.data() + static_cast<std::size_t>(t) * Out);
    row = w_time.view() * time_embeddings[t] + bias;
  }
}

// GroupNorm(16 groups, 128 channels, eps 1e-5, per-channel affine) of one sample's channels
// `in` into `out`, each group's 8 contiguous channels as one fixed-size array (one AVX register).
void group_norm(const float* in, const VectorParam<Diffusion::kHidden>& gamma,
                const VectorParam<Diffusion::kHidden>& beta, float* out) {
  constexpr int kPerGroup = Diffusion::kHidden / Diffusion::kGroups;
  using Group = Eigen::Array<float, kPerGroup, 1>;
  const float* g = gamma.storage().data();
  const float* b = beta.storage().data();
  for (int first = 0; first < Diffusion::kHidden; first += kPerGroup) {
    const Eigen::Map<const Group> x(in + first);
    const Group centred = x - x.sum() / kPerGroup;
    const float inv = 1.0f / std::sqrt(centred.square().sum() / kPerGroup + 1e-5f);
    Eigen::Map<Group>(out + first) =
        centred * inv * Eigen::Map<const Group>(g + first) + Eigen::Map<const Group>(b + first);
  }
}

// GroupNorm, then SiLU, on one sample.
Eigen::Matrix<float, Diffusion::kHidden, 1> group_norm_silu(
    const Eigen::Matrix<float, Diffusion::kHidden, 1>& h,
    const VectorParam<Diffusion::kHidden>& gamma, const VectorParam<Diffusion::kHidden>& beta) {
  Eigen::Matrix<float, Diffusion::kHidden, 1> out;
  group_norm(h.data(), gamma, beta, out.data());
  silu_inplace(out);
  return out;
}

// Windows per pass of run_batch: 64 columns keep a pass's activations (128 × 64 floats each) in
// L1/L2 while the weights stream through once.
constexpr int kBatchChunk = 64;
using HiddenBatch = Eigen::Matrix<float, Diffusion::kHidden, Eigen::Dynamic, Eigen::ColMajor,
                                  Diffusion::kHidden, kBatchChunk>;
using PoseBatch =
    Eigen::Matrix<float, kPoseSize, Eigen::Dynamic, Eigen::ColMajor, kPoseSize, kBatchChunk>;

// group_norm_silu() on every column of a batch, with one vectorised SiLU over the whole batch.
void group_norm_silu_batch(const HiddenBatch& h, const VectorParam<Diffusion::kHidden>& gamma,
                           const VectorParam<Diffusion::kHidden>& beta, HiddenBatch& out) {
  out.resize(Diffusion::kHidden, h.cols());
  for (Eigen::Index j = 0; j < h.cols(); ++j) {
    group_norm(h.col(j).data(), gamma, beta, out.col(j).data());
  }
  silu_inplace(out);
}

}  // namespace

bool UgnetDiffusion::recognises(const SafetensorsFile& file) {
  return file.contains("model.fin.weight") && file.contains("time_mlp.1.weight") &&
         file.contains("sigma");
}

void UgnetDiffusion::load(const SafetensorsFile& file) {
  Linear<kTimeEmbedding, kTimeEmbedding> time_mlp_1;
  Linear<kTimeEmbedding, kTimeEmbedding> time_mlp_3;
  time_mlp_1.load(file, "time_mlp.1");
  time_mlp_3.load(file, "time_mlp.3");
  std::array<Eigen::Matrix<float, kTimeEmbedding, 1>, kSteps> e;
  for (int t = 0; t < kSteps; ++t) {
    Eigen::Matrix<float, kTimeEmbedding, 1> hidden = time_mlp_1.run(sinusoid(t));
    silu_inplace(hidden);
    e[t] = time_mlp_3.run(hidden);
  }

  // fin's input is c ++ x ++ e; the blocks' and fco's are h ++ x ++ c ++ e.
  load_conditioned(file, "model.fin", 0, kConditionSize, 0, kConditionSize + kPoseSize, e, fin);
  constexpr int kNoisyAt = kHidden;
  constexpr int kConditionAt = kHidden + kPoseSize;
  constexpr int kTimeAt = kConditionAt + kConditionSize;
  for (int k = 0; k < kBlocks; ++k) {
    const std::string norm = "model.net." + std::to_string(3 * k);
    load_vector(file, norm + ".weight", norm_weight[k]);
    load_vector(file, norm + ".bias", norm_bias[k]);
    load_conditioned(file, "model.net." + std::to_string(3 * k + 2), 0, kNoisyAt, kConditionAt,
                     kTimeAt, e, blocks[k]);
  }
  load_conditioned(file, "model.fco", 0, kNoisyAt, kConditionAt, kTimeAt, e, fco);
  load_vector(file, "sigma", sigma);
}

PoseVector UgnetDiffusion::run(UgnetWindow window, std::span<const float> noise,
                               UgnetTrace* trace) const {
  const ConditionVector c = condition_vector(window);
  // The condition's contribution to every layer, once per call.
  const Eigen::Matrix<float, kHidden, 1> fin_c = fin.w_condition.view() * c;
  Eigen::Matrix<float, kHidden, kBlocks> block_c;
  for (int k = 0; k < kBlocks; ++k) {
    block_c.col(k).noalias() = blocks[k].w_condition.view() * c;
  }
  const Eigen::Matrix<float, kPoseSize, 1> fco_c = fco.w_condition.view() * c;

  using Pose = Eigen::Matrix<float, kPoseSize, 1>;
  const bool has_noise = noise.size() >= static_cast<std::size_t>(kDiffusionNoiseSize);
  Pose x = has_noise ? Pose(Eigen::Map<const Pose>(noise.data())) : Pose::Zero();
  for (int i = 0; i < kSteps; ++i) {
    const int t = kSteps - 1 - i;
    Eigen::Matrix<float, kHidden, 1> h = fin_c + fin.time_and_bias.view().row(t).transpose();
    h.noalias() += fin.w_noisy.view() * x;
    for (int k = 0; k < kBlocks; ++k) {
      const Eigen::Matrix<float, kHidden, 1> g = group_norm_silu(h, norm_weight[k], norm_bias[k]);
      h = block_c.col(k) + blocks[k].time_and_bias.view().row(t).transpose();
      h.noalias() += blocks[k].w_hidden.view() * g;
      h.noalias() += blocks[k].w_noisy.view() * x;
    }
    Pose x0 = fco_c + fco.time_and_bias.view().row(t).transpose();
    x0.noalias() += fco.w_hidden.view() * h;
    x0.noalias() += fco.w_noisy.view() * x;
    if (trace != nullptr) {
      Eigen::Map<Pose>(trace->denoised_steps.data() + i * kPoseSize) = x0;
    }
    x = x0;
    if (t > 0 && has_noise) {
      x += sigma.view()(t) * Eigen::Map<const Pose>(noise.data() + (i + 1) * kPoseSize);
    }
  }
  PoseVector out;
  Eigen::Map<Pose>(out.data()) = x;
  return out;
}

void UgnetDiffusion::run_batch(std::span<const float> windows, std::span<const float> noise,
                               std::span<float> out) const {
  using Hidden = HiddenBatch;
  using Poses = PoseBatch;
  using Pose = Eigen::Matrix<float, kPoseSize, 1>;
  const std::size_t count = out.size() / kPoseSize;
  const bool has_noise = !noise.empty();
  for (std::size_t first = 0; first < count; first += kBatchChunk) {
    const auto n = static_cast<Eigen::Index>(std::min<std::size_t>(kBatchChunk, count - first));
    // noise row `row` (0: the initial sample) of window `j` of this chunk
    const auto draws_of = [&](Eigen::Index j, int row) {
      return Eigen::Map<const Pose>(noise.data() + (first + j) * kDiffusionNoiseSize +
                                    static_cast<std::size_t>(row) * kPoseSize);
    };
    Eigen::Matrix<float, kConditionSize, Eigen::Dynamic> c(kConditionSize, n);
    for (Eigen::Index j = 0; j < n; ++j) {
      c.col(j) = condition_vector(
          UgnetWindow(windows.subspan((first + j) * kUgnetWindowSize, kUgnetWindowSize)));
    }
    const Hidden fin_c = fin.w_condition.view() * c;
    // On the heap: ten of these (320 KB) would crowd a thread's stack.
    std::array<Eigen::Matrix<float, kHidden, Eigen::Dynamic>, kBlocks> block_c;
    for (int k = 0; k < kBlocks; ++k) {
      block_c[k] = blocks[k].w_condition.view() * c;
    }
    const Poses fco_c = fco.w_condition.view() * c;

    Poses x = Poses::Zero(kPoseSize, n);
    if (has_noise) {
      for (Eigen::Index j = 0; j < n; ++j) {
        x.col(j) = draws_of(j, 0);
      }
    }
    Hidden h(kHidden, n), g(kHidden, n);
    Poses x0(kPoseSize, n);
    for (int i = 0; i < kSteps; ++i) {
      const int t = kSteps - 1 - i;
      h = fin_c;
      h.colwise() += fin.time_and_bias.view().row(t).transpose();
      h.noalias() += fin.w_noisy.view() * x;
      for (int k = 0; k < kBlocks; ++k) {
        group_norm_silu_batch(h, norm_weight[k], norm_bias[k], g);
        h = block_c[k];
        h.colwise() += blocks[k].time_and_bias.view().row(t).transpose();
        h.noalias() += blocks[k].w_hidden.view() * g;
        h.noalias() += blocks[k].w_noisy.view() * x;
      }
      x0 = fco_c;
      x0.colwise() += fco.time_and_bias.view().row(t).transpose();
      x0.noalias() += fco.w_hidden.view() * h;
      x0.noalias() += fco.w_noisy.view() * x;
      x = x0;
      if (t > 0 && has_noise) {
        for (Eigen::Index j = 0; j < n; ++j) {
          x.col(j) += sigma.view()(t) * draws_of(j, i + 1);
        }
      }
    }
    Eigen::Map<Poses>(out.data() + first * kPoseSize, kPoseSize, n) = x;
  }
}

}  // namespace deixis::nn
