// The paper's networks in libtorch (the authors' model.py; docs/conventions.md#mpnet, #ugnet), one
// class each, registered under the authors' module names.

#include "train/models.h"

#include <ATen/CPUGeneratorImpl.h>
#include <torch/nn/functional.h>
#include <torch/nn/init.h>
#include <torch/nn/modules.h>
#include <torch/torch.h>

#include <cmath>
#include <map>
#include <sstream>

#include "core/error.h"
#include "train/conv_as_matmul.h"
#include "train/forward.h"
#include "train/fused_denoiser.h"
#include "train/fused_experts.h"
#include "train/fused_gru.h"
#include "train/fused_transformer.h"

namespace deixis::train {

namespace {

constexpr int kWindow = 30;
constexpr int kExperts = 9;
constexpr int kPose = 24;
constexpr int kCondition = 8;                                   // target feature 5 + progression 3
constexpr int kConditionVector = kPose + kCondition * kWindow;  // 264

// Experts stored [experts, in, out] and applied x·W (docs/conventions.md#mixture-of-experts),
// initialised as the authors' init_params: U(±√(6 / (in·out))), biases 0.
class ExpertLayers : public torch::nn::Module {
 public:
  ExpertLayers(int in, int hidden, int out) {
    auto weight = [&](const std::string& name, int rows, int cols) {
      const double bound = std::sqrt(6.0 / (static_cast<double>(rows) * cols));
      return register_parameter(name, torch::empty({kExperts, rows, cols}).uniform_(-bound, bound));
    };
    w_[0] = weight("w_l1", in, hidden);
    b_[0] = register_parameter("b_l1", torch::zeros({kExperts, hidden}));
    w_[1] = weight("w_l2", hidden, hidden);
    b_[1] = register_parameter("b_l2", torch::zeros({kExperts, hidden}));
    w_[2] = weight("w_l3", hidden, out);
    b_[2] = register_parameter("b_l3", torch::zeros({kExperts, out}));
  }

  // The authors blend each layer's weights with ω and then multiply, x·Σ_e ω_e W_e + Σ_e ω_e b_e.
  // Multiplying by every expert and blending the products is the same function (it is linear in
  // W) and the same gradients, without a [batch, in, out] weight per sample: 9 small GEMMs per
  // layer (docs/decisions.md 2), in one autograd node (fused_experts.h).
  torch::Tensor forward(const torch::Tensor& x, const torch::Tensor& omega) {
    return expert_layers(x, omega, w_, b_);
  }

 private:
  std::array<torch::Tensor, 3> w_, b_;
};

// Softmax of the last output of a 2-layer GRU (hidden 9): the expert weights ω. There is no
// linear layer before the softmax (docs/conventions.md#mixture-of-experts).
class GatingNetwork : public torch::nn::Module {
 public:
  explicit GatingNetwork(int inputs)
      : gru_(register_module("gru", FusedGru(inputs, kExperts, 2))) {}
  torch::Tensor forward(const torch::Tensor& x) {
    return torch::softmax(gru_->forward(x).select(1, -1), -1);
  }

 private:
  FusedGru gru_;
};

class MpnetNetwork : public TrainableNetwork {
 public:
  virtual torch::Tensor preclamp(const torch::Tensor& window) = 0;
  torch::Tensor forward(const torch::Tensor& window) override {
    return torch::clamp(preclamp(window), 0.0, 1.0);
  }
};

// MPNet GRU-MoE (model.py MPNet_MoE).
class MpnetMoe : public MpnetNetwork {
 public:
  MpnetMoe()
      : gating_(register_module("gating_network", std::make_shared<GatingNetwork>(5))),
        gru_(register_module("gru", FusedGru(11, 24, 1))),
        experts_(register_module("moe_network", std::make_shared<ExpertLayers>(24, 12, 3))) {}
  torch::Tensor preclamp(const torch::Tensor& window) override {
    const torch::Tensor omega = gating_->forward(window.slice(2, 6, 11));
    const torch::Tensor z = gru_->forward(window).select(1, -1);
    return experts_->forward(z, omega);
  }

