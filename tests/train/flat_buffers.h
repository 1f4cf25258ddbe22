#pragma once
// Test helpers for the direct training steps: a network's tensors cut out of one flat buffer, as
// the trainer's flat parameter and gradient buffers are, and random fill.

#include <cstddef>
#include <random>
#include <vector>

#include "train/autoencoder_step.h"
#include "train/moe_step.h"

namespace deixis::train::test_data {

// A tensor's place in a flat buffer.
struct TensorRange {
  std::size_t offset = 0, count = 0;
};

// MoeBuffers pointing into `base`, which holds MoeShape::parameter_count() floats.
struct FlatMoe {
  MoeBuffers buffers;
  std::vector<TensorRange> tensors;  // in the order they were cut

  FlatMoe(const MoeShape& s, float* base) {
    float* next = base;
    auto take = [&](std::size_t n) {
      float* p = next;
      tensors.push_back({static_cast<std::size_t>(next - base), n});
      next += n;
      return p;
    };
    auto gru = [&](int in, int hidden) {
      const auto g = static_cast<std::size_t>(3 * hidden);
      GruLayerBuffers b;
      b.w_ih = take(g * static_cast<std::size_t>(in));
      b.w_hh = take(g * static_cast<std::size_t>(hidden));
      b.b_ih = take(g);
      b.b_hh = take(g);
      return b;
    };
    buffers.gating[0] = gru(s.gating_columns, MoeStep::kExperts);
    buffers.gating[1] = gru(MoeStep::kExperts, MoeStep::kExperts);
    if (s.encoder_hidden > 0) {
      buffers.encoder = gru(s.window_columns, s.encoder_hidden);
    }
    const int dims[4] = {s.expert_in, s.expert_hidden, s.expert_hidden, s.expert_out};
    for (int l = 0; l < 3; ++l) {
      const auto out = static_cast<std::size_t>(dims[l + 1]);
      buffers.expert_weights[l] = take(MoeStep::kExperts * static_cast<std::size_t>(dims[l]) * out);
      buffers.expert_biases[l] = take(MoeStep::kExperts * out);
    }
  }
};

// AutoencoderBuffers pointing into `base`, which holds AutoencoderStep::parameter_count() floats.
struct FlatAutoencoder {
  AutoencoderBuffers buffers;
  std::vector<TensorRange> tensors;

  explicit FlatAutoencoder(float* base) {
    float* next = base;
    auto take = [&](std::size_t n) {
      float* p = next;
      tensors.push_back({static_cast<std::size_t>(next - base), n});
      next += n;
      return p;
    };
    for (int i = 0; i < 4; ++i) {
      const AutoencoderStep::LayerShape l = AutoencoderStep::layer_shape(i);
      buffers.weight[i] =
          take(static_cast<std::size_t>(l.in_channels) * static_cast<std::size_t>(l.out_channels) *
               static_cast<std::size_t>(l.kernel));
      buffers.bias[i] = take(static_cast<std::size_t>(l.out_channels));
    }
  }
};

// Fills in place (buffers may point into the vector's memory).
template <typename Floats>
void fill_random(Floats& v, float spread, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> normal(0.0f, spread);
  for (float& x : v) {
    x = normal(rng);
  }
}

inline std::vector<float> random_values(std::size_t n, float spread, unsigned seed) {
  std::vector<float> v(n);
  fill_random(v, spread, seed);
  return v;
}

}  // namespace deixis::train::test_data
