#include "gesture/nn/amnet.h"

#include "core/error.h"
#include "gesture/nn/expert_layer.h"
#include "gesture/nn/gru.h"

namespace deixis::nn {

namespace {

constexpr int kRows = kAmnetWindowRows;
constexpr int kAngles = 12;
constexpr int kTarget = 3;
constexpr int kScaleColumn = kAngles + kTarget;
constexpr int kExperts = 6;
constexpr int kHidden = 16;

using Window = Eigen::Matrix<float, kRows, kAmnetColumns, Eigen::RowMajor>;
using Omegas = Eigen::Matrix<float, kRows, kExperts, Eigen::RowMajor>;

// BatchNorm1d in eval mode: running statistics, eps 1e-5.
struct BatchNorm {
  VectorParam<kHidden> weight, bias, running_mean, running_var;
  void load(const SafetensorsFile& file, const std::string& prefix) {
    load_vector(file, prefix + ".weight", weight);
    load_vector(file, prefix + ".bias", bias);
    load_vector(file, prefix + ".running_mean", running_mean);
    load_vector(file, prefix + ".running_var", running_var);
  }
  void apply(Eigen::Matrix<float, kHidden, 1>& x) const {
    x = ((x - running_mean.view()).array() / (running_var.view().array() + 1e-5f).sqrt() *
             weight.view().array() +
         bias.view().array())
            .matrix();
  }
};

// ExpertMLP of ISMAR2023/model.py: layer 1, BatchNorm, ELU, layer 2.
template <int In, int Out>
struct ExpertMlp {
  ExpertLayer<kExperts, In, kHidden> l1;
  BatchNorm bn;
  ExpertLayer<kExperts, kHidden, Out> l2;
  void load(const SafetensorsFile& file, const std::string& prefix) {
    l1.load(file, prefix + ".w_l1", prefix + ".b_l1");
    bn.load(file, prefix + ".bn");
    l2.load(file, prefix + ".w_l2", prefix + ".b_l2");
  }
  template <typename Input, typename Omega>
  Eigen::Matrix<float, Out, 1> run(const Input& x, const Omega& omega) const {
    Eigen::Matrix<float, kHidden, 1> h = l1.run(x, omega);
    bn.apply(h);
    elu_inplace(h);
    return l2.run(h, omega);
  }
};

}  // namespace

struct Amnet::Network {
  GruLayer<kTarget, kExperts> gating_l0;
  GruLayer<kExperts, kExperts> gating_l1;
  ExpertMlp<kAngles, kHidden> angle_encoder;
  ExpertMlp<kHidden + 1, kAmnetOutputSize> motion_decoder;
  GruLayer<kHidden, kHidden> gru_l0;
  GruLayer<kHidden, kHidden> gru_l1;

  // Softmax of the 2-layer gating GRU's output at every row.
  Omegas gate(const Window& x) const {
    Eigen::Matrix<float, kRows, kExperts, Eigen::RowMajor> hidden;
    gating_l0.run<kRows>(x.middleCols<kTarget>(kAngles), hidden);
    Omegas omega;
    gating_l1.run<kRows>(hidden, omega);
    for (int r = 0; r < kRows; ++r) {
      auto row = omega.row(r);
      softmax_inplace(row);
    }
    return omega;
  }
};

Amnet Amnet::load(const SafetensorsFile& file) {
  if (!file.contains("angle_encoder.w_l1") || !file.contains("motion_decoder.w_l1")) {
    throw Error(file.source() +
                ": not an AMNet (ISMAR 2023) checkpoint: expected 'angle_encoder.*' and "
                "'motion_decoder.*' tensors");
  }
  auto net = std::make_shared<Network>();
  net->gating_l0.load(file, "gating_network.gru", 0);
  net->gating_l1.load(file, "gating_network.gru", 1);
  net->angle_encoder.load(file, "angle_encoder");
  net->motion_decoder.load(file, "motion_decoder");
  net->gru_l0.load(file, "gru", 0);
  net->gru_l1.load(file, "gru", 1);
  return Amnet(std::move(net));
}

Amnet Amnet::load(const std::filesystem::path& path) {
  return load(SafetensorsFile::read(path));
}

std::array<float, kAmnetOutputSize> Amnet::run(
    std::span<const float, kAmnetWindowSize> local,
    std::span<const float, kAmnetWindowSize> remote) const noexcept {
  const Network& net = *network_;
  const Eigen::Map<const Window> l(local.data());
  const Eigen::Map<const Window> r(remote.data());
  const Omegas omega_local = net.gate(l);
  const Omegas omega_remote = net.gate(r);

  Eigen::Matrix<float, kRows, kHidden, Eigen::RowMajor> encoded;
  for (int row = 0; row < kRows; ++row) {
    encoded.row(row) = (net.angle_encoder.run(l.row(row).head<kAngles>().transpose(),
                                              omega_local.row(row).transpose()) +
                        net.angle_encoder.run(r.row(row).head<kAngles>().transpose(),
                                              omega_remote.row(row).transpose()))
                           .transpose();
  }
  Eigen::Matrix<float, kRows, kHidden, Eigen::RowMajor> hidden;
  net.gru_l0.run<kRows>(encoded, hidden);
  Eigen::Matrix<float, kRows, kHidden, Eigen::RowMajor> out;
  net.gru_l1.run<kRows>(hidden, out);

  Eigen::Matrix<float, kHidden + 1, 1> decoder_input;
  decoder_input.head<kHidden>() = out.row(kRows - 1).transpose();
  decoder_input(kHidden) = r(kRows - 1, kScaleColumn);
  std::array<float, kAmnetOutputSize> y;
  Eigen::Map<Eigen::Matrix<float, kAmnetOutputSize, 1>>(y.data()) =
      net.motion_decoder.run(decoder_input, omega_remote.row(kRows - 1).transpose());
  return y;
}

}  // namespace deixis::nn