 private:
  std::shared_ptr<GatingNetwork> gating_;
  FusedGru gru_;
  std::shared_ptr<ExpertLayers> experts_;
};

// MPNet MLP (model.py MPNet_MLP): the window flattened row-major, 330 → 24 → 24 → 3, ELU.
class MpnetMlp : public MpnetNetwork {
 public:
  MpnetMlp()
      : l1_(register_module("linear1", torch::nn::Linear(330, 24))),
        l2_(register_module("linear2", torch::nn::Linear(24, 24))),
        l3_(register_module("linear3", torch::nn::Linear(24, 3))) {}
  torch::Tensor preclamp(const torch::Tensor& window) override {
    torch::Tensor z = torch::elu(l1_(window.reshape({window.size(0), -1})));
    return l3_(torch::elu(l2_(z)));
  }

 private:
  torch::nn::Linear l1_, l2_, l3_;
};

// nn.TransformerEncoder of the authors: post-norm layers, ReLU, dropout 0.1 (active in
// training), no positional encoding. libtorch's encoder is sequence-first.
torch::nn::TransformerEncoder make_encoder(int d_model, int feed_forward) {
  return torch::nn::TransformerEncoder(
      torch::nn::TransformerEncoderOptions(torch::nn::TransformerEncoderLayerOptions(d_model, 4)
                                               .dim_feedforward(feed_forward)
                                               .dropout(0.1),
                                           4));
}

// MPNet Transformer (model.py MPNet_Transformer). The encoder module holds the parameters (the
// authors' names and layouts); its maths runs as one fused autograd node per layer
// (fused_transformer.h says why), with dropout keyed by the global generator, which the trainer
// seeds per batch.
class MpnetTransformer : public MpnetNetwork {
 public:
  MpnetTransformer()
      : encoder_(register_module("transformer", make_encoder(16, 16))),
        in_(register_module("linear_input", torch::nn::Linear(11, 16))),
        out_(register_module("linear_output", torch::nn::Linear(16, 3))) {}
  torch::Tensor preclamp(const torch::Tensor& window) override {
    const torch::Tensor tokens = in_(window).transpose(0, 1);  // [30, batch, 16]
    return out_(encoder_last_token(encoder_, tokens, at::detail::getDefaultCPUGenerator()));
  }

 private:
  torch::nn::TransformerEncoder encoder_;
  torch::nn::Linear in_, out_;
};

// The 264-vector the UGNet MoE experts, MLP and diffusion read: newest x ++ the 8 conditioning
// columns of all 30 rows, oldest first.
torch::Tensor condition_vector(const torch::Tensor& window) {
  return torch::cat({window.select(1, -1).slice(1, 0, kPose),
                     window.slice(2, kPose, kPose + kCondition).reshape({window.size(0), -1})},
                    1);
}

// UGNet MoE (model.py UGNet_MoE): hidden 24 + (8·30)//2 = 144.
class UgnetMoe : public TrainableNetwork {
 public:
  UgnetMoe()
      : gating_(register_module("gating_network", std::make_shared<GatingNetwork>(kCondition))),
        experts_(register_module("moe_network",
                                 std::make_shared<ExpertLayers>(kConditionVector, 144, kPose))) {}
  torch::Tensor forward(const torch::Tensor& window) override {
    const torch::Tensor omega = gating_->forward(window.slice(2, kPose, kPose + kCondition));
    return experts_->forward(condition_vector(window), omega);
  }

 private:
  std::shared_ptr<GatingNetwork> gating_;
  std::shared_ptr<ExpertLayers> experts_;
};

// UGNet MLP (model.py UGNet_MLP): 264 → 1056 → 264 → 24, ELU.
class UgnetMlp : public TrainableNetwork {
 public:
  UgnetMlp()
      : l1_(register_module("linear1", torch::nn::Linear(kConditionVector, 4 * kConditionVector))),
        l2_(register_module("linear2", torch::nn::Linear(4 * kConditionVector, kConditionVector))),
        l3_(register_module("linear3", torch::nn::Linear(kConditionVector, kPose))) {}
  torch::Tensor forward(const torch::Tensor& window) override {
    return l3_(torch::elu(l2_(torch::elu(l1_(condition_vector(window))))));
  }

 private:
  torch::nn::Linear l1_, l2_, l3_;
};

// UGNet Transformer (model.py UGNet_Transformer): 30 condition tokens then the pose token.
class UgnetTransformer : public TrainableNetwork {
 public:
  UgnetTransformer()
      : pose_(register_module("linear_input_pose", torch::nn::Linear(kPose, 160))),
        feature_(register_module("linear_input_feature", torch::nn::Linear(kCondition, 160))),
        encoder_(register_module("transformer", make_encoder(160, 160))),
        out_(register_module("linear_output", torch::nn::Linear(160, kPose))) {}
  torch::Tensor forward(const torch::Tensor& window) override {
    const torch::Tensor features = feature_(window.slice(2, kPose, kPose + kCondition));
    const torch::Tensor pose = pose_(window.select(1, -1).slice(1, 0, kPose)).unsqueeze(1);
    const torch::Tensor tokens = torch::cat({features, pose}, 1).transpose(0, 1);
    return out_(encoder_last_token(encoder_, tokens, at::detail::getDefaultCPUGenerator()));
  }

 private:
  torch::nn::Linear pose_, feature_;
  torch::nn::TransformerEncoder encoder_;
  torch::nn::Linear out_;
};

// The AMDM-style denoiser (model.py NoiseDecoder): h = fin(c ++ x ++ e); 10 blocks of
// GroupNorm(16) → SiLU → Linear(h ++ x ++ c ++ e); fco(h ++ x ++ c ++ e). It predicts the clean
// pose.
class NoiseDecoder : public torch::nn::Module {
 public:
  static constexpr int kHidden = 128;
  static constexpr int kTime = 64;
  static constexpr int kBlocks = 10;
  NoiseDecoder() {
    constexpr int kWide = kHidden + kPose + kConditionVector + kTime;  // 480
    net_ = register_module("net", torch::nn::ModuleList());
    for (int b = 0; b < kBlocks; ++b) {
      net_->push_back(torch::nn::GroupNorm(16, kHidden));
      net_->push_back(torch::nn::SiLU());
      net_->push_back(torch::nn::Linear(kWide, kHidden));
    }
    fin_ = register_module("fin", torch::nn::Linear(kConditionVector + kPose + kTime, kHidden));
    fco_ = register_module("fco", torch::nn::Linear(kWide, kPose));
  }
  // Through the fused node (fused_denoiser.h: one autograd node instead of ≈ 60 operations).
  torch::Tensor forward(const torch::Tensor& condition, const torch::Tensor& noisy,
                        const torch::Tensor& time) {
    DenoiserWeights w;
    w.fin_weight = fin_->weight;
    w.fin_bias = fin_->bias;
    for (int b = 0; b < kBlocks; ++b) {
      auto* norm = net_[static_cast<std::size_t>(3 * b)]->as<torch::nn::GroupNorm>();
      auto* linear = net_[static_cast<std::size_t>(3 * b + 2)]->as<torch::nn::Linear>();
      w.blocks.push_back({norm->weight, norm->bias, linear->weight, linear->bias});
      w.groups = norm->options.num_groups();
    }
    w.fco_weight = fco_->weight;
    w.fco_bias = fco_->bias;
    return denoise(condition, noisy, time, w);
  }

 private:
  torch::nn::ModuleList net_{nullptr};
  torch::nn::Linear fin_{nullptr}, fco_{nullptr};
};

// Sinusoidal embedding of integer steps (model.py PositionalEmbedding, dim 64, scale 1).
torch::Tensor step_embedding(const torch::Tensor& steps) {
  constexpr int kHalf = NoiseDecoder::kTime / 2;
  const double scale = std::log(10000.0) / kHalf;
  const torch::Tensor frequencies = torch::exp(torch::arange(kHalf, torch::kFloat32) * -scale);
  const torch::Tensor angles = torch::outer(steps.to(torch::kFloat32), frequencies);
  return torch::cat({angles.sin(), angles.cos()}, -1);
}

// UGNet Diffusion (model.py UGNet_Diffusion, T = 30, cosine schedule, x0 prediction).
class UgnetDiffusion : public TrainableNetwork {
 public:
  static constexpr int kSteps = 30;
  UgnetDiffusion() {
    // Cosine schedule (s = 0.008) in double as numpy, stored as float32 buffers like the authors'.
    std::vector<double> betas;
    auto f = [](double t) {
      const double s = 0.008;
      const double c = std::cos((t / kSteps + s) / (1 + s) * M_PI / 2);
      return c * c;
    };
    std::vector<double> alpha_bar;
    for (int t = 0; t <= kSteps; ++t) {
      alpha_bar.push_back(f(t) / f(0));
    }
    for (int t = 1; t <= kSteps; ++t) {
      betas.push_back(std::min(1 - alpha_bar[t] / alpha_bar[t - 1], 0.999));
    }
    std::vector<double> alphas, cumprod;
    double running = 1;
    for (const double b : betas) {
      alphas.push_back(1 - b);
      running *= 1 - b;
      cumprod.push_back(running);
    }
    auto buffer = [&](const std::string& name, auto fn) {
      std::vector<float> v;
      for (int t = 0; t < kSteps; ++t) {
        v.push_back(static_cast<float>(fn(t)));
      }
      return register_buffer(name, torch::tensor(v));
    };
    auto at = [](const std::vector<double>& v, int t) { return v[static_cast<std::size_t>(t)]; };
    buffer("betas", [&](int t) { return at(betas, t); });
    buffer("alphas", [&](int t) { return at(alphas, t); });
    buffer("alphas_cumprod", [&](int t) { return at(cumprod, t); });
    sqrt_alphas_cumprod_ =
        buffer("sqrt_alphas_cumprod", [&](int t) { return std::sqrt(at(cumprod, t)); });
    sqrt_one_minus_alphas_cumprod_ = buffer("sqrt_one_minus_alphas_cumprod",
                                            [&](int t) { return std::sqrt(1 - at(cumprod, t)); });
    buffer("reciprocal_sqrt_alphas", [&](int t) { return std::sqrt(1 / at(alphas, t)); });
    buffer("reciprocal_sqrt_alphas_cumprod", [&](int t) { return std::sqrt(1 / at(cumprod, t)); });
    buffer("reciprocal_sqrt_alphas_cumprod_m1",
           [&](int t) { return std::sqrt(1 / at(cumprod, t) - 1); });
    buffer("remove_noise_coeff",
           [&](int t) { return at(betas, t) / std::sqrt(1 - at(cumprod, t)); });
    sigma_ = buffer("sigma", [&](int t) { return std::sqrt(at(betas, t)); });

    decoder_ = register_module("model", std::make_shared<NoiseDecoder>());
    time_mlp_ = register_module(
        "time_mlp",
        torch::nn::Sequential(torch::nn::Functional(step_embedding),
                              torch::nn::Linear(NoiseDecoder::kTime, NoiseDecoder::kTime),
                              torch::nn::SiLU(),
                              torch::nn::Linear(NoiseDecoder::kTime, NoiseDecoder::kTime)));
  }

  // Without draws: sampling with all draws zero (deterministic), as nn::Ugnet::run.
  torch::Tensor forward(const torch::Tensor& window) override {
    return sample(window, torch::zeros({window.size(0), kSteps, kPose}));
  }

  torch::Tensor training_prediction(const torch::Tensor& window, const torch::Tensor& target,
                                    torch::Generator& generator) override {
    const std::int64_t batch = window.size(0);
    const torch::Tensor steps =
        torch::randint(0, kSteps, {batch}, generator, torch::TensorOptions(torch::kLong));
    const torch::Tensor noise = torch::randn({batch, kPose}, generator, torch::TensorOptions());
    const torch::Tensor noisy =
        sqrt_alphas_cumprod_.index_select(0, steps).unsqueeze(1) * target +
        sqrt_one_minus_alphas_cumprod_.index_select(0, steps).unsqueeze(1) * noise;
    return decoder_->forward(condition_vector(window), noisy, time_mlp_->forward(steps));
  }

  // model.py sample_ddpm with supplied draws (docs/conventions.md#ugnet-diffusion):
  // x ← denoise(x, t) for t = 29 … 0, then x += σ_t·ε when t > 0.
  torch::Tensor sample(const torch::Tensor& window, const torch::Tensor& noise) {
    const torch::Tensor condition = condition_vector(window);
    torch::Tensor x = noise.select(1, 0);
    for (int t = kSteps - 1; t >= 0; --t) {
      const torch::Tensor steps = torch::full({window.size(0)}, t, torch::kLong);
      x = decoder_->forward(condition, x, time_mlp_->forward(steps));
      if (t > 0) {
        x = x + sigma_[t] * noise.select(1, kSteps - t);
      }
    }
    return x;
  }

 private:
  torch::Tensor sqrt_alphas_cumprod_, sqrt_one_minus_alphas_cumprod_, sigma_;
  std::shared_ptr<NoiseDecoder> decoder_;
  torch::nn::Sequential time_mlp_{nullptr};
};

// The FMD autoencoder (model.py ConvolutionalAutoEncoder with 18 inputs, width 256, kernel 15):
// 30 frames → 16 → 1 (a 128-d code) and back.
class MotionAutoencoder : public TrainableNetwork {
 public:
  MotionAutoencoder()
      : encode1_(register_module("conv_encode1",
                                 torch::nn::Conv1d(torch::nn::Conv1dOptions(18, 256, 15)))),
        encode2_(register_module("conv_encode2",
                                 torch::nn::Conv1d(torch::nn::Conv1dOptions(256, 128, 16)))),
        decode2_(register_module(
            "conv_decode2",
            torch::nn::ConvTranspose1d(torch::nn::ConvTranspose1dOptions(128, 256, 16)))),
        decode1_(register_module(
            "conv_decode1",
            torch::nn::ConvTranspose1d(torch::nn::ConvTranspose1dOptions(256, 18, 15)))) {}

  // The modules hold the parameters (names, layouts and initialisation of the authors' model);
  // the maths runs as matrix products on time-major tensors (conv_as_matmul.h says why).
  torch::Tensor encode(const torch::Tensor& segments) {  // [batch, 30, 18] → [batch, 1, 128]
    const torch::Tensor hidden =
        torch::relu(conv1d_as_matmul(segments, encode1_->weight, encode1_->bias));
    return conv1d_as_matmul(hidden, encode2_->weight, encode2_->bias);
  }
  torch::Tensor forward(const torch::Tensor& segments) override {
    const torch::Tensor code = encode(segments);
    const torch::Tensor hidden =
        torch::relu(conv_transpose1d_as_matmul(code, decode2_->weight, decode2_->bias));
    return conv_transpose1d_as_matmul(hidden, decode1_->weight, decode1_->bias);
  }

 private:
  torch::nn::Conv1d encode1_, encode2_;
  torch::nn::ConvTranspose1d decode2_, decode1_;
};

std::string shape_of(const torch::Tensor& t) {
  std::ostringstream s;
  s << t.sizes();
  return s.str();
}

}  // namespace

namespace {

// Every parameter's memory (or its gradient's) by state_dict name, for the direct steps.
class TensorMemory {
 public:
  TensorMemory(TrainableNetwork& network, bool gradients, std::string network_kind)
      : kind_(std::move(network_kind)) {
    for (const auto& item : network.named_parameters()) {
      const torch::Tensor t = gradients ? item.value().grad() : item.value();
      const std::string what = gradients ? "the gradient of '" + item.key() + "'" : item.key();
      if (!t.defined()) {
        throw Error("direct training step: " + what + " is not defined");
      }
      if (!t.is_contiguous() || t.scalar_type() != torch::kFloat32) {
        throw Error("direct training step: " + what + " is not a contiguous float32 tensor");
      }
      tensors_[item.key()] = {t.data_ptr<float>(), t.numel()};
    }
  }
  bool has(const std::string& name) const { return tensors_.count(name) > 0; }
  // The tensor's memory, which must hold `values` floats (the shape the direct step assumes).
  float* operator()(const std::string& name, std::int64_t values) const {
    const auto it = tensors_.find(name);
    if (it == tensors_.end()) {
      throw Error("direct training step: the network has no tensor '" + name + "' (not " + kind_ +
                  ")");
    }
    if (it->second.values != values) {
      throw Error("direct training step: tensor '" + name + "' has " +
                  std::to_string(it->second.values) + " values, the step expects " +
                  std::to_string(values));
    }
    return it->second.memory;
  }

 private:
  struct Tensor {
    float* memory;
    std::int64_t values;
  };
  std::string kind_;
  std::map<std::string, Tensor> tensors_;
};

}  // namespace

MoeBuffers moe_buffers(TrainableNetwork& network, bool gradients) {
  const TensorMemory find(network, gradients, "a MoE network");
  const bool mpnet = find.has("gru.weight_ih_l0");
  const MoeShape shape = mpnet ? MoeShape::mpnet() : MoeShape::ugnet();
  auto gru = [&](const std::string& prefix, int layer, std::int64_t in, std::int64_t hidden) {
    const std::string k = "_l" + std::to_string(layer);
    return GruLayerBuffers{find(prefix + "weight_ih" + k, 3 * hidden * in),
                           find(prefix + "weight_hh" + k, 3 * hidden * hidden),
                           find(prefix + "bias_ih" + k, 3 * hidden),
                           find(prefix + "bias_hh" + k, 3 * hidden)};
  };
  const std::int64_t experts = MoeStep::kExperts;
  MoeBuffers b;
  b.gating[0] = gru("gating_network.gru.", 0, shape.gating_columns, experts);
  b.gating[1] = gru("gating_network.gru.", 1, experts, experts);
  if (mpnet) {
    b.encoder = gru("gru.", 0, shape.window_columns, shape.encoder_hidden);
  }
  const std::int64_t dims[4] = {shape.expert_in, shape.expert_hidden, shape.expert_hidden,
                                shape.expert_out};
  for (int l = 0; l < 3; ++l) {
    b.expert_weights[l] =
        find("moe_network.w_l" + std::to_string(l + 1), experts * dims[l] * dims[l + 1]);
    b.expert_biases[l] = find("moe_network.b_l" + std::to_string(l + 1), experts * dims[l + 1]);
  }
  return b;
}

AutoencoderBuffers autoencoder_buffers(TrainableNetwork& network, bool gradients) {
  const TensorMemory find(network, gradients, "the FMD autoencoder");
  AutoencoderBuffers b;
  const char* layers[4] = {"conv_encode1", "conv_encode2", "conv_decode2", "conv_decode1"};
  for (int i = 0; i < 4; ++i) {
    const AutoencoderStep::LayerShape l = AutoencoderStep::layer_shape(i);
    b.weight[i] = find(std::string(layers[i]) + ".weight",
                       std::int64_t{l.in_channels} * l.out_channels * l.kernel);
    b.bias[i] = find(std::string(layers[i]) + ".bias", l.out_channels);
  }
  return b;
}

std::shared_ptr<TrainableNetwork> make_network(Network network) {
  switch (network) {
    case Network::kMpnetMoe:
      return std::make_shared<MpnetMoe>();
    case Network::kMpnetMlp:
      return std::make_shared<MpnetMlp>();
    case Network::kMpnetTransformer:
      return std::make_shared<MpnetTransformer>();
    case Network::kUgnetMoe:
      return std::make_shared<UgnetMoe>();
    case Network::kUgnetMlp:
      return std::make_shared<UgnetMlp>();
    case Network::kUgnetTransformer:
      return std::make_shared<UgnetTransformer>();
    case Network::kUgnetDiffusion:
      return std::make_shared<UgnetDiffusion>();
    case Network::kMotionAutoencoder:
      return std::make_shared<MotionAutoencoder>();
  }
  throw Error("unknown network");
}

torch::Tensor mpnet_preclamp(TrainableNetwork& mpnet, const torch::Tensor& window) {
  auto* m = dynamic_cast<MpnetNetwork*>(&mpnet);
  if (m == nullptr) {
    throw Error("mpnet_preclamp: not an MPNet");
  }
  return m->preclamp(window);
}

torch::Tensor diffusion_sample(TrainableNetwork& diffusion, const torch::Tensor& window,
                               const torch::Tensor& noise) {
  auto* d = dynamic_cast<UgnetDiffusion*>(&diffusion);
  if (d == nullptr) {
    throw Error("diffusion_sample: not the diffusion UGNet");
  }
  return d->sample(window, noise);
}

torch::Tensor motion_codes(TrainableNetwork& autoencoder, const torch::Tensor& segments) {
  auto* a = dynamic_cast<MotionAutoencoder*>(&autoencoder);
  if (a == nullptr) {
    throw Error("motion_codes: not the motion autoencoder");
  }
  return a->encode(segments).squeeze(1);
}

void load_weights(TrainableNetwork& model, const SafetensorsFile& file) {
  torch::NoGradGuard no_grad;
  std::map<std::string, torch::Tensor> wanted;
  for (const auto& item : model.named_parameters()) {
    wanted.emplace(item.key(), item.value());
  }
  for (const auto& item : model.named_buffers()) {
    wanted.emplace(item.key(), item.value());
  }
  for (const TensorInfo& info : file.tensors()) {
    if (!wanted.contains(info.name)) {
      throw Error(file.source() + ": tensor '" + info.name + "' is not a tensor of this network");
    }
  }
  for (auto& [name, tensor] : wanted) {
    const std::vector<std::int64_t> shape(tensor.sizes().begin(), tensor.sizes().end());
    if (!file.contains(name)) {
      throw Error(file.source() + ": tensor '" + name + "' missing (expected shape " +
                  shape_of(tensor) + ")");
    }
    const std::vector<float> values = file.read_f32(name, shape);
    tensor.copy_(
        torch::from_blob(const_cast<float*>(values.data()), tensor.sizes(), torch::kFloat32));
  }
}

SafetensorsWriter export_weights(TrainableNetwork& model) {
  SafetensorsWriter writer;
  auto add = [&](const std::string& name, const torch::Tensor& t) {
    const torch::Tensor c = t.detach().to(torch::kFloat32).contiguous();
    writer.add_f32(
        name, std::vector<std::int64_t>(c.sizes().begin(), c.sizes().end()),
        std::span<const float>(c.data_ptr<float>(), static_cast<std::size_t>(c.numel())));
  };
  for (const auto& item : model.named_parameters()) {
    add(item.key(), item.value());
  }
  for (const auto& item : model.named_buffers()) {
    add(item.key(), item.value());
  }
  return writer;
}

SafetensorsWriter initial_weights(Network network, std::uint64_t seed) {
  torch::manual_seed(seed);
  const std::shared_ptr<TrainableNetwork> model = make_network(network);
  return export_weights(*model);
}

ForwardOutputs libtorch_forward(Network network, const SafetensorsFile& weights,
                                std::span<const float> inputs, std::int64_t count,
                                std::span<const float> noise) {
  torch::NoGradGuard no_grad;
  const std::shared_ptr<TrainableNetwork> model = make_network(network);
  load_weights(*model, weights);
  model->eval();
  const std::int64_t columns = static_cast<std::int64_t>(inputs.size()) / (count * kWindow);
  const torch::Tensor x =
      torch::from_blob(const_cast<float*>(inputs.data()), {count, kWindow, columns}).clone();
  ForwardOutputs out;
  auto to_vector = [](const torch::Tensor& t) {
    const torch::Tensor c = t.contiguous();
    return std::vector<float>(c.data_ptr<float>(), c.data_ptr<float>() + c.numel());
  };
  switch (family_of(network)) {
    case Family::kMpnet:
      out.preclamp = to_vector(mpnet_preclamp(*model, x));
      out.output = to_vector(model->forward(x));
      break;
    case Family::kUgnet:
      if (network == Network::kUgnetDiffusion) {
        const torch::Tensor draws =
            noise.empty()
                ? torch::zeros({count, kWindow, kPose})
                : torch::from_blob(const_cast<float*>(noise.data()), {count, kWindow, kPose})
                      .clone();
        out.output = to_vector(diffusion_sample(*model, x, draws));
      } else {
        out.output = to_vector(model->forward(x));
      }
      break;
    case Family::kMotionAutoencoder:
      out.output = to_vector(motion_codes(*model, x));
      break;
  }
  return out;
}

}  // namespace deixis::train
